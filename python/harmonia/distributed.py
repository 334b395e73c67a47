"""Batches larger than one machine: ``harmonia batch`` on a Dask cluster.

``python3 -m harmonia.distributed INPUTS... --out DIR [--scheduler ADDRESS] [--atlas | --method M]
[options of batch] [--resume] [--retries N] [--json]`` runs what ``harmonia batch`` runs, with Dask
(``python3-distributed``) as the scheduler: without ``--scheduler`` on a LocalCluster of one
single-threaded worker process per core, with it on that cluster (``dask scheduler`` on one
machine, ``dask worker ADDRESS --nthreads 1`` on each of the others; dask-jobqueue and
dask-kubernetes start the same on SLURM and Kubernetes). Inputs and OUT must be on storage that
every worker sees (a shared file system).

The batch is written once, in the ``harmonia`` program, and this module only schedules it:

- ``harmonia batch INPUTS --out DIR ... --plan`` names every input's output (the same names, the
  same ``--resume`` decisions) and is read line by line, so that millions of inputs are
  submitted in waves as results come back (``as_completed``), never as one graph;
- each task runs ``harmonia batch --out DIR ... --task INPUT OUTPUT`` in a process of its own on a
  worker, which runs the input in a child process exactly as ``harmonia batch`` does (the same
  command, so the outputs are byte-identical) and prints its log line. A file that crashes or
  exhausts memory ends only that child, and the task reports it as the batch does. While it runs
  the worker only waits on a process, holding no interpreter lock, so its heartbeats go on;
- a worker lost in the middle of a file (killed, out of memory) makes its file run again on
  another worker, up to ``--retries`` times; its log line counts the retries. Outputs are
  written atomically, so none is ever seen half-written, and the task's process stops its child
  when the worker that asked for it is gone;
- the client holds only the log lines: it appends each to ``OUT/batch-log.jsonl`` as it arrives
  and asks ``harmonia batch --summary-of`` for the summary and the exit code at the end.

With ``--backend vulkan`` every task asks for the Dask resource ``GPU`` (workers started with
``--resources GPU=1`` have one; on a LocalCluster every worker gets it when this machine has a
hardware Vulkan device), so CPU-only workers never receive device work.
"""

import argparse
import contextlib
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import uuid

LOG_NAME = "batch-log.jsonl"

#: Exit codes of ``harmonia batch`` (docs/cli.md): every input succeeded or was skipped; some
#: failed; a bad command line; OUT or its log cannot be written. 130: stopped by Ctrl-C.
EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_ENVIRONMENT, EXIT_INTERRUPTED = 0, 2, 1, 5, 130


def find_program(program=None):
    """The ``harmonia`` program: ``program``, else $HARMONIA_PROGRAM, else the one beside this
    package (a build tree's, or an installation's ``<prefix>/bin``), else the one on PATH."""
    if program:
        return str(program)
    if os.environ.get("HARMONIA_PROGRAM"):
        return os.environ["HARMONIA_PROGRAM"]
    here = pathlib.Path(__file__).resolve().parent
    for ancestor in here.parents:
        for candidate in (ancestor / "bin" / "harmonia", ancestor / "harmonia"):
            if candidate.is_file() and os.access(candidate, os.X_OK):
                return str(candidate)
    found = shutil.which("harmonia")
    if found:
        return found
    raise FileNotFoundError("no harmonia program found: pass program= or set HARMONIA_PROGRAM")


def batch_options(out, method=None, cut=False, resolution=None, padding=None, max_distortion=None,
                  texels_per_unit=None, max_pages=None, cleanup=None, keep_splits=False,
                  join_charts=False, repack=False, backend=None):
    """The options of ``harmonia batch`` that the plan, every task and the summary share."""
    options = ["--out", str(out)]
    if method:
        options += ["--method", method]
    if cut:
        options.append("--cut")
    for flag, value in (("--resolution", resolution), ("--padding", padding),
                        ("--max-distortion", max_distortion), ("--texels-per-unit", texels_per_unit),
                        ("--max-pages", max_pages), ("--cleanup", cleanup), ("--backend", backend)):
        if value is not None:
            options += [flag, str(value)]
    for flag, value in (("--keep-splits", keep_splits), ("--join-charts", join_charts), ("--repack", repack)):
        if value:
            options.append(flag)
    return options


