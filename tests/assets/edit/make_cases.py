#!/usr/bin/python3
"""Writes the edit cases of this folder (<case>.json), limbs turned about their joints on the closed
corpus meshes with legs or arms, in the format of ../shared/data/edit/README.md: explicit vertex
lists, with the selection that chose them recorded beside them.

    /usr/bin/python3 tests/assets/edit/make_cases.py [SHARED_DATA_DIR]

Selections (the public cases' own words): below(axis, v) = the vertices whose coordinate is < v;
ball(center, r) = the vertices within r of the centre, restricted to the edge-connected piece that
holds the vertex nearest to it; beyond(q, n, seed) = the vertices with n.(p - q) > 0, restricted to
the piece that holds the vertex nearest to seed; piece(below(axis, v), seed) = the piece of
below(axis, v) that holds the vertex nearest to seed. The fixed set is always below(y, v) less the
handles' vertices (the feet the character stands on). Standard library only.
"""

import json
import math
import os
import sys

AXES = {"x": 0, "y": 1, "z": 2}

# Each case: the mesh, what it does, the fixed set's below(y, v), and the handles. A handle's
# selection is ("ball", center, r), ("beyond", q, n, seed) or ("piece_below", axis, v, seed).
CASES = {
    "cheburashka-a": {
        "mesh": "cheburashka", "fixed_below_y": 0.16,
        "description": "lower the right arm 70 degrees about the shoulder; feet fixed",
        "handles": [{"select": ("ball", [0.262, 0.29, 0.48], 0.045),
                     "rotate": {"axis": [0, 0, 1], "degrees": -70, "center": [0.33, 0.45, 0.48]}}]},
    "cheburashka-b": {
        "mesh": "cheburashka", "fixed_below_y": 0.16,
        "description": "turn the head 50 degrees about the vertical; pull the left hand forward; feet fixed",
        "handles": [{"select": ("beyond", [0, 0.66, 0], [0, 1, 0], [0.5, 0.9, 0.5]),
                     "rotate": {"axis": [0, 1, 0], "degrees": 50, "center": [0.5, 0.6, 0.5]}},
                    {"select": ("ball", [0.735, 0.29, 0.48], 0.045), "translate": [0.05, -0.03, 0.1]}]},
    "cow-a": {
        "mesh": "cow", "fixed_below_y": -0.25,
        "description": "swing the left foreleg 40 degrees forward about the shoulder; the other hooves fixed",
        "handles": [{"select": ("piece_below", "y", -0.25, [0.122, -0.3, 0.091]),
                     "rotate": {"axis": [0, 0, 1], "degrees": 40, "center": [0.12, -0.08, 0.09]}}]},
    "cow-b": {
        "mesh": "cow", "fixed_below_y": -0.25,
        "description": "lower the head 35 degrees about the neck; hooves fixed",
        "handles": [{"select": ("beyond", [0.3, 0, 0], [1, 0, 0], [0.52, 0.15, 0]),
                     "rotate": {"axis": [0, 0, 1], "degrees": -35, "center": [0.27, 0.15, 0]}}]},
    "spot-a": {
        "mesh": "spot", "fixed_below_y": -0.6,
        "description": "swing the right foreleg 30 degrees forward about its top; the other feet fixed",
        "handles": [{"select": ("piece_below", "y", -0.6, [-0.228, -0.7, 0.042]),
                     "rotate": {"axis": [1, 0, 0], "degrees": 30, "center": [-0.23, -0.35, 0.04]}}]},
    "spot-b": {
        "mesh": "spot", "fixed_below_y": -0.6,
        "description": "turn the head 45 degrees about the vertical at the neck; feet fixed",
        "handles": [{"select": ("beyond", [0, 0, -0.35], [0, 0, -1], [0, 0.5, -0.65]),
                     "rotate": {"axis": [0, 1, 0], "degrees": 45, "center": [0, 0.4, -0.3]}}]},
    "homer-d": {
        "mesh": "homer", "fixed_below_y": 0.19,
        "description": "kick the right leg 40 degrees forward about the hip; the left foot fixed",
        "handles": [{"select": ("piece_below", "y", 0.19, [0.435, 0.17, 0.517]),
                     "rotate": {"axis": [1, 0, 0], "degrees": -40, "center": [0.44, 0.38, 0.49]}}]},
    "elephant-d": {
        "mesh": "elephant", "fixed_below_y": 3.0,
        "description": "raise the right arm 50 degrees about the shoulder; feet fixed",
        "handles": [{"select": ("ball", [-45.16, 51.0, -1.4], 12.0),
                     "rotate": {"axis": [0, 0, 1], "degrees": -50, "center": [-20.0, 51.0, 0.0]}}]},
    "elephant-e": {
        "mesh": "elephant", "fixed_below_y": 3.0,
        "description": "kick the right leg 30 degrees forward about the hip; the left foot fixed",
        "handles": [{"select": ("piece_below", "y", 3.0, [-13.0, 0.0, 0.0]),
                     "rotate": {"axis": [1, 0, 0], "degrees": -30, "center": [-12.0, 18.0, 0.0]}}]},
}


