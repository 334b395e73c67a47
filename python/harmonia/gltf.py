"""glTF 2.0 assets (``.gltf`` with external or embedded buffers, ``.glb``): read, map, write back.

A :class:`GltfDocument` is read once; its triangles come out as arrays (the default scene in world
coordinates, or one mesh), and maps of them go back into a copy of the document as a new
texture-coordinate set or new positions of each primitive, with every other part of the file kept
(materials, textures, nodes, skins, animations, extensions). What the reader decodes (strides,
normalized and sparse accessors, strips and fans, KHR_mesh_quantization, EXT_meshopt_compression,
KHR_draco_mesh_compression) and what the writer keeps is said in docs/gltf.md.

Quick start::

    import harmonia
    atlases = harmonia.atlas_gltf("Duck.glb", "Duck-atlas.glb")   # as `harmonia atlas IN OUT.glb`
    document = harmonia.read_gltf("Duck.glb")
    triangles = document.triangles()          # .positions (n, 3), .faces (m, 3), .parts
"""

import os

import numpy as np

from . import _core
from .atlas import atlas as _atlas
from .atlas import repack as _repack


class GltfDocument:
    """A glTF document in memory. Cheap to keep; reading it again is not needed to write it."""

    def __init__(self, core_document):
        self._core = core_document

    @classmethod
    def read(cls, path):
        """Read ``.gltf`` or ``.glb`` (external buffers from beside the file)."""
        return cls(_core.GltfDocument.read(os.fspath(path)))

    @property
    def name(self):
        """The file it was read from."""
        return self._core.name

    @property
    def mesh_count(self):
        """Number of meshes in the document."""
        return self._core.mesh_count

    def primitive_count(self, mesh):
        """Number of primitives of mesh ``mesh`` (an index)."""
        return self._core.primitive_count(self.mesh_index(mesh))

    def texcoord_sets(self, mesh, primitive):
        """The TEXCOORD_n sets a primitive has (n = 0 .. count - 1)."""
        return self._core.texcoord_sets(self.mesh_index(mesh), primitive)

    def texcoords(self, mesh, primitive, texcoord_set=0):
        """A primitive's TEXCOORD_n, (vertices, 2) float64, v upwards (harmonia's convention)."""
        return self._core.texcoords(self.mesh_index(mesh), primitive, texcoord_set)

    def corner_texcoords(self, triangles, texcoord_set=0):
        """TEXCOORD_n at every corner of ``triangles`` (from :meth:`triangles`), (faces, 6)."""
        return self._core.corner_texcoords(triangles, texcoord_set)

    def mesh_index(self, mesh):
        """The index of ``mesh``: an index as it is, a name looked up (InvalidInputError if none)."""
        return mesh if isinstance(mesh, int) else self._core.find_mesh(str(mesh))

    def summary(self):
        """What ``harmonia info`` lists: meshes (name, instances, primitives with mode, counts and
        attributes), scenes, nodes, materials, textures, images, skins, animations, extensions."""
        return self._core.summary()

    def triangles(self, mesh=None, primitive=None):
        """Triangles as arrays: ``.positions`` (n, 3), ``.faces`` (m, 3), ``.parts`` (a dict per
        primitive: mesh, primitive, node, first_vertex, vertex_count, first_face, face_count).

        ``mesh=None``: the default scene, each placed mesh in world coordinates (a file without a
        scene: every mesh once in its own). Else that mesh (index or name) in the world frame of
        its first instance, and only ``primitive`` of it when given.
        """
        if mesh is None:
            return self._core.scene_triangles()
        return self._core.mesh_triangles(self.mesh_index(mesh), -1 if primitive is None else primitive)

    def all_mesh_triangles(self):
        """Every mesh once, one after another (the triangles of a scene atlas)."""
        return self._core.all_mesh_triangles()

    def write(self, path, *, layouts=(), positions=(), texcoord=None, overwrite=False):
        """Write the document with new texture coordinates and positions, atomically.

        ``layouts``: tuples ``(triangles, corner_uv, chart_of_face=None, page_of_face=None)``,
        corner_uv (m, 3, 2) or (m, 6) in harmonia's convention (v up; written as glTF's v down)
        for the faces of ``triangles``; each primitive gets a new TEXCOORD_n (``texcoord``: which,
        None the lowest it lacks; ``overwrite`` lets it replace one), with chart ids a ``_CHART``
        attribute and with pages a ``_PAGE`` attribute. ``positions``: pairs ``(triangles, positions)`` (n, 3) in the coordinates the
        triangles have. The format follows the extension (.glb, or .gltf with a .bin beside it).
        """
        updates = []
        for layout in layouts:
            triangles, corner_uv = layout[0], layout[1]
            chart_of_face = layout[2] if len(layout) > 2 else None
            page_of_face = layout[3] if len(layout) > 3 else None
            updates += _core.gltf_texcoord_updates(triangles, corner_uv, chart_of_face, page_of_face)
        for triangles, new_positions in positions:
            updates += _core.gltf_position_updates(triangles, new_positions)
        _core.write_gltf(os.fspath(path), self._core, updates,
                         -1 if texcoord is None else int(texcoord), bool(overwrite))

    def __repr__(self):
        return "<harmonia.GltfDocument %s: %d meshes>" % (self.name, self.mesh_count)