def run_task(program, options, input_path, output_path):
    """One input, run on a worker as ``harmonia batch`` runs it: its log line (a dict). Waits on
    the task's process without the interpreter lock."""
    # Dask's nanny sets MALLOC_TRIM_THRESHOLD_ for its worker's own memory: passed on, glibc would
    # hand memory back to the system at every free and the program would run 5-20 % slower.
    environment = {name: value for name, value in os.environ.items() if name != "MALLOC_TRIM_THRESHOLD_"}
    finished = subprocess.run([program, "batch", *options, "--task", input_path, output_path],
                              stdin=subprocess.DEVNULL, capture_output=True, text=True, env=environment)
    for line in reversed(finished.stdout.splitlines()):
        with contextlib.suppress(ValueError):
            record = json.loads(line)
            if isinstance(record, dict) and record.get("input") == input_path:
                return record
    reason = (finished.stderr.strip().splitlines() or ["no log line"])[-1]
    if reason.startswith("harmonia: "):
        reason = reason[len("harmonia: "):]
    exit_code = finished.returncode if finished.returncode >= 0 else -1
    signal_name = signal.Signals(-finished.returncode).name if finished.returncode < 0 else None
    return {"error": "its task ended without a log line (%s)" % reason, "exit_code": exit_code,
            "input": input_path, "output": output_path, "quality": None, "retries": 0,
            "seconds": 0.0, "signal": signal_name, "status": "failed"}


def log_text(record):
    """A record as ``harmonia batch`` writes a log line: one JSON object, keys sorted, no spaces."""
    return json.dumps(record, sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def _lost_worker(error):
    """Whether a task's error says that the worker running it was lost (not the file's fault)."""
    return type(error).__name__ in ("KilledWorker", "CommClosedError", "FutureCancelledError")


def _hardware_vulkan_device():
    """Whether this machine has a hardware Vulkan device (the LocalCluster's GPU resource)."""
    try:
        from . import _core
        context = _core.VulkanContext()
        return context.type not in ("cpu", "")
    except Exception:  # no loader, no device: a CPU machine
        return False


def local_cluster(workers=None):
    """The LocalCluster run_batch starts without a client: ``workers`` single-threaded worker
    processes (default: one per core), with the GPU resource where this machine has a hardware
    Vulkan device. Its scheduler leaves the retries to run_batch, which counts them for the log,
    and gives a worker only the task it runs (no second one waiting on it), so that a worker lost
    loses that file alone, not a bystander queued behind it."""
    import dask
    from dask.distributed import LocalCluster

    with dask.config.set({"distributed.scheduler.allowed-failures": 0,
                          "distributed.scheduler.worker-saturation": 1.0}):
        return LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                            dashboard_address=None,
                            resources={"GPU": 1} if _hardware_vulkan_device() else None)


