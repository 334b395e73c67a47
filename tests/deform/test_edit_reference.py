#!/usr/bin/python3
"""bench/corpus_edit_reference, which makes the references of this project's edit cases
(tests/assets/edit), against libigl's references of a public case (../shared/data/edit, homer-c):

* harmonic: the same linear system solved by two programs: equal to 1e-9 of the diagonal (the
  cotangent Laplacian's conditioning, about 1e6 on these meshes, times double rounding, with room);
* arap10: the same ten iterations from the same cold start; libigl fits its rotations in single
  precision (igl::arap_solve calls fit_rotations with single_precision = true), so they agree to a
  few hundred float roundings (1.2e-7 each): 1e-5 of the diagonal;
* the converged result: within 1e-4 of the diagonal, the level at which the data's README says
  its arap500 files count as converged.

    test_edit_reference.py TOOL SHARED_DATA_DIR

Standard library only. Without the corpus: skipped (exit 77), or failed under CI=true.
"""

import math
import os
import subprocess
import sys
import tempfile


def positions(path):
    with open(path) as file:
        return [tuple(float(t) for t in line.split()[1:4]) for line in file if line.startswith("v ")]


def rms_relative(result, reference):
    lows = [min(p[k] for p in reference) for k in range(3)]
    highs = [max(p[k] for p in reference) for k in range(3)]
    diagonal = math.dist(lows, highs)
    return math.sqrt(sum(math.dist(a, b) ** 2 for a, b in zip(result, reference)) / len(reference)) / diagonal


def main():
    tool, shared_data = sys.argv[1], sys.argv[2]
    edit = os.path.join(shared_data, "edit")
    if not os.path.isfile(os.path.join(edit, "homer-c.json")):
        print("no corpus at", edit)
        return 1 if os.environ.get("CI") == "true" else 77
    with tempfile.TemporaryDirectory() as folder:
        prefix = os.path.join(folder, "homer-c")
        subprocess.run([tool, os.path.join(shared_data, "closed", "homer.obj"), os.path.join(edit, "homer-c.json"),
                        prefix], check=True)
        failures = 0
        for ours, theirs, limit in (("harmonic", "harmonic", 1e-9), ("arap10", "arap10", 1e-5),
                                    ("arap500", "arap500", 1e-4)):
            ours_positions = positions(f"{prefix}.{ours}.obj")
            theirs_positions = positions(os.path.join(edit, f"homer-c.{theirs}.obj"))
            if len(ours_positions) != len(theirs_positions):
                print(f"{ours}: {len(ours_positions)} vertices against libigl's {len(theirs_positions)}")
                failures += 1
                continue
            distance = rms_relative(ours_positions, theirs_positions)
            verdict = "ok" if distance <= limit else "FAILED"
            print(f"{ours}: rms_rel {distance:.3g} to libigl's (limit {limit:g}) {verdict}")
            failures += distance > limit
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
