"""Mesh files: OBJ, OFF, PLY (ASCII and binary), STL and glTF in, OBJ, OFF, PLY and glTF out.

Readers accept what the usual tools accept (polygons are triangulated as fans, OBJ's v/vt/vn and
negative indices, STL corners at one point merged) and raise :class:`harmonia.ParseError` with
"FILE:LINE: problem" for a file that holds no usable surface, :class:`harmonia.FileError` for one
that cannot be opened. Writers replace their file atomically: a failure leaves it as it was.
"""

import os

from . import _core


def read_mesh(path):
    """Read a mesh file (format by extension) -> ``(positions, faces)``.

    positions: (n, 3) float64; faces: (m, 3) int32, counter-clockwise, 0-based. A glTF file gives
    the triangles of its default scene in world coordinates (see :mod:`harmonia.gltf`).
    """
    return _core.read_mesh(os.fspath(path))


def read_textured_obj(path):
    """Read an OBJ with texture coordinates -> ``(positions, faces, uv, uv_faces)``.

    uv: (k, 2) float64; uv_faces: (m, 3) int32, the uv row of each corner of each face.
    """
    return _core.read_textured_obj(os.fspath(path))


def write_mesh(path, positions, faces):
    """Write positions (n, 3) and faces (m, 3) as OBJ, OFF, PLY or glTF (by extension), atomically."""
    _core.write_mesh(os.fspath(path), positions, faces)


def write_textured_obj(path, positions, faces, uv, uv_faces=None):
    """Write an OBJ with texture coordinates, atomically.

    uv: (k, 2); uv_faces: (m, 3) rows of uv per corner, or None when uv has one row per position.
    """
    _core.write_textured_obj(os.fspath(path), positions, faces, uv, uv_faces)