def _plan(program, inputs, options, resume, resume_keep_defective):
    """Starts ``harmonia batch --plan``; its lines are read as the batch goes."""
    command = [program, "batch", *map(str, inputs), *options, "--plan"]
    if resume:
        command.append("--resume")
    if resume_keep_defective:
        command.append("--resume-keep-defective")
    return subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def run_batch(inputs, out, client=None, *, method=None, cut=False, resolution=None, padding=None,
              max_distortion=None, texels_per_unit=None, max_pages=None, cleanup=None,
              keep_splits=False, join_charts=False, repack=False, backend=None, resume=False,
              resume_keep_defective=False, retries=2, json_summary=False, program=None,
              workers=None, summary_stream=None):
    """Runs the batch on a Dask cluster and returns ``harmonia batch``'s exit code.

    ``client``: a ``dask.distributed.Client`` of your own cluster; without one a LocalCluster of
    ``workers`` single-threaded processes (default: one per core) is started and closed. The
    summary (``harmonia batch``'s table, or its JSON with ``json_summary``) goes to
    ``summary_stream`` (default: standard output).
    """
    from dask.distributed import Client, as_completed

    program = find_program(program)
    out = pathlib.Path(out)
    options = batch_options(out, method, cut, resolution, padding, max_distortion, texels_per_unit,
                            max_pages, cleanup, keep_splits, join_charts, repack, backend)
    summary_stream = summary_stream or sys.stdout
    started = time.monotonic()
    plan = _plan(program, inputs, options, resume, resume_keep_defective)
    first_line = plan.stdout.readline()  # the plan has read the old log (for --resume) by now
    if not first_line:
        error = plan.stderr.read()
        plan.wait()
        sys.stderr.write(error)
        return plan.returncode or EXIT_USAGE

    try:
        log = open(out / LOG_NAME, "a" if resume else "w", encoding="utf-8")
    except OSError:  # as harmonia batch says it, before any work
        plan.kill()
        plan.wait()
        sys.stderr.write("harmonia: %s: cannot be written\n" % (out / LOG_NAME))
        return EXIT_ENVIRONMENT
    cluster = None
    own_client = client is None
    if own_client:
        cluster = local_cluster(workers)
        client = Client(cluster)
    threads = max(1, sum(client.nthreads().values()))
    if backend == "vulkan" and not any(worker.get("resources", {}).get("GPU", 0) > 0
                                       for worker in client.scheduler_info()["workers"].values()):
        # A task that asks for a resource no worker has would wait for ever.
        sys.stderr.write("harmonia: --backend vulkan: no worker of the cluster has the GPU resource "
                         "(start them with `dask worker ADDRESS --nthreads 1 --resources GPU=1`)\n")
        plan.kill()
        plan.wait()
        log.close()
        if own_client:
            client.close()
            cluster.close()
        return EXIT_ENVIRONMENT
    in_flight_limit = 2 * threads  # a wave: enough to keep every worker busy, no more
    resources = {"GPU": 1} if backend == "vulkan" else None

    # This run's log lines, for the summary (the log may hold earlier runs' too); outside OUT, so
    # that a client that dies leaves nothing there but outputs and the log.
    run_records = tempfile.NamedTemporaryFile("w", prefix="harmonia-batch-run-", suffix=".jsonl",
                                              delete=False, encoding="utf-8")
    interrupted = False
    plan_failed = 0
    attempts = {}  # future in flight -> (input, output, retries so far)
    try:
        with log:
            def write(record):
                line = log_text(record) + "\n"
                log.write(line)
                log.flush()
                run_records.write(line)
                run_records.flush()

            def submit(input_path, output_path, retried):
                future = client.submit(run_task, program, options, input_path, output_path,
                                       pure=False, resources=resources,
                                       key="harmonia-task-" + uuid.uuid4().hex)
                attempts[future] = (input_path, output_path, retried)
                return future

            plan_lines = _chain_first(first_line, plan.stdout)
            running = as_completed()

            def fill():
                while running.count() < in_flight_limit:
                    line = next(plan_lines, None)
                    if line is None:
                        return
                    step = json.loads(line)
                    if step["run"]:
                        running.add(submit(step["input"], step["output"], 0))
                    else:
                        write(step["record"])

            fill()
            for future in running:
                input_path, output_path, retried = attempts.pop(future)
                if future.status == "error":
                    error = future.exception()
                    if _lost_worker(error) and retried < retries:
                        running.add(submit(input_path, output_path, retried + 1))
                        continue
                    record = {"error": "its worker was lost %d time(s) running it (%s: %s)" %
                                       (retried + 1, type(error).__name__, error) if _lost_worker(error)
                              else "its task failed (%s: %s)" % (type(error).__name__, error),
                              "exit_code": -1, "input": input_path, "output": output_path,
                              "quality": None, "retries": retried, "seconds": 0.0, "signal": None,
                              "status": "failed"}
                else:
                    record = future.result()
                    record["retries"] = retried
                future.release()
                write(record)
                fill()
        plan.wait()
        if plan.returncode != 0:
            sys.stderr.write(plan.stderr.read())
            plan_failed = plan.returncode
    except KeyboardInterrupt:
        interrupted = True
        if not own_client:  # a cluster of the caller's: its workers drop what was in flight
            client.cancel(list(attempts))
    finally:
        run_records.close()
        if plan.poll() is None:
            plan.kill()
        if own_client:
            client.close()
            cluster.close()
    if interrupted or plan_failed:
        os.unlink(run_records.name)
        return EXIT_INTERRUPTED if interrupted else plan_failed
    summary_command = [program, "batch", *options, "--summary-of", run_records.name,
                       "--elapsed", repr(time.monotonic() - started), "-j", str(threads)]
    if json_summary:
        summary_command.append("--json")
    summary = subprocess.run(summary_command, stdin=subprocess.DEVNULL, capture_output=True, text=True)
    os.unlink(run_records.name)
    summary_stream.write(summary.stdout)
    sys.stderr.write(summary.stderr)
    return summary.returncode


