#!/usr/bin/env python3
"""python -m harmonia.distributed against `harmonia batch` on this machine (docs/python.md, "Batches
on a cluster"): throughput over the closed corpus times 20 (160 files) with 2 workers against
`harmonia batch -j2`, the per-task overhead over 1,000 tiny meshes, and Dask's own cost per task
(1,000 empty tasks), the figures the scaling model in the docs is made of.

usage: PYTHONPATH=build/python /usr/bin/python3 bench/distributed_benchmark.py --program build/harmonia
       [--shared ../shared/data] [--copies 20] [--tiny 1000] [--workers 2] [--json FILE]
"""

import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

CLOSED = ["bunny", "cheburashka", "cow", "decimated-max", "elephant", "fandisk", "homer", "spot"]
# A tetrahedron: the smallest closed mesh, so that a task is nearly all overhead.
TINY_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def timed(function):
    started = time.monotonic()
    result = function()
    return result, time.monotonic() - started


def run_batch_program(program, folder, out, workers):
    return subprocess.run([program, "batch", str(folder), "--out", str(out), "-j", str(workers)],
                          capture_output=True, text=True).returncode


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--program", required=True)
    parser.add_argument("--shared", default=str(pathlib.Path(__file__).resolve().parents[2] / "shared" / "data"))
    parser.add_argument("--copies", type=int, default=20)
    parser.add_argument("--tiny", type=int, default=1000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json")
    args = parser.parse_args()
    from dask.distributed import Client

    from harmonia.distributed import local_cluster, run_batch

    program = os.path.abspath(args.program)
    figures = {"workers": args.workers}
    with tempfile.TemporaryDirectory() as scratch:
        scratch = pathlib.Path(scratch)
        corpus = scratch / "corpus"
        for copy in range(args.copies):
            (corpus / str(copy)).mkdir(parents=True)
            for name in CLOSED:
                shutil.copy(pathlib.Path(args.shared) / "closed" / (name + ".obj"), corpus / str(copy))
        tiny = scratch / "tiny"
        tiny.mkdir()
        for index in range(args.tiny):
            (tiny / ("t%04d.obj" % index)).write_text(TINY_OBJ)

        with local_cluster(args.workers) as cluster, Client(cluster) as client:  # run_batch's own
            # Dask's own cost per task: empty tasks through the same scheduler.
            client.gather(client.map(lambda i: i, range(50), pure=False))
            _, seconds = timed(lambda: client.gather(client.map(lambda i: i, range(args.tiny), pure=False)))
            figures["dask_seconds_per_empty_task"] = seconds / args.tiny
            with open(os.devnull, "w") as quiet:
                for label, folder, count in (("corpus", corpus, args.copies * len(CLOSED)),
                                             ("tiny", tiny, args.tiny)):
                    code, batch_seconds = timed(lambda: run_batch_program(program, folder, scratch / ("b-" + label),
                                                                          args.workers))
                    assert code == 0, (label, code)
                    code, dask_seconds = timed(lambda: run_batch([str(folder)], scratch / ("d-" + label), client,
                                                                 program=program, summary_stream=quiet))
                    assert code == 0, (label, code)
                    figures[label] = {
                        "files": count,
                        "batch_seconds": batch_seconds,
                        "distributed_seconds": dask_seconds,
                        "batch_files_per_second": count / batch_seconds,
                        "distributed_files_per_second": count / dask_seconds,
                        "throughput_ratio": batch_seconds / dask_seconds,
                        "overhead_seconds_per_task": (dask_seconds - batch_seconds) * args.workers / count,
                    }
                    print(label, json.dumps(figures[label]), flush=True)
    print(json.dumps(figures, indent=2))
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(figures, indent=2) + "\n")
    ratio = figures["corpus"]["throughput_ratio"]
    print("throughput of the distributed batch / harmonia batch -j%d: %.3f (target >= 0.9): %s" %
          (args.workers, ratio, "met" if ratio >= 0.9 else "missed"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
