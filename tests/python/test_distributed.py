"""python -m harmonia.distributed (harmonia.distributed.run_batch) on LocalClusters, judged against
`harmonia batch` and against what the issue asks it to survive: the same outputs bit for bit, the
same log and exit code; a worker killed in the middle of a file (the file redone elsewhere, the
retry in the log); a file that kills every worker it runs on (failed, with the reason, the batch
not hung); the client killed and resumed (nothing done twice, nothing lost); a task longer than
the workers' time-to-live (the worker's heartbeat goes on); device work only where a worker has
the GPU resource.

Workers are killed through a stand-in for the program: a shell script that, for one input, kills
the process that started it (the worker) before handing over to the real program."""

import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time

import pytest

dask = pytest.importorskip("dask")
distributed = pytest.importorskip("dask.distributed")

from conftest import CLOSED_MESHES, corpus_path, harmonia_program  # noqa: E402
from harmonia.distributed import run_batch  # noqa: E402

PYTHON_PATH = os.environ.get("PYTHONPATH", "")


def log_lines(path):
    with open(path) as text:
        return [json.loads(line) for line in text if line.strip()]


def by_input(lines, drop=("seconds", "output")):
    return {line["input"]: {k: v for k, v in line.items() if k not in drop} for line in lines}


@pytest.fixture
def inputs(tmp_path):
    """The closed corpus and a file that holds no surface, in one folder."""
    folder = tmp_path / "in"
    folder.mkdir()
    for name in CLOSED_MESHES:
        shutil.copy(corpus_path("closed", name + ".obj"), folder)
    shutil.copy(corpus_path("wild", "obj_wireframe.obj"), folder)
    return folder


def stand_in(tmp_path, body):
    """A program that runs `body` (sh, with $input the task's input) for a task and then is the
    real program."""
    script = tmp_path / "harmonia-stand-in"
    script.write_text("#!/bin/sh\n"
                      "input=''\n"
                      "previous=''\n"
                      "for argument in \"$@\"; do\n"
                      "  if [ \"$previous\" = --task ]; then input=\"$argument\"; fi\n"
                      "  previous=\"$argument\"\n"
                      "done\n"
                      + body + "\n"
                      "exec '%s' \"$@\"\n" % harmonia_program())
    script.chmod(0o755)
    return str(script)


def run_on_local_cluster(inputs, out, cluster_options=None, **batch_options):
    """run_batch on a LocalCluster of the test's own (one single-threaded worker unless said)."""
    cluster = distributed.LocalCluster(**dict({"n_workers": 1, "threads_per_worker": 1, "processes": True,
                                               "dashboard_address": None}, **(cluster_options or {})))
    client = distributed.Client(cluster)
    try:
        return run_batch(inputs, out, client, **batch_options)
    finally:
        client.close()
        cluster.close()


def test_outputs_log_and_exit_code_are_harmonia_batchs(inputs, tmp_path, capsys):
    batch = subprocess.run([harmonia_program(), "batch", str(inputs), "--out", str(tmp_path / "batch"),
                            "-j", "2"], capture_output=True, text=True)
    code = run_batch([str(inputs)], tmp_path / "dask", workers=2, program=harmonia_program())
    assert code == batch.returncode == 2  # the wireframe failed, the rest ran
    for name in CLOSED_MESHES:
        ours, theirs = tmp_path / "dask" / (name + ".obj"), tmp_path / "batch" / (name + ".obj")
        assert ours.read_bytes() == theirs.read_bytes(), name
    assert not (tmp_path / "dask" / "obj_wireframe.obj").exists()
    ours, theirs = log_lines(tmp_path / "dask" / "batch-log.jsonl"), log_lines(tmp_path / "batch" / "batch-log.jsonl")
    assert by_input(ours) == by_input(theirs)
    assert sorted(ours[0]) == sorted(theirs[0])  # the same fields
    for line in ours:
        assert line["output"] == str(tmp_path / "dask" / (pathlib.Path(line["input"]).stem + ".obj"))
    summary = capsys.readouterr().out
    assert "failure" in summary and "obj_wireframe.obj" in summary
    # Nothing else was left in OUT (the run's records are removed).
    assert sorted(p.name for p in (tmp_path / "dask").iterdir()) == sorted(
        [name + ".obj" for name in CLOSED_MESHES] + ["batch-log.jsonl"])


def test_a_worker_killed_in_the_middle_of_a_file_has_it_redone_elsewhere(inputs, tmp_path):
    marker = tmp_path / "killed-once"
    program = stand_in(tmp_path, "case \"$input\" in *cow.obj) if [ ! -e '%s' ]; then touch '%s'; "
                                 "kill -9 $PPID; sleep 5; fi;; esac" % (marker, marker))
    out = tmp_path / "out"
    code = run_batch([str(inputs)], out, workers=2, program=program, retries=2)
    assert code == 2  # the wireframe, as before
    assert marker.exists()
    lines = by_input(log_lines(out / "batch-log.jsonl"), drop=())
    cow = next(line for name, line in lines.items() if name.endswith("cow.obj"))
    assert cow["status"] == "ok" and cow["retries"] == 1
    # A worker holds only the file it runs: no other file was lost with it.
    for name, line in lines.items():
        assert line["retries"] == (1 if name.endswith("cow.obj") else 0), line
        assert line["status"] == ("failed" if name.endswith("obj_wireframe.obj") else "ok"), line
    assert len(lines) == len(CLOSED_MESHES) + 1
    reference = tmp_path / "reference"
    subprocess.run([harmonia_program(), "batch", str(corpus_path("closed", "cow.obj")), "--out", str(reference)],
                   capture_output=True)
    assert (out / "cow.obj").read_bytes() == (reference / "cow.obj").read_bytes()