def read_gltf(path):
    """Read a glTF document -> :class:`GltfDocument`."""
    return GltfDocument.read(path)


def atlas_gltf(source, destination, *, group="mesh", mesh=None, texcoord=None, overwrite=False,
               repack=False, **atlas_options):
    """``harmonia atlas SOURCE DESTINATION`` for glTF: atlases written into the document.

    ``group``: "mesh" (an atlas per mesh), "primitive" (per primitive) or "scene" (one atlas of
    every mesh at one texel density, each mesh once in the world frame of its first instance).
    ``mesh``: only this mesh (index or name). ``texcoord``/``overwrite`` as
    :meth:`GltfDocument.write`. ``repack``: keep each primitive's TEXCOORD_0 charts and only
    pack them anew (:func:`harmonia.repack`; ``atlas_options`` then those it takes).
    ``atlas_options``: those of :func:`harmonia.atlas`.
    Returns a list of ``(name, Atlas)``, one per atlas, in the order they were made.
    """
    if group not in ("mesh", "primitive", "scene"):
        raise ValueError("group must be 'mesh', 'primitive' or 'scene', not %r" % (group,))
    document = read_gltf(source)
    meshes = [document.mesh_index(mesh)] if mesh is not None else list(range(document.mesh_count))
    groups = []
    if group == "scene":
        triangles = document.all_mesh_triangles() if mesh is None else document.triangles(meshes[0])
        groups.append(("scene", triangles))
    for index in meshes if group != "scene" else []:
        if group == "mesh":
            groups.append(("mesh %d" % index, document.triangles(index)))
        else:
            for primitive in range(document.primitive_count(index)):
                groups.append(("meshes[%d].primitives[%d]" % (index, primitive),
                               document.triangles(index, primitive)))
    made, layouts = [], []
    for name, triangles in groups:
        if len(triangles.faces) == 0:
            continue
        if repack:
            corners = document.corner_texcoords(triangles, 0).reshape(-1, 3, 2)
            result = _repack(triangles.positions, triangles.faces, corners.reshape(-1, 2),
                             np.arange(3 * len(corners)).reshape(-1, 3), **atlas_options)
        else:
            result = _atlas(triangles.positions, triangles.faces, **atlas_options)
        made.append((name, result))
        layouts.append((triangles, result.corner_uv, result.chart_of_face,
                        result.page_of_face if result.pages > 1 else None))
    document.write(destination, layouts=layouts, texcoord=texcoord, overwrite=overwrite)
    return made
