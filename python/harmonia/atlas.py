"""Texture atlases of any triangle mesh, and a drop-in for xatlas' ``parametrize``.

The surface is cut into charts that are topological disks, each flattened without a fold (linear
ABF, relaxed toward an isometry where that stretches less, else the free-boundary quasi-harmonic
map, else a Tutte embedding) within a distortion limit,
and packed at one texel density into a square texture. Vertices an exporter split at one point
are one point while charting, so charts span the file's seams (``keep_splits=True`` keeps them).
"""

import os
from dataclasses import dataclass

import numpy as np

from . import _core



def parametrize(positions, indices, *, resolution=1024, padding=2, max_distortion=1.0025,
                threads=0, backend="auto", device=None, progress=None, cancel=None):
    """Texture atlas in xatlas-python's form: ``vmapping, indices, uvs = parametrize(V, F)``.

    The same contract as ``xatlas.parametrize``, so that ``V[vmapping]`` code keeps working:

    - vmapping: (k,) uint32, the input vertex of each output vertex;
    - indices: (m, 3) uint32, the input's faces in input order over the output vertices;
    - uvs: (k, 2) float32 in [0, 1] (v up, OBJ's convention).

    An output vertex is an input vertex at one UV: a vertex on a chart boundary appears once per
    chart. Options: ``resolution`` (texels per side), ``padding`` (texels between charts; half
    of them along the atlas' edges), ``max_distortion`` (largest L2 stretch of a chart, > 1), ``threads`` (0: one per core),
    ``backend`` ("auto", "cpu", "vulkan"), ``device`` (a :class:`harmonia.VulkanContext`),
    ``progress`` (callable(phase, fraction); return False to cancel) and ``cancel`` (a
    ``threading.Event``). Raises :class:`harmonia.Error` subclasses, e.g. InvalidInputError.
    """
    result = _core.texture_atlas(positions, indices, resolution=resolution, padding=padding,
                                 max_distortion=max_distortion, max_normal_deviation=60.0,
                                 keep_splits=False, threads=threads, backend=backend,
                                 device=device, progress=progress, cancel=cancel)
    return result.xatlas_form()


@dataclass(frozen=True)
class Chart:
    """One chart of an atlas: its faces and how well it was flattened."""

    faces: object           #: (k,) int32, the chart's faces in input order
    method: str             #: "linear_abf", "relaxed_linear_abf", "free_boundary", "tutte", "single_triangle", "degenerate", "projection", "input_layout"
    piece_of_a_cut: bool    #: a piece of a larger chart that was cut, keeping its layout
    l2_stretch: float       #: Sander's L2 stretch (1: an isometry), the chart scaled to its area
    angle_distortion: float  #: area-weighted mean sigma1/sigma2
    area_distortion: float  #: area-weighted mean |log area ratio|
    surface_area: float     #: the chart's 3D area
    texel_box: tuple        #: (xmin, ymin, xmax, ymax) in texels, y up from the bottom
    page: int = 0           #: the atlas page it is on (0 unless the atlas has several)


class Atlas:
    """A texture atlas and its report (what ``harmonia atlas --json`` prints).

    Attributes: ``corner_uv`` ((m, 3, 2) float64 UVs of each face's corners, in [0, 1] over
    the face's page), ``chart_of_face`` ((m,) int32), ``charts`` (list of :class:`Chart`),
    ``resolution`` (the width in texels) and ``height``, ``pages`` (squares of resolution x resolution texels: 1 unless a
    ``texels_per_unit`` did not fit one), ``page_of_face`` ((m,) int32),
    ``welded_vertices`` (vertices merged with an earlier one at the same point), ``metrics``
    (dict: charts, coverage, page_coverage, texels_per_unit, l2_stretch, angle_distortion,
    area_distortion, flipped_triangles, mirrored_charts, overlapping_texels, boundary_crossings,
    dropped_faces),
    ``report`` (dict: backend, solver, backend_notice, timings per phase, seconds, fallbacks),
    and the main figures as attributes of their own.
    """

    def __init__(self, core_result):
        self._core = core_result
        self.corner_uv = core_result.corner_uv
        self.chart_of_face = core_result.chart_of_face
        self.charts = [Chart(**chart) for chart in core_result.charts]
        self.metrics = core_result.metrics
        self.report = core_result.report
        self.resolution = core_result.resolution
        self.height = core_result.height
        self.pages = core_result.pages
        self.page_of_face = core_result.page_of_face
        self.welded_vertices = core_result.welded_vertices

    @property
    def charts_count(self):
        """Number of charts."""
        return self.metrics["charts"]

    @property
    def coverage(self):
        """Share of the atlas' texels covered by charts."""
        return self.metrics["coverage"]

    @property
    def l2_stretch(self):
        """Sander's L2 stretch of the whole atlas (1: no stretch)."""
        return self.metrics["l2_stretch"]

    @property
    def texels_per_unit(self):
        """Texels per unit of 3D length: the texel density, one for all charts."""
        return self.metrics["texels_per_unit"]

    @property
    def timings(self):
        """Seconds per phase (segmentation, flattening, packing, metrics, ...)."""
        return self.report["timings"]

    def xatlas_form(self):
        """``(vmapping, indices, uvs)`` as :func:`parametrize` returns them."""
        return self._core.xatlas_form()

    def write_obj(self, path):
        """Write the OBJ ``harmonia atlas`` writes: input vertices and faces, per-corner vt."""
        self._core.write_obj(os.fspath(path))

    def write_picture(self, path, *, width=1600, height=800, title=""):
        """Draw the atlas coloured by distortion beside the mesh wearing a checker (PNG)."""
        self._core.write_picture(os.fspath(path), width, height, title)

    def __repr__(self):
        return ("<harmonia.Atlas: %d charts, coverage %.3f, L2 stretch %.4f, %d x %d texels>"
                % (self.charts_count, self.coverage, self.l2_stretch, self.resolution,
                   self.height))


