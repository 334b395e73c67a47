"""harmonia.parametrize and harmonia.atlas on every closed corpus mesh: the atlas the program
makes, bit for bit, and xatlas-python's contract for the arrays."""

import json
import subprocess

import numpy as np
import pytest

import harmonia
from conftest import CLOSED_MESHES, corpus_path, harmonia_program, read_obj


@pytest.fixture(scope="module", autouse=True)
def the_programs_blas_policy():
    """The program holds OpenBLAS to one thread while it factorizes halves side by side, which
    rounds differently from a whole factorization: its results are reproduced under its policy."""
    previous = harmonia.set_blas_thread_policy("hold_during_split_factorizations")
    yield
    harmonia.set_blas_thread_policy(previous)


@pytest.fixture(scope="module", params=CLOSED_MESHES)
def mesh_and_program_atlas(request, tmp_path_factory):
    """A closed corpus mesh (read by the tests' own reader) and the program's atlas of it."""
    path = corpus_path("closed", request.param + ".obj")
    out = tmp_path_factory.mktemp(request.param) / "atlas.obj"
    run = subprocess.run([harmonia_program(), "atlas", str(path), str(out), "--json"],
                         capture_output=True, text=True, check=True)
    report = json.loads(run.stdout)
    positions, faces, _ = read_obj(path)
    _, program_faces, program_corner_uv = read_obj(out)
    assert np.array_equal(program_faces, faces)
    return request.param, positions, faces, program_corner_uv, report


def test_atlas_is_the_programs_bit_for_bit(mesh_and_program_atlas):
    name, positions, faces, program_corner_uv, report = mesh_and_program_atlas
    atlas = harmonia.atlas(positions, faces)
    # The program prints each UV in the shortest form that reads back to the same double.
    assert np.array_equal(atlas.corner_uv, program_corner_uv), name
    assert atlas.charts_count == report["charts"]
    assert atlas.coverage == report["coverage"]
    assert atlas.l2_stretch == report["l2_stretch"]
    assert len(atlas.charts) == report["charts"]
    assert sorted(np.concatenate([c.faces for c in atlas.charts]).tolist()) == list(range(len(faces)))
    assert set(atlas.timings) >= {"segmentation", "flattening", "packing", "metrics"}


def test_parametrize_keeps_xatlas_contract(mesh_and_program_atlas):
    name, positions, faces, program_corner_uv, _ = mesh_and_program_atlas
    vmapping, indices, uvs = harmonia.parametrize(positions, faces)
    assert vmapping.dtype == np.uint32 and vmapping.ndim == 1
    assert indices.dtype == np.uint32 and indices.shape == faces.shape
    assert uvs.dtype == np.float32 and uvs.shape == (len(vmapping), 2)
    assert vmapping.max() < len(positions) and indices.max() < len(vmapping)
    # V[vmapping] is the input's positions, every face the input face's vertices, in order.
    assert np.array_equal(positions[vmapping][indices], positions[faces])
    assert np.array_equal(vmapping[indices], faces)
    # Each corner's UV is the atlas' (to float32), and every UV lies in the unit square.
    assert np.array_equal(uvs[indices], program_corner_uv.astype(np.float32))
    assert uvs.min() >= 0.0 and uvs.max() <= 1.0
    # One output vertex per input vertex and UV: no two share both.
    pairs = np.concatenate([vmapping[:, None].astype(np.float64), uvs.astype(np.float64)], axis=1)
    assert len(np.unique(pairs, axis=0)) == len(vmapping), name


def test_atlas_writes_the_programs_obj(spot, tmp_path):
    positions, faces = spot
    ours = tmp_path / "python.obj"
    harmonia.atlas(positions, faces).write_obj(ours)
    program = tmp_path / "program.obj"
    subprocess.run([harmonia_program(), "atlas", str(corpus_path("closed", "spot.obj")), str(program)],
                   capture_output=True, check=True)
    assert ours.read_bytes() == program.read_bytes()


def test_atlas_picture_is_a_png(spot, tmp_path):
    positions, faces = spot
    picture = tmp_path / "atlas.png"
    harmonia.atlas(positions, faces).write_picture(picture, width=640, height=320, title="spot")
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_options_reach_the_atlas(spot):
    positions, faces = spot
    small = harmonia.atlas(positions, faces, resolution=256, padding=4)
    assert small.resolution == 256
    boxes = np.array([c.texel_box for c in small.charts])
    assert boxes.min() >= 0 and boxes.max() <= 256
    finer = harmonia.atlas(positions, faces, max_normal_deviation=20.0)
    assert finer.charts_count > harmonia.atlas(positions, faces).charts_count
    joined = harmonia.atlas(positions, faces, join_charts=True)
    assert joined.charts_count < harmonia.atlas(positions, faces).charts_count
    assert max(c.l2_stretch for c in joined.charts) <= 1.006
    with pytest.raises(harmonia.InvalidInputError, match="resolution"):
        harmonia.atlas(positions, faces, resolution=4)
    with pytest.raises(harmonia.InvalidInputError, match="backend"):
        harmonia.atlas(positions, faces, backend="gpu")


def test_repack_is_the_programs(tmp_path):
    """harmonia.repack of a textured OBJ: the program's `atlas --repack`, bit for bit; two charts
    (a seam splits the square's UVs), each at the one density."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    uv = np.array([[0, 0], [0.5, 0], [0.5, 0.5], [3, 3], [3.5, 3.5], [3, 3.5]])
    uv_faces = np.array([[0, 1, 2], [3, 4, 5]])
    source = tmp_path / "square.obj"
    harmonia.write_textured_obj(source, positions, faces, uv, uv_faces)
    out = tmp_path / "repacked.obj"
    subprocess.run([harmonia_program(), "atlas", str(source), str(out), "--repack"], check=True,
                   capture_output=True)
    _, program_faces, program_corner_uv = read_obj(out)
    atlas = harmonia.repack(*harmonia.read_textured_obj(source))
    assert atlas.charts_count == 2
    assert [c.method for c in atlas.charts] == ["input_layout", "input_layout"]
    assert np.array_equal(atlas.corner_uv, program_corner_uv)
    with pytest.raises(harmonia.InvalidInputError, match="corner_uv"):
        harmonia.repack(positions, faces, np.full((6, 2), np.nan), uv_faces)