def read_obj(path):
    vertices, faces = [], []
    with open(path) as file:
        for line in file:
            if line.startswith("v "):
                vertices.append(tuple(float(t) for t in line.split()[1:4]))
            elif line.startswith("f "):
                corners = [int(t.split("/")[0]) - 1 for t in line.split()[1:]]
                for k in range(1, len(corners) - 1):
                    faces.append((corners[0], corners[k], corners[k + 1]))
    return vertices, faces


def neighbours_of(vertex_count, faces):
    neighbours = [set() for _ in range(vertex_count)]
    for a, b, c in faces:
        neighbours[a] |= {b, c}
        neighbours[b] |= {a, c}
        neighbours[c] |= {a, b}
    return neighbours


def piece_holding(candidates, seed_point, vertices, neighbours):
    """The edge-connected piece of `candidates` that holds the candidate nearest to seed_point."""
    start = min(candidates, key=lambda v: math.dist(vertices[v], seed_point))
    piece, stack = {start}, [start]
    while stack:
        for w in neighbours[stack.pop()]:
            if w in candidates and w not in piece:
                piece.add(w)
                stack.append(w)
    return piece


def select(selection, vertices, neighbours):
    kind = selection[0]
    if kind == "ball":
        _, center, radius = selection
        inside = {v for v, p in enumerate(vertices) if math.dist(p, center) <= radius}
        return piece_holding(inside, center, vertices, neighbours), f"ball(center={center}, r={radius})"
    if kind == "beyond":
        _, q, n, seed = selection
        ahead = {v for v, p in enumerate(vertices) if sum(n[k] * (p[k] - q[k]) for k in range(3)) > 0}
        return piece_holding(ahead, seed, vertices, neighbours), f"beyond(q={q}, n={n}, seed={seed})"
    if kind == "piece_below":
        _, axis, value, seed = selection
        below = {v for v, p in enumerate(vertices) if p[AXES[axis]] < value}
        return piece_holding(below, seed, vertices, neighbours), f"piece(below({axis}, {value}), seed={seed})"
    raise ValueError(f"unknown selection {kind}")


def main():
    shared_data = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..", "shared", "data")
    here = os.path.dirname(os.path.abspath(__file__))
    for name, case in CASES.items():
        vertices, faces = read_obj(os.path.join(shared_data, "closed", case["mesh"] + ".obj"))
        neighbours = neighbours_of(len(vertices), faces)
        handles, taken = [], set()
        for handle in case["handles"]:
            chosen, words = select(handle["select"], vertices, neighbours)
            if chosen & taken:
                raise SystemExit(f"{name}: handles overlap")
            taken |= chosen
            entry = {"selection": words, "vertices": sorted(chosen)}
            for key in ("translate", "rotate"):
                if key in handle:
                    entry[key] = handle[key]
            handles.append(entry)
        level = case["fixed_below_y"]
        fixed = sorted(v for v, p in enumerate(vertices) if p[1] < level and v not in taken)
        edit = {"mesh": case["mesh"] + ".obj", "description": case["description"],
                "fixed": {"selection": f"below(y, {level}) less the handles", "vertices": fixed},
                "handles": handles}
        with open(os.path.join(here, name + ".json"), "w") as file:
            json.dump(edit, file, separators=(",", ":"))
            file.write("\n")
        print(name, "fixed", len(fixed), "handles", [len(h["vertices"]) for h in handles])


if __name__ == "__main__":
    main()
