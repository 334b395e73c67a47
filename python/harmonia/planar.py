"""Flattening a disk with any planar method of the thesis, measuring a layout, comparing layouts."""

import os

from . import _core


def unwrap(positions, faces, *, method="conformal", weights=None, boundary="circle", rounds=None,
           polish=False, stop_after="quasi-harmonic", boundary_t=2.0, solver="auto",
           underdetermined=False, reconstruction="lsq", normalize="surface-area", backend="auto",
           device=None, progress=None, cancel=None):
    """Flatten a disk-shaped mesh -> ``(uv, report)`` (``harmonia unwrap``, the same options).

    uv: (n, 2) float64, one UV per vertex in the input's order. method: "conformal" (fixed
    boundary, chapter 4; ``weights`` any scheme of the Laplacian family, ``boundary`` "circle"
    or "square"), "lscm", "qhm" (chapter 5; ``rounds``), "abf" (chapter 2; ``boundary_t``,
    ``solver``, ``underdetermined``), "linabf" (chapter 3; ``rounds``) or "free" (chapter 6;
    ``polish``, ``stop_after``). ``reconstruction`` ("lsq", "greedy") for abf and linabf;
    ``normalize`` "surface-area", "unit-square" or "none". A mesh that is not a disk raises
    NotADiskError (``harmonia.cut`` opens it). A map with flipped triangles is returned, with
    ``report["status"] == "flipped_triangles"`` and their count.
    """
    return _core.unwrap(positions, faces, method=method, weights=weights, boundary=boundary,
                        rounds=rounds, polish=polish, stop_after=stop_after, boundary_t=boundary_t,
                        solver=solver, underdetermined=underdetermined,
                        reconstruction=reconstruction, normalize=normalize, backend=backend,
                        device=device, progress=progress, cancel=cancel)


def evaluate(positions, faces, uv, uv_faces=None):
    """The distortion figures of a layout (``harmonia eval``) -> dict.

    uv: (k, 2); uv_faces: (m, 3) rows of uv per corner, or None when uv has one row per vertex.
    Keys: flipped_triangles, zero_area_triangles, boundary_self_intersections,
    conformal_distortion_mean/max, area_distortion_mean/max, l2_stretch, angle_error_mean_squared,
    abf_energy, faces, degenerate_input_triangles.
    """
    return _core.evaluate(positions, faces, uv, uv_faces)


def compare(positions, faces, layouts, *, picture=None, title=""):
    """Several layouts of one mesh side by side (``harmonia compare``) -> {label: figures}.

    layouts: {label: uv} (one UV per vertex) or {label: (uv, uv_faces)}, at most 10 for a
    picture. The figures of each are evaluate()'s, and ``face_angle_distortion`` ((m,) float64:
    per triangle the mean relative change of its angles, NaN where undefined). ``picture``
    (.png or .svg): also draw the
    sorted per-triangle angle distortion and log area ratio of every layout, one curve each.
    """
    return _core.compare(positions, faces, dict(layouts), "" if picture is None else os.fspath(picture), title)