def _chain_first(first, rest):
    yield first
    yield from rest


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python3 -m harmonia.distributed",
        description="harmonia batch on a Dask cluster: the texture atlas (or a planar map) of many "
                    "meshes, each input a task; the same outputs, log, summary and exit codes")
    parser.add_argument("inputs", nargs="+", metavar="INPUTS", help="mesh files and folders")
    parser.add_argument("--out", required=True, help="output folder (on storage every worker sees)")
    parser.add_argument("--scheduler", help="address of a Dask scheduler (default: a LocalCluster)")
    parser.add_argument("-j", "--workers", type=int, help="LocalCluster workers (default: one per core)")
    parser.add_argument("--atlas", action="store_true", help="harmonia atlas on each input (default)")
    parser.add_argument("--method", help="harmonia unwrap --method M on each input instead")
    parser.add_argument("--cut", action="store_true", help="--method only: cut non-disks open")
    parser.add_argument("--resolution")
    parser.add_argument("--padding", type=int)
    parser.add_argument("--max-distortion", type=float)
    parser.add_argument("--texels-per-unit", type=float)
    parser.add_argument("--max-pages", type=int)
    parser.add_argument("--cleanup", choices=["none", "strict", "repair"])
    parser.add_argument("--keep-splits", action="store_true")
    parser.add_argument("--join-charts", action="store_true")
    parser.add_argument("--repack", action="store_true")
    parser.add_argument("--backend", choices=["auto", "cpu", "vulkan"],
                        help="vulkan: the tasks go to workers with the GPU resource only")
    parser.add_argument("--resume", action="store_true", help="skip inputs whose output exists")
    parser.add_argument("--resume-keep-defective", action="store_true")
    parser.add_argument("--retries", type=int, default=2,
                        help="times a file is run again after its worker was lost (default 2)")
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    parser.add_argument("--program", help="the harmonia program (default: found beside the package)")
    args = parser.parse_args(argv)
    if args.atlas and args.method:
        parser.error("--atlas and --method exclude each other")
    if args.retries < 0:
        parser.error("--retries must be 0 or more")
    client = None
    if args.scheduler:
        from dask.distributed import Client
        client = Client(args.scheduler)
    # SIGTERM ends the client as Ctrl-C does: the tasks are dropped, --resume runs them again.
    signal.signal(signal.SIGTERM, signal.default_int_handler)
    try:
        return run_batch(args.inputs, args.out, client, method=args.method, cut=args.cut,
                         resolution=args.resolution, padding=args.padding,
                         max_distortion=args.max_distortion, texels_per_unit=args.texels_per_unit,
                         max_pages=args.max_pages, cleanup=args.cleanup, keep_splits=args.keep_splits,
                         join_charts=args.join_charts, repack=args.repack, backend=args.backend,
                         resume=args.resume, resume_keep_defective=args.resume_keep_defective,
                         retries=args.retries, json_summary=args.json, program=args.program,
                         workers=args.workers)
    finally:
        if client is not None:
            client.close()


if __name__ == "__main__":
    # Run as a module, the task function must still be pickled as harmonia.distributed's (the
    # workers import that, not this __main__).
    from harmonia import distributed as _module
    sys.exit(_module.main())