def test_a_file_that_kills_every_worker_ends_failed_with_the_reason(tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(corpus_path("closed", "spot.obj"), folder)
    shutil.copy(corpus_path("closed", "fandisk.obj"), folder / "killer.obj")
    program = stand_in(tmp_path, "case \"$input\" in *killer.obj) kill -9 $PPID; sleep 5;; esac")
    started = time.monotonic()
    code = run_batch([str(folder)], tmp_path / "out", workers=2, program=program, retries=1)
    assert code == 2
    lines = by_input(log_lines(tmp_path / "out" / "batch-log.jsonl"), drop=())
    killer = next(line for name, line in lines.items() if name.endswith("killer.obj"))
    assert killer["status"] == "failed" and killer["retries"] == 1
    assert "worker was lost 2 time(s)" in killer["error"]
    spot = next(line for name, line in lines.items() if name.endswith("spot.obj"))
    assert spot["status"] == "ok"
    assert not (tmp_path / "out" / "killer.obj").exists()
    assert time.monotonic() - started < 120


def test_a_client_killed_and_resumed_does_nothing_twice_and_loses_nothing(inputs, tmp_path):
    out = tmp_path / "out"
    environment = dict(os.environ, PYTHONPATH=PYTHON_PATH, HARMONIA_PROGRAM=harmonia_program())
    command = [sys.executable, "-m", "harmonia.distributed", str(inputs), "--out", str(out), "-j", "2"]
    client = subprocess.Popen(command, env=environment, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              start_new_session=True)
    log = out / "batch-log.jsonl"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not (log.exists() and len(log_lines(log)) >= 2):
        time.sleep(0.05)
    # The client and its LocalCluster's processes, all at once, as a crash would end them.
    os.killpg(client.pid, signal.SIGKILL)
    client.wait()
    first_run = log_lines(log)
    assert 2 <= len(first_run) < len(CLOSED_MESHES) + 1, "the client finished before it could be killed"
    resumed = subprocess.run(command + ["--resume", "--json"], env=environment, capture_output=True, text=True)
    assert resumed.returncode == 2, resumed.stderr
    summary = json.loads(resumed.stdout)
    lines = log_lines(log)
    second_run = lines[len(first_run):]
    done_first = {line["input"] for line in first_run if line["status"] == "ok"}
    ran_second = {line["input"] for line in second_run if line["status"] != "skipped"}
    assert not done_first & ran_second  # nothing done twice
    assert {line["input"] for line in second_run} == {str(p) for p in inputs.iterdir()}  # nothing lost
    assert summary["inputs"] == len(CLOSED_MESHES) + 1 and summary["failed"] == 1
    for name in CLOSED_MESHES:
        assert (out / (name + ".obj")).stat().st_size > 0


def test_a_task_longer_than_the_workers_time_to_live_finishes(tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(corpus_path("closed", "spot.obj"), folder)
    program = stand_in(tmp_path, "sleep 6")
    with dask.config.set({"distributed.scheduler.worker-ttl": "2s",
                          "distributed.scheduler.allowed-failures": 0}):
        code = run_on_local_cluster([str(folder)], tmp_path / "out", program=program, retries=0)
    assert code == 0
    (line,) = log_lines(tmp_path / "out" / "batch-log.jsonl")
    assert line["status"] == "ok" and line["retries"] == 0 and line["seconds"] > 0


def test_device_work_goes_only_to_workers_with_the_gpu_resource(tmp_path, capsys):
    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(corpus_path("closed", "spot.obj"), folder)
    # CPU workers only: refused at once, nothing run (a task would wait for ever).
    code = run_on_local_cluster([str(folder)], tmp_path / "cpu", program=harmonia_program(), backend="vulkan")
    assert code == 5
    assert "GPU resource" in capsys.readouterr().err
    assert not (tmp_path / "cpu" / "spot.obj").exists()
    # A worker that has it gets the task (on lavapipe here, the Vulkan device of the tests).
    code = run_on_local_cluster([str(folder)], tmp_path / "gpu",
                                {"resources": {"GPU": 1}, "env": {"HARMONIA_VULKAN_DEVICE": "llvmpipe"}},
                                program=harmonia_program(), backend="vulkan")
    (line,) = log_lines(tmp_path / "gpu" / "batch-log.jsonl")
    assert code == 0, line
    assert line["status"] == "ok"


def test_a_log_that_cannot_be_written_stops_it_before_any_work_as_harmonia_batch(tmp_path, capsys):
    out = tmp_path / "out"
    (out / "batch-log.jsonl").mkdir(parents=True)  # a folder where the log would go
    mesh = str(corpus_path("closed", "spot.obj"))
    batch = subprocess.run([harmonia_program(), "batch", mesh, "--out", str(out)], capture_output=True, text=True)
    code = run_batch([mesh], out, workers=1, program=harmonia_program())
    assert code == batch.returncode == 5
    assert "batch-log.jsonl: cannot be written" in capsys.readouterr().err
    assert not (out / "spot.obj").exists()
