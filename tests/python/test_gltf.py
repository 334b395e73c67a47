"""harmonia.read_gltf and harmonia.atlas_gltf against the program: the same glTF bytes as
`harmonia atlas IN OUT.glb` for every grouping, the triangles as `harmonia info` counts them, and
the writer's refusals."""

import json
import subprocess

import numpy as np
import pytest

import harmonia
from conftest import corpus_path, harmonia_program


@pytest.fixture(scope="module", autouse=True)
def the_programs_blas_policy():
    previous = harmonia.set_blas_thread_policy("hold_during_split_factorizations")
    yield
    harmonia.set_blas_thread_policy(previous)


@pytest.mark.parametrize("asset,group", [("Duck.glb", "mesh"), ("CesiumMilkTruck.glb", "mesh"),
                                         ("CesiumMilkTruck.glb", "scene"),
                                         ("CesiumMilkTruck.glb", "primitive")])
def test_atlas_gltf_is_the_programs(asset, group, tmp_path):
    source = corpus_path("gltf", asset)
    by_program, by_python = tmp_path / "program.glb", tmp_path / "python.glb"
    subprocess.run([harmonia_program(), "atlas", str(source), str(by_program), "--group", group],
                   capture_output=True, check=True)
    made = harmonia.atlas_gltf(source, by_python, group=group)
    assert by_python.read_bytes() == by_program.read_bytes()
    assert all(atlas.metrics["flipped_triangles"] == 0 for _, atlas in made)


def test_paged_atlas_gltf_is_the_programs(tmp_path):
    # At a texel density the Duck does not fit one 256^2 square: pages, and each vertex's page in
    # _PAGE, the same bytes as the program's.
    source = corpus_path("gltf", "Duck.glb")
    by_program, by_python = tmp_path / "program.glb", tmp_path / "python.glb"
    subprocess.run([harmonia_program(), "atlas", str(source), str(by_program), "--resolution", "256",
                    "--texels-per-unit", "150"], capture_output=True, check=True)
    (_, atlas), = harmonia.atlas_gltf(source, by_python, resolution=256, texels_per_unit=150.0)
    assert atlas.pages > 1
    assert by_python.read_bytes() == by_program.read_bytes()
    assert b'"_PAGE"' in by_python.read_bytes()
    assert sorted(set(atlas.page_of_face.tolist())) == list(range(atlas.pages))
    assert [chart.page for chart in atlas.charts] == [atlas.page_of_face[chart.faces[0]] for chart in atlas.charts]
    assert len(atlas.metrics["page_coverage"]) == atlas.pages
    assert atlas.metrics["overlapping_texels"] == 0


def test_non_square_atlas_gltf_is_the_programs(tmp_path):
    source = corpus_path("gltf", "Duck.glb")
    by_program, by_python = tmp_path / "program.glb", tmp_path / "python.glb"
    subprocess.run([harmonia_program(), "atlas", str(source), str(by_program), "--resolution", "512x256"],
                   capture_output=True, check=True)
    (_, atlas), = harmonia.atlas_gltf(source, by_python, resolution=(512, 256))
    assert (atlas.resolution, atlas.height) == (512, 256)
    assert by_python.read_bytes() == by_program.read_bytes()
    with pytest.raises(ValueError):
        harmonia.atlas_gltf(source, tmp_path / "bad.glb", resolution=(512, 256, 1))


def test_triangles_are_the_ones_the_program_reads(tmp_path):
    source = corpus_path("gltf", "CesiumMilkTruck.glb")
    info = json.loads(subprocess.run([harmonia_program(), "info", str(source), "--json"],
                                     capture_output=True, check=True, text=True).stdout)
    document = harmonia.read_gltf(source)
    triangles = document.triangles()
    assert len(triangles.positions) == info["vertices"] and len(triangles.faces) == info["faces"]
    positions, faces = harmonia.read_mesh(source)
    assert np.array_equal(positions, triangles.positions) and np.array_equal(faces, triangles.faces)
    # The wheels are placed twice in the scene, once in a mesh of their own.
    wheels = document.triangles("Wheels")
    assert document.summary()["meshes"][1]["instances"] == 2
    assert len(wheels.faces) * 2 + len(document.triangles(0).faces) == len(triangles.faces)


def test_writing_refuses_a_set_the_primitive_has(tmp_path):
    source = corpus_path("gltf", "Duck.glb")
    with pytest.raises(harmonia.InvalidInputError, match="already has TEXCOORD_0"):
        harmonia.atlas_gltf(source, tmp_path / "out.glb", texcoord=0)
    with pytest.raises(harmonia.InvalidInputError, match="gap"):
        harmonia.atlas_gltf(source, tmp_path / "out.glb", texcoord=3)
    assert not (tmp_path / "out.glb").exists()
    with pytest.raises(harmonia.InvalidInputError, match="no mesh named"):
        harmonia.read_gltf(source).triangles("Nope")


def test_positions_go_back_into_each_primitive(tmp_path):
    source = corpus_path("gltf", "Duck.glb")
    document = harmonia.read_gltf(source)
    triangles = document.triangles()
    moved = triangles.positions + np.array([1.0, 2.0, 3.0])
    document.write(tmp_path / "moved.glb", positions=[(triangles, moved)])
    back = harmonia.read_gltf(tmp_path / "moved.glb").triangles()
    assert np.array_equal(back.faces, triangles.faces)
    # Written as floats through the node's inverse transform: equal to float precision.
    scale = np.abs(moved).max()
    assert np.allclose(back.positions, moved, rtol=0, atol=4 * np.finfo(np.float32).eps * scale)


def test_repack_is_the_programs_and_keeps_the_texture_set(tmp_path):
    """atlas_gltf(repack=True): the program's `atlas --repack` bytes; TEXCOORD_0 read back as it was,
    the repacked set added beside it."""
    source = corpus_path("gltf", "Duck.glb")
    by_program, by_python = tmp_path / "program.glb", tmp_path / "python.glb"
    subprocess.run([harmonia_program(), "atlas", str(source), str(by_program), "--repack"],
                   capture_output=True, check=True)
    made = harmonia.atlas_gltf(source, by_python, repack=True)
    assert by_python.read_bytes() == by_program.read_bytes()
    assert {c.method for c in made[0][1].charts} == {"input_layout"}
    before, after = harmonia.read_gltf(source), harmonia.read_gltf(by_python)
    assert after.texcoord_sets(0, 0) == before.texcoord_sets(0, 0) + 1
    triangles_before, triangles_after = before.triangles(0), after.triangles(0)
    assert np.array_equal(before.corner_texcoords(triangles_before, 0),
                          after.corner_texcoords(triangles_after, 0))
