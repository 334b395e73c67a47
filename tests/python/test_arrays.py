"""numpy as users hand it over: every real dtype for positions and integer dtype for faces, any
memory order, and errors that name the argument and what it got."""

import numpy as np
import pytest

import harmonia
import harmonia.errors

# A unit cube's eight corners and twelve triangles, counter-clockwise seen from outside.
CUBE_POSITIONS = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=np.float64)
CUBE_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                       [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])


@pytest.fixture(scope="module")
def reference():
    return harmonia.atlas(CUBE_POSITIONS, CUBE_FACES.astype(np.int32))


@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.float64, np.longdouble, np.int8, np.int16,
                                   np.int32, np.int64, np.uint8, np.uint16, np.uint32, np.uint64])
def test_every_real_dtype_of_positions(reference, dtype):
    # The cube's coordinates are 0 and 1: exact in every dtype, so the atlas is the same.
    atlas = harmonia.atlas(CUBE_POSITIONS.astype(dtype), CUBE_FACES)
    assert np.array_equal(atlas.corner_uv, reference.corner_uv)


@pytest.mark.parametrize("dtype", [np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16,
                                   np.uint32, np.uint64])
def test_every_integer_dtype_of_faces(reference, dtype):
    atlas = harmonia.atlas(CUBE_POSITIONS, CUBE_FACES.astype(dtype))
    assert np.array_equal(atlas.corner_uv, reference.corner_uv)


def test_any_memory_order(reference):
    fortran = harmonia.atlas(np.asfortranarray(CUBE_POSITIONS), np.asfortranarray(CUBE_FACES))
    assert np.array_equal(fortran.corner_uv, reference.corner_uv)
    # Every other row and column of larger arrays: non-contiguous views.
    wide = np.zeros((16, 6))
    wide[::2, ::2] = CUBE_POSITIONS
    faces_wide = np.zeros((24, 3), dtype=np.int64)
    faces_wide[::2] = CUBE_FACES
    strided = harmonia.atlas(wide[::2, ::2], faces_wide[::2])
    assert np.array_equal(strided.corner_uv, reference.corner_uv)
    lists = harmonia.atlas(CUBE_POSITIONS.tolist(), CUBE_FACES.tolist())
    assert np.array_equal(lists.corner_uv, reference.corner_uv)


def test_results_own_their_memory(reference):
    vmapping, indices, uvs = harmonia.parametrize(CUBE_POSITIONS, CUBE_FACES)
    for array in (vmapping, indices, uvs, reference.corner_uv, reference.chart_of_face):
        assert array.flags.owndata
        assert array.flags.writeable and array.flags.c_contiguous


@pytest.mark.parametrize("positions, faces, message", [
    (CUBE_POSITIONS[:, :2], CUBE_FACES, r"positions has shape \(8, 2\): expected \(n, 3\)"),
    (CUBE_POSITIONS, CUBE_FACES[:, :2], r"faces has shape \(12, 2\): expected \(n, 3\)"),
    (CUBE_POSITIONS.ravel(), CUBE_FACES, r"positions has shape \(24,\): expected \(n, 3\)"),
    (CUBE_POSITIONS, CUBE_FACES.astype(np.float64), r"faces has dtype float64: expected integer indices"),
    (CUBE_POSITIONS.astype(np.complex128), CUBE_FACES, r"positions has dtype complex128"),
    (np.array([["a", "b", "c"]] * 8), CUBE_FACES, r"positions has dtype <U1"),
    (CUBE_POSITIONS, CUBE_FACES + 1, r"faces\[2, 2\] = 8 is not a vertex \(there are 8: 0..7\)"),
    (CUBE_POSITIONS, CUBE_FACES - 1, r"faces\[0, 0\] = -1 is not a vertex"),
    (CUBE_POSITIONS, np.zeros((0, 3), dtype=np.int32), r"faces is empty: the mesh has no faces"),
    (None, CUBE_FACES, r"positions is None"),
])
def test_bad_arrays_are_named(positions, faces, message):
    with pytest.raises(harmonia.InvalidInputError, match=message) as raised:
        harmonia.atlas(positions, faces)
    assert isinstance(raised.value, ValueError) and isinstance(raised.value, harmonia.Error)
    assert raised.value.status == "invalid_input"


def test_not_finite_positions_are_named():
    for bad in (np.nan, np.inf):
        positions = CUBE_POSITIONS.copy()
        positions[5, 2] = bad
        with pytest.raises(harmonia.InvalidInputError, match=r"positions\[5, 2\] = (nan|inf) is not finite"):
            harmonia.parametrize(positions, CUBE_FACES)


def test_uint64_beyond_int64_is_named():
    faces = CUBE_FACES.astype(np.uint64)
    faces[3, 0] = np.uint64(2**63 + 5)
    with pytest.raises(harmonia.InvalidInputError, match=r"faces\[3, 0\] = 9223372036854775813 is not a vertex"):
        harmonia.atlas(CUBE_POSITIONS, faces)


def test_error_classes_mirror_the_statuses():
    classes = harmonia.errors.ERROR_OF_STATUS
    assert set(classes) == {"invalid_input", "parse_error", "io_error", "not_a_disk", "not_a_sphere",
                            "non_manifold", "not_converged", "numerical_failure", "flipped_triangles",
                            "cancelled", "unsupported", "device_failure"}
    for status, cls in classes.items():
        assert issubclass(cls, harmonia.Error) and cls.status == status
    assert issubclass(harmonia.FileError, OSError)
    assert issubclass(harmonia.ParseError, ValueError)


def test_file_errors_name_the_file(tmp_path):
    missing = tmp_path / "missing.obj"
    with pytest.raises(harmonia.FileError, match="missing.obj"):
        harmonia.read_mesh(missing)
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    with pytest.raises(harmonia.ParseError, match=r"broken.obj:4"):
        harmonia.read_mesh(broken)


def test_mesh_files_round_trip(tmp_path):
    for extension in ("obj", "off", "ply"):
        path = tmp_path / ("cube." + extension)
        harmonia.write_mesh(path, CUBE_POSITIONS, CUBE_FACES)
        positions, faces = harmonia.read_mesh(path)
        assert np.array_equal(positions, CUBE_POSITIONS) and np.array_equal(faces, CUBE_FACES)
    uv = CUBE_POSITIONS[:, :2] * 0.5
    path = tmp_path / "textured.obj"
    harmonia.write_textured_obj(path, CUBE_POSITIONS, CUBE_FACES, uv)
    positions, faces, read_uv, uv_faces = harmonia.read_textured_obj(path)
    assert np.array_equal(read_uv[uv_faces], uv[CUBE_FACES])
