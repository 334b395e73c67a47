"""harmonia.unwrap with every method against `harmonia unwrap`, and harmonia.evaluate against
`harmonia eval`, on a disk of the corpus."""

import json
import subprocess

import numpy as np
import pytest

import harmonia
from conftest import corpus_path, harmonia_program, read_obj


@pytest.fixture(scope="module", autouse=True)
def the_programs_blas_policy():
    previous = harmonia.set_blas_thread_policy("hold_during_split_factorizations")
    yield
    harmonia.set_blas_thread_policy(previous)


@pytest.fixture(scope="module")
def woody():
    """woody.obj, a small disk of the corpus."""
    return corpus_path("disk", "woody.obj")


METHODS = [
    ("conformal", {}, []),
    ("conformal", {"weights": "mean-value", "boundary": "square"}, ["--weights", "mean-value", "--boundary", "square"]),
    ("lscm", {}, []),
    ("qhm", {"rounds": 3}, ["--rounds", "3"]),
    ("abf", {"boundary_t": 1.0}, ["--boundary-t", "1"]),
    ("linabf", {"reconstruction": "greedy"}, ["--reconstruction", "greedy"]),
    ("free", {"polish": True}, ["--polish"]),
    ("conformal", {"normalize": "unit-square"}, ["--normalize", "unit-square"]),
]


@pytest.mark.parametrize("method, keywords, flags", METHODS)
def test_unwrap_is_the_programs(woody, tmp_path, method, keywords, flags):
    positions, faces, _ = read_obj(woody)
    out = tmp_path / "uv.obj"
    subprocess.run([harmonia_program(), "unwrap", str(woody), str(out), "--method", method] + flags,
                   capture_output=True, check=True)
    _, program_faces, program_corner_uv = read_obj(out)
    uv, report = harmonia.unwrap(positions, faces, method=method, **keywords)
    assert report["status"] == "ok" and uv.shape == (len(positions), 2)
    assert np.array_equal(program_faces, faces)
    # One vt per vertex: the program's corner UVs are the rows of uv at each face's vertices.
    assert np.array_equal(uv[faces], program_corner_uv), method


def test_evaluate_is_the_programs(woody, tmp_path):
    positions, faces, _ = read_obj(woody)
    out = tmp_path / "uv.obj"
    subprocess.run([harmonia_program(), "unwrap", str(woody), str(out), "--method", "lscm"],
                   capture_output=True, check=True)
    figures = json.loads(subprocess.run([harmonia_program(), "eval", str(woody), str(out), "--json"],
                                        capture_output=True, text=True, check=True).stdout)
    uv, _ = harmonia.unwrap(positions, faces, method="lscm")
    ours = harmonia.evaluate(positions, faces, uv)
    for key in ("flipped_triangles", "zero_area_triangles", "boundary_self_intersections",
                "conformal_distortion_mean", "conformal_distortion_max", "area_distortion_mean",
                "area_distortion_max", "l2_stretch", "angle_error_mean_squared", "abf_energy", "faces"):
        assert ours[key] == figures[key], key


def test_unwrap_refuses_what_it_cannot_map(spot):
    positions, faces = spot
    with pytest.raises(harmonia.NotADiskError):
        harmonia.unwrap(positions, faces)
    disk_positions, disk_faces, _, _ = harmonia.cut(positions, faces)
    uv, report = harmonia.unwrap(disk_positions, disk_faces, method="lscm")
    assert harmonia.evaluate(disk_positions, disk_faces, uv)["flipped_triangles"] == report["flipped_triangles"]
    with pytest.raises(harmonia.InvalidInputError, match="method is \"tutte\""):
        harmonia.unwrap(disk_positions, disk_faces, method="tutte")
    with pytest.raises(harmonia.InvalidInputError, match="takes weights"):
        harmonia.unwrap(disk_positions, disk_faces, method="qhm", weights="uniform")


def test_compare_is_the_programs(woody, tmp_path):
    positions, faces, _ = read_obj(woody)
    files = []
    for method in ("lscm", "conformal"):
        out = tmp_path / (method + ".obj")
        subprocess.run([harmonia_program(), "unwrap", str(woody), str(out), "--method", method],
                       capture_output=True, check=True)
        files.append(out)
    plot = tmp_path / "program.png"
    program = json.loads(subprocess.run([harmonia_program(), "compare", str(woody)] + [str(f) for f in files]
                                        + ["--json", "--picture", str(plot)],
                                        capture_output=True, text=True, check=True).stdout)
    layouts = {"lscm.obj": harmonia.unwrap(positions, faces, method="lscm")[0],
               "conformal.obj": harmonia.unwrap(positions, faces)[0]}
    picture = tmp_path / "python.png"
    table = harmonia.compare(positions, faces, layouts, picture=picture)
    for row in program["layouts"]:
        ours = table[row["label"]]
        for key in ("flipped_triangles", "conformal_distortion_mean", "area_distortion_mean", "l2_stretch",
                    "angle_error_mean_squared", "boundary_self_intersections"):
            assert ours[key] == row[key], (row["label"], key)
        assert np.nanmax(ours["face_angle_distortion"]) == row["angle_distortion_max"]
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cleanup_cut_unwrap_is_the_programs_unwrap_with_both(spot, tmp_path):
    positions, faces = spot
    # The mesh as files often come: a vertex written twice, one face using the copy.
    doubled = np.concatenate([positions, positions[:1]])
    dirty_faces = faces.copy()
    dirty_faces[np.argmax((faces == 0).any(axis=1))] = np.where(
        faces[np.argmax((faces == 0).any(axis=1))] == 0, len(positions), faces[np.argmax((faces == 0).any(axis=1))])
    dirty = tmp_path / "dirty.obj"
    harmonia.write_mesh(dirty, doubled, dirty_faces)
    out = tmp_path / "uv.obj"
    subprocess.run([harmonia_program(), "unwrap", str(dirty), str(out), "--method", "lscm",
                    "--cleanup", "repair", "--cut"], capture_output=True, check=True)
    _, program_faces, program_corner_uv = read_obj(out)
    with pytest.raises(harmonia.InvalidInputError, match="unreferenced vertex, first v2930"):  # strict names it
        harmonia.cleanup(np.concatenate([positions, [[9.0, 9.0, 9.0]]]), faces, mode="strict")
    clean = harmonia.cleanup(doubled, dirty_faces)
    assert clean.merged_vertices == 1 and clean.changes
    disk_positions, disk_faces, original_vertex, _ = harmonia.cut(clean.positions, clean.faces)
    uv, _ = harmonia.unwrap(disk_positions, disk_faces, method="lscm")
    # The program writes the input's vertices with the disk's UVs per corner.
    assert np.array_equal(clean.original_vertex[original_vertex[disk_faces]], program_faces)
    assert np.array_equal(uv[disk_faces], program_corner_uv)
