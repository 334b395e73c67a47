"""harmonia.sphere, harmonia.cut and harmonia.SurfaceEditor against the program's output on
corpus meshes, and their own invariants."""

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


def test_sphere_is_the_programs(spot, tmp_path):
    positions, faces = spot
    out = tmp_path / "sphere.obj"
    subprocess.run([harmonia_program(), "sphere", str(corpus_path("closed", "spot.obj")), str(out)],
                   capture_output=True, check=True)
    program_positions, program_faces, _ = read_obj(out)
    mapped = harmonia.sphere(positions, faces)
    assert mapped.report["status"] == "ok"
    assert np.array_equal(program_faces, faces)
    assert np.array_equal(mapped.positions, program_positions)
    # Points of the unit sphere, the poles where the angles say.
    assert np.allclose(np.linalg.norm(mapped.positions, axis=1), 1.0, rtol=0, atol=1e-12)
    polar = mapped.angles[:, 1]
    assert polar.argmin() == mapped.north_pole and polar.argmax() == mapped.south_pole
    assert mapped.date_line[0] == mapped.north_pole and mapped.date_line[-1] == mapped.south_pole


def test_sphere_refuses_a_disk():
    # Two triangles: an open square.
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    with pytest.raises(harmonia.NotASphereError):
        harmonia.sphere(positions, faces)
    with pytest.raises(harmonia.InvalidInputError, match="weights"):
        harmonia.sphere(positions, faces, weights="uniform")


def test_cut_is_the_programs(spot, tmp_path):
    positions, faces = spot
    out = tmp_path / "disk.obj"
    subprocess.run([harmonia_program(), "cut", str(corpus_path("closed", "spot.obj")), str(out)],
                   capture_output=True, check=True)
    program_positions, program_faces, _ = read_obj(out)
    disk_positions, disk_faces, original_vertex, seam_edges = harmonia.cut(positions, faces)
    assert np.array_equal(disk_positions, program_positions) and np.array_equal(disk_faces, program_faces)
    # Every disk vertex copies its input vertex and every face is the input face's; a closed mesh
    # cut along a path of k edges has its k - 1 inner vertices doubled.
    assert np.array_equal(disk_positions, positions[original_vertex])
    assert np.array_equal(original_vertex[disk_faces], faces)
    assert len(disk_positions) == len(positions) + seam_edges - 1


def edit_case(name):
    """The regions and the one frame of a public edit case (shared/data/edit)."""
    case = json.loads(corpus_path("edit", name + ".json").read_text())
    rotations, centers, scales, translations, handles = [], [], [], [], []
    for handle in case["handles"]:
        handles.append(handle["vertices"])
        rotate = handle.get("rotate", {"axis": [0, 0, 1], "degrees": 0, "center": [0, 0, 0]})
        axis = np.array(rotate["axis"], dtype=float)
        half = np.radians(rotate["degrees"]) / 2
        rotations.append(np.concatenate([[np.cos(half)], np.sin(half) * axis / np.linalg.norm(axis)]))
        centers.append(rotate["center"])
        scales.append(handle.get("scale", 1.0))
        translations.append(handle.get("translate", [0.0, 0.0, 0.0]))
    return case, handles, (np.array(rotations), np.array(centers), np.array(scales), np.array(translations))


def test_surface_editor_is_the_programs(tmp_path):
    case, handles, frame = edit_case("homer-b")
    mesh = corpus_path("edit", case["mesh"]) if corpus_path("edit").joinpath(case["mesh"]).exists() \
        else corpus_path("closed", case["mesh"])
    positions, faces, _ = read_obj(mesh)
    out = tmp_path / "homer-b.obj"
    subprocess.run([harmonia_program(), "deform", str(mesh), str(corpus_path("edit", "homer-b.json")), str(out)],
                   capture_output=True, check=True)
    program_positions, _, _ = read_obj(out)
    editor = harmonia.SurfaceEditor(positions, faces, case["fixed"]["vertices"], handles)
    first = editor.deform(*frame)
    # The program turns the file's axis and angle into a quaternion by its own arithmetic: the same
    # frame up to the rounding of that quaternion, amplified by the solve (a bound of 1e-9 of the
    # model's size, far below any visible or measurable difference).
    size = np.ptp(positions, axis=0).max()
    assert np.abs(first - program_positions).max() < 1e-9 * size
    # Constraints exact: fixed vertices stay.
    fixed = case["fixed"]["vertices"]
    assert np.array_equal(first[fixed], positions[fixed])
    # Frames reuse the one factorization, and the same frame gives the same result.
    again = editor.deform(*frame)
    assert np.array_equal(again, first) and editor.factorization_count == 1
    assert editor.last_report["status"] == "ok" and editor.last_report["flipped_triangles"] == 0
    # Dragging a handle by t moves its vertices by exactly t.
    moved = editor.drag([[0.0, 0.01, 0.0]])
    assert np.allclose(moved[handles[0]] - positions[handles[0]], [0.0, 0.01, 0.0], rtol=0, atol=1e-14 * size)
    assert editor.handle_fields.shape == (len(positions), 1)


def test_surface_editor_names_bad_regions(spot):
    positions, faces = spot
    with pytest.raises(harmonia.InvalidInputError, match="handles\\[0\\]"):
        harmonia.SurfaceEditor(positions, faces, [0, 1, 2], [[len(positions)]])
    editor = harmonia.SurfaceEditor(positions, faces, [0, 1, 2], [[100, 101]])
    with pytest.raises(harmonia.InvalidInputError, match="translations has 2 rows for 1 handles"):
        editor.drag([[0, 0, 1], [0, 0, 1]])


def test_deformation_transfer_is_the_programs(tmp_path):
    source_rest, source_faces, _ = read_obj(corpus_path("deform", "lion-reference.obj"))
    target_rest, target_faces, _ = read_obj(corpus_path("deform", "cat-reference.obj"))
    pose, _, _ = read_obj(corpus_path("deform", "lion-01.obj"))
    markers = np.loadtxt(corpus_path("deform", "markers-lion-cat.txt"), dtype=np.int64, comments="#")
    out = tmp_path / "poses"
    subprocess.run([harmonia_program(), "transfer", "--source-rest", str(corpus_path("deform", "lion-reference.obj")),
                    "--source-poses", str(corpus_path("deform", "lion-01.obj")),
                    "--target", str(corpus_path("deform", "cat-reference.obj")),
                    "--markers", str(corpus_path("deform", "markers-lion-cat.txt")), "--out", str(out)],
                   capture_output=True)  # exit code 1: some triangles turned over, written anyway
    program_positions, _, _ = read_obj(out / "lion-01.obj")
    transfer = harmonia.DeformationTransfer(source_rest, source_faces, target_rest, target_faces, markers)
    positions = transfer.transfer(pose)
    assert np.array_equal(positions, program_positions)
    assert transfer.matched_triangles + transfer.unmatched_triangles == len(target_faces)
    assert transfer.last_report["turned_over_triangles"] >= 0
    with pytest.raises(harmonia.InvalidInputError, match="source_pose has 3 rows"):
        transfer.transfer(pose[:3])
