"""Shared pieces of the Python package's tests: where the corpus and the program are, an OBJ reader
of their own (independent of the library's), and midpoint subdivision for larger meshes.

The corpus is ../shared/data beside the checkout (or $HARMONIA_SHARED_DATA). Without it the tests
that need it are skipped, except under CI=true, where they fail.
"""

import os
import pathlib

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]
SHARED_DATA = pathlib.Path(os.environ.get("HARMONIA_SHARED_DATA", SOURCE_DIR.parent / "shared" / "data"))
CLOSED_MESHES = ["bunny", "cheburashka", "cow", "decimated-max", "elephant", "fandisk", "homer", "spot"]


def corpus_path(*parts):
    """A path of the corpus; skips the test without it (fails under CI=true)."""
    path = SHARED_DATA.joinpath(*parts)
    if not path.exists():
        if os.environ.get("CI") == "true":
            pytest.fail("the corpus is missing: %s (CI=true needs ../shared/data)" % path)
        pytest.skip("no corpus at %s" % path)
    return path


def harmonia_program():
    """The harmonia program of this build ($HARMONIA_CLI, set by the build's test registration)."""
    program = os.environ.get("HARMONIA_CLI", "")
    if not program or not os.path.exists(program):
        pytest.fail("HARMONIA_CLI does not name the harmonia program: %r" % program)
    return program


def read_obj(path):
    """Positions, faces, and per-corner UVs (None without vt) of an OBJ: v, vt and f lines only,
    polygons as fans; written here so that the tests do not check the library with itself."""
    positions, uvs, faces, corner_uv = [], [], [], []
    with open(path) as text:
        for line in text:
            fields = line.split()
            if not fields:
                continue
            if fields[0] == "v":
                positions.append([float(x) for x in fields[1:4]])
            elif fields[0] == "vt":
                uvs.append([float(x) for x in fields[1:3]])
            elif fields[0] == "f":
                corners = [field.split("/") for field in fields[1:]]
                vertex = [int(c[0]) - 1 if int(c[0]) > 0 else len(positions) + int(c[0]) for c in corners]
                texture = [int(c[1]) - 1 for c in corners] if len(corners[0]) > 1 and corners[0][1] else None
                for k in range(1, len(vertex) - 1):
                    faces.append([vertex[0], vertex[k], vertex[k + 1]])
                    if texture is not None:
                        corner_uv.append([uvs[texture[0]], uvs[texture[k]], uvs[texture[k + 1]]])
    positions = np.array(positions, dtype=np.float64)
    faces = np.array(faces, dtype=np.int64).reshape(-1, 3)
    return positions, faces, (np.array(corner_uv, dtype=np.float64) if corner_uv else None)


def subdivide(positions, faces, times=1):
    """1 -> 4 midpoint subdivision (shared_data's subdivide.py, in numpy): the shape unchanged."""
    for _ in range(times):
        edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
        unique, inverse = np.unique(np.sort(edges, axis=1), axis=0, return_inverse=True)
        midpoints = (positions[unique[:, 0]] + positions[unique[:, 1]]) / 2
        mid = inverse.reshape(3, -1).T + len(positions)  # ab, bc, ca per face
        a, b, c = faces.T
        ab, bc, ca = mid.T
        faces = np.concatenate([np.stack(t, axis=1) for t in
                                ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
        positions = np.concatenate([positions, midpoints])
    return positions, faces


@pytest.fixture(scope="session")
def spot():
    """spot.obj of the corpus (2,930 vertices, 5,856 faces)."""
    positions, faces, _ = read_obj(corpus_path("closed", "spot.obj"))
    return positions, faces