def _width_and_height(resolution):
    """``resolution`` as an int (a square) or a pair (width, height) -> (width, height or 0)."""
    if isinstance(resolution, (tuple, list)):
        if len(resolution) != 2:
            raise ValueError("resolution must be N or (width, height), not %r" % (resolution,))
        width, height = int(resolution[0]), int(resolution[1])
        return width, (0 if height == width else height)
    return int(resolution), 0


def repack(positions, faces, uv, uv_faces=None, *, resolution=1024, padding=2, threads=0,
           texels_per_unit=0.0, max_pages=0):
    """The atlas of a mesh's own UV charts, only packed anew -> :class:`Atlas` (``harmonia atlas
    --repack``).

    uv: (k, 2) and uv_faces: (m, 3), the uv row of each face corner, as
    :func:`harmonia.read_textured_obj` returns them (uv_faces None: one uv row per position).
    The charts are the input's (faces joined where an edge has the same vertices and UVs in
    both), each kept as it is laid out at the atlas' one texel density and turned by quarter
    turns at most; ``resolution``, ``padding``, ``threads``, ``texels_per_unit`` and
    ``max_pages`` as in :func:`atlas`. Chart methods are "input_layout".
    """
    uv = np.asarray(uv, dtype=np.float64)
    corners = uv[np.asarray(faces) if uv_faces is None else np.asarray(uv_faces)]
    width, height = _width_and_height(resolution)
    return Atlas(_core.repack_atlas(positions, faces, corners.reshape(len(corners), 6),
                                    resolution=width, padding=padding, threads=threads,
                                    texels_per_unit=texels_per_unit, max_pages=max_pages,
                                    height=height))


def atlas(positions, faces, *, resolution=1024, padding=2, max_distortion=1.0025,
          max_normal_deviation=60.0, keep_splits=False, threads=0, backend="auto", device=None,
          progress=None, cancel=None, texels_per_unit=0.0, join_charts=False, max_pages=0):
    """Texture atlas of any triangle mesh -> :class:`Atlas` (the options of ``harmonia atlas``).

    positions: (n, 3) of any real dtype; faces: (m, 3) of any integer dtype. Options as
    :func:`parametrize` (``resolution`` also a pair ``(width, height)``: a non-square atlas),
    and ``max_normal_deviation`` (degrees a face's normal may turn from its
    chart's mean, 1..89), ``keep_splits`` (every split of the file a chart boundary),
    ``texels_per_unit`` (0: the densest that fits; else exactly this density, the charts that
    do not fit one square of the resolution on further pages), ``max_pages`` (with
    ``texels_per_unit``: the most pages, 0 any number; InvalidInputError beyond) and ``join_charts``
    (join neighbouring charts whose union flattens within ``max_distortion``: fewer charts).
    The same options give the same atlas as the program, bit for bit.
    """
    width, height = _width_and_height(resolution)
    return Atlas(_core.texture_atlas(positions, faces, resolution=width, height=height, padding=padding,
                                     max_distortion=max_distortion,
                                     max_normal_deviation=max_normal_deviation,
                                     keep_splits=keep_splits, threads=threads, backend=backend,
                                     device=device, progress=progress, cancel=cancel,
                                     texels_per_unit=texels_per_unit, join_charts=join_charts,
                                     max_pages=max_pages))
