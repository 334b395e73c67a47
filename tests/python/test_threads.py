"""The interpreter lock is released while the library computes, and several Python threads may
call it at once."""

import threading
import time

import numpy as np
import pytest

import harmonia
from conftest import corpus_path, read_obj, subdivide


@pytest.fixture(scope="module")
def large_mesh():
    """cow x16 (88K faces): an atlas of about two seconds on two cores."""
    positions, faces, _ = read_obj(corpus_path("closed", "cow.obj"))
    return subdivide(positions, faces, 2)


def count_while(run):
    """How far a Python thread counts in a loop while `run()` runs, and for how long it ran."""
    counted = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            counted[0] += 1

    counter = threading.Thread(target=count)
    counter.start()
    started = time.perf_counter()
    try:
        run()
    finally:
        seconds = time.perf_counter() - started
        stop.set()
        counter.join()
    return counted[0], seconds


def test_a_python_thread_keeps_running_during_an_atlas(large_mesh):
    positions, faces = large_mesh
    free_count, free_seconds = count_while(lambda: time.sleep(0.5))
    free_rate = free_count / free_seconds
    busy_count, busy_seconds = count_while(lambda: harmonia.atlas(positions, faces, threads=1))
    busy_rate = busy_count / busy_seconds
    # With the lock held through the call the counter would stop for all of it (rate near 0);
    # released, it shares the machine's cores with the atlas' one thread.
    assert busy_seconds > 0.5
    assert busy_rate > 0.25 * free_rate, (busy_rate, free_rate)


def test_two_threads_give_the_serial_results(spot):
    positions, faces = spot
    cow_positions, cow_faces, _ = read_obj(corpus_path("closed", "cow.obj"))
    serial = [harmonia.atlas(positions, faces).corner_uv, harmonia.atlas(cow_positions, cow_faces).corner_uv]
    parallel = [None, None]

    def run(slot, mesh):
        parallel[slot] = harmonia.atlas(*mesh).corner_uv

    threads = [threading.Thread(target=run, args=(0, (positions, faces))),
               threading.Thread(target=run, args=(1, (cow_positions, cow_faces)))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert np.array_equal(parallel[0], serial[0]) and np.array_equal(parallel[1], serial[1])
