#!/usr/bin/env python3
"""The Python package's cost over the library call it wraps, and harmonia.parametrize beside
xatlas (the closing note's tables; docs/python.md quotes them).

Usage (from the source tree, after the build):
  PYTHONPATH=build/python /usr/bin/python3 bench/python_parametrize.py [--build build]
      [--repeat 3] [--skip-xatlas] [--out-md FILE]

1. Wrapping cost: cow x16 (88K faces) and x64 (353K), made by ../shared/tools/subdivide.py. For
   each: `harmonia atlas IN OUT --json` (the program's own figure: its report's seconds, the
   library call's phases) and harmonia.atlas(V, F) from Python: its wall time against the same
   call's report seconds, so the difference is what the package adds (array conversion, the
   worker thread, the results' arrays). Medians of --repeat runs, under the program's BLAS policy.
2. Per-call cost on a 100-face mesh: the median over 200 calls of wall time minus the library's
   own seconds. Editing: harmonia.SurfaceEditor frames on the public case homer-b and on cow x16
   (handles and fixed vertices by height), wall time against the library's frame time.
   Cancellation: at cow x64, a threading.Event set at ten moments through the
   atlas, and the time from each set to the call's return (CancelledError).
3. harmonia.parametrize beside xatlas on every closed corpus mesh x16: wall times (xatlas through
   ../shared/tools/xatlas built as bench/xatlas_run, its generate time: ComputeCharts and
   PackCharts), chart counts of both, harmonia's coverage of its 1024 x 1024 square beside
   xatlas's utilization (its own figure, of the larger W x H atlas it packs into: not the same
   measure; corpus_atlas_benchmark scores both atlases with one code), harmonia's L2 stretch.
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

import harmonia

SOURCE = pathlib.Path(__file__).resolve().parents[1]
SHARED = SOURCE.parent / "shared"
CLOSED = ["bunny", "cheburashka", "cow", "decimated-max", "elephant", "fandisk", "homer", "spot"]


def subdivided(name, times, folder):
    out = folder / ("%s-x%d.obj" % (name, 4 ** times))
    if not out.exists():
        subprocess.run([sys.executable, str(SHARED / "tools" / "subdivide.py"),
                        str(SHARED / "data" / "closed" / (name + ".obj")), str(out), "--times", str(times)],
                       check=True, capture_output=True)
    return out


def wrapping_cost(build, folder, repeat):
    rows = []
    for times in (2, 3):
        mesh = subdivided("cow", times, folder)
        positions, faces = harmonia.read_mesh(mesh)
        program = []
        for _ in range(repeat):
            run = subprocess.run([str(build / "harmonia"), "atlas", str(mesh), str(folder / "out.obj"), "--json"],
                                 capture_output=True, text=True, check=True)
            program.append(json.loads(run.stdout)["seconds"])
        wall, library = [], []
        for _ in range(repeat):
            started = time.perf_counter()
            atlas = harmonia.atlas(positions, faces)
            wall.append(time.perf_counter() - started)
            library.append(atlas.report["seconds"])
        rows.append((len(faces), statistics.median(program), statistics.median(library), statistics.median(wall)))
    return rows


def per_call_cost():
    # A 10 x 5 grid of squares, each two triangles: 100 faces.
    xs, ys = np.meshgrid(np.arange(11.0), np.arange(6.0))
    positions = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    index = np.arange(66).reshape(6, 11)
    a, b, c, d = index[:-1, :-1].ravel(), index[:-1, 1:].ravel(), index[1:, 1:].ravel(), index[1:, :-1].ravel()
    faces = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    extra, totals = [], []
    for _ in range(200):
        started = time.perf_counter()
        atlas = harmonia.atlas(positions, faces)
        wall = time.perf_counter() - started
        extra.append(wall - atlas.report["seconds"])
        totals.append(wall)
    return len(faces), statistics.median(totals), statistics.median(extra)


def cancellation_latency(folder):
    positions, faces = harmonia.read_mesh(subdivided("cow", 3, folder))
    started = time.perf_counter()
    harmonia.atlas(positions, faces)
    whole = time.perf_counter() - started
    latencies = []
    for share in [k / 10 for k in range(10)]:
        event = threading.Event()
        set_at = []

        def set_later():
            time.sleep(share * whole)
            set_at.append(time.perf_counter())
            event.set()

        setter = threading.Thread(target=set_later)
        setter.start()
        try:
            harmonia.atlas(positions, faces, cancel=event)
        except harmonia.CancelledError:
            latencies.append(time.perf_counter() - set_at[0])
        setter.join()
    return len(faces), whole, latencies


def editor_frames(folder):
    """(case, faces, median library frame s, median Python wall s) for two editors."""
    import json as json_module
    rows = []
    case = json_module.loads((SHARED / "data" / "edit" / "homer-b.json").read_text())
    positions, faces = harmonia.read_mesh(SHARED / "data" / "closed" / "homer.obj")
    fixed, handle = case["fixed"]["vertices"], case["handles"][0]["vertices"]
    cow, cow_faces = harmonia.read_mesh(subdivided("cow", 2, folder))
    height = cow[:, 1]
    low, high = np.quantile(height, [0.1, 0.9])
    meshes = [("homer-b", positions, faces, fixed, handle),
              ("cow x16", cow, cow_faces, np.flatnonzero(height < low), np.flatnonzero(height > high))]
    for name, V, F, fixed_vertices, handle_vertices in meshes:
        editor = harmonia.SurfaceEditor(V, F, fixed_vertices, [handle_vertices])
        library, wall = [], []
        for k in range(30):
            angle = 0.01 * k
            rotation = [[np.cos(angle / 2), 0.0, np.sin(angle / 2), 0.0]]
            center = [V[handle_vertices].mean(axis=0)]
            started = time.perf_counter()
            editor.deform(rotations=rotation, centers=center, translations=[[0.0, 0.001 * k, 0.0]])
            wall.append(time.perf_counter() - started)
            library.append(editor.last_report["frame_seconds"])
        rows.append((name, len(F), statistics.median(library), statistics.median(wall)))
    return rows


def beside_xatlas(build, folder):
    rows = []
    xatlas = build / "bench" / "xatlas_run"
    for name in CLOSED:
        mesh = subdivided(name, 2, folder)
        positions, faces = harmonia.read_mesh(mesh)
        started = time.perf_counter()
        atlas = harmonia.atlas(positions, faces)
        vmapping, indices, uvs = atlas.xatlas_form()
        ours = time.perf_counter() - started
        row = dict(mesh=name, faces=len(faces), ours=ours, charts=atlas.charts_count, coverage=atlas.coverage,
                   l2=atlas.l2_stretch, vertices=len(vmapping))
        if xatlas.exists():
            run = subprocess.run([str(xatlas), str(mesh), "--out", str(folder / "xatlas.obj"), "--target-res", "1024",
                                  "--padding", "2"], capture_output=True, text=True, check=True)
            report = json.loads(run.stdout.splitlines()[0])
            row.update(xatlas=report["t_generate"], xatlas_charts=report["charts"],
                       xatlas_coverage=report["utilization"][0], xatlas_vertices=report["out_vertices"])
        rows.append(row)
        print(row, flush=True)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=str(SOURCE / "build"))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--skip-xatlas", action="store_true")
    parser.add_argument("--out-md")
    arguments = parser.parse_args()
    build = pathlib.Path(arguments.build)
    harmonia.set_blas_thread_policy("hold_during_split_factorizations")  # the program's
    lines = []
    with tempfile.TemporaryDirectory() as temporary:
        folder = pathlib.Path(temporary)
        lines += ["| mesh | faces | program (report s) | Python call: library s | Python call: wall s | wall / library |",
                  "|---|---:|---:|---:|---:|---:|"]
        for faces, program, library, wall in wrapping_cost(build, folder, arguments.repeat):
            lines.append("| cow x%d | %d | %.3f | %.3f | %.3f | %.3f |"
                         % (16 if faces < 200000 else 64, faces, program, library, wall, wall / library))
        faces, total, extra = per_call_cost()
        lines += ["", "Per call on a %d-face mesh: %.3f ms in all, %.3f ms of it outside the library call "
                  "(median of 200)." % (faces, total * 1e3, extra * 1e3)]
        lines += ["", "| editor | faces | library frame ms | Python frame ms (wall) |", "|---|---:|---:|---:|"]
        for name, faces, library, wall in editor_frames(folder):
            lines.append("| %s | %d | %.2f | %.2f |" % (name, faces, library * 1e3, wall * 1e3))
        faces, whole, latencies = cancellation_latency(folder)
        lines += ["", "Cancellation at cow x64 (%d faces, the atlas %.2f s): %d cancels through it, returned "
                  "%.3f s after the event at worst, %.3f s median." % (faces, whole, len(latencies), max(latencies),
                                                                       statistics.median(latencies))]
        if not arguments.skip_xatlas:
            lines += ["", "| mesh x16 | faces | harmonia.parametrize s | xatlas s | speed-up | charts (h / x) | "
                      "coverage h / xatlas utilization | harmonia L2 | output vertices (h / x) |",
                      "|---|---:|---:|---:|---:|---|---|---:|---|"]
            for row in beside_xatlas(build, folder):
                if "xatlas" in row:
                    lines.append("| %s | %d | %.2f | %.2f | %.1fx | %d / %d | %.3f / %.3f | %.4f | %d / %d |" % (
                        row["mesh"], row["faces"], row["ours"], row["xatlas"], row["xatlas"] / row["ours"],
                        row["charts"], row["xatlas_charts"], row["coverage"], row["xatlas_coverage"], row["l2"],
                        row["vertices"], row["xatlas_vertices"]))
                else:
                    lines.append("| %s | %d | %.2f | (xatlas_run not built) | | %d | %.3f | %.4f | %d |" % (
                        row["mesh"], row["faces"], row["ours"], row["charts"], row["coverage"], row["l2"],
                        row["vertices"]))
    text = "\n".join(lines) + "\n"
    print(text)
    if arguments.out_md:
        pathlib.Path(arguments.out_md).write_text(text)


if __name__ == "__main__":
    main()
