"""Reusable solvers: the connectivity analysed once, then new positions and solves as often as
needed (one topology in many shapes: the frames of an animation, a scan refined in place)."""

from . import _core


class DiskMapper:
    """The fixed-boundary map of a disk (chapter 4), reusable.

    ``DiskMapper(positions, faces, *, weights="cotangent", boundary="circle", backend="auto",
    device=None)``: analyses the topology, places the boundary and factorizes.
    ``update_geometry(positions)`` takes new positions of the same connectivity (re-assembles and
    re-factorizes); ``solve(boundary_uv=None)`` -> ``(uv, report)``, with new positions for the
    boundary vertices (``boundary`` gives them and their placement) by back-substitution alone.
    """

    def __init__(self, positions, faces, *, weights="cotangent", boundary="circle", backend="auto",
                 device=None):
        self._core = _core.DiskMapper(positions, faces, weights=weights, boundary=boundary,
                                      backend=backend, device=device)

    @property
    def boundary(self):
        """``(vertices, uv)``: the fixed boundary vertices (int32) and their positions (float64)."""
        return self._core.boundary

    def update_geometry(self, positions):
        """New vertex positions, (n, 3), of the same connectivity."""
        self._core.update_geometry(positions)

    def solve(self, boundary_uv=None):
        """The map -> ``(uv, report)``; ``boundary_uv`` (b, 2) moves the boundary vertices."""
        return self._core.solve(boundary_uv)


class SphereMapper:
    """The spherical map of a closed genus-0 mesh (chapter 7), reusable: the poles, the date line
    and the system's pattern chosen once; ``update_geometry(positions)`` and ``solve()`` ->
    ``(sphere_positions, report)`` as often as needed."""

    def __init__(self, positions, faces, *, backend="auto", device=None):
        self._core = _core.SphereMapper(positions, faces, backend=backend, device=device)

    def update_geometry(self, positions):
        """New vertex positions, (n, 3), of the same connectivity."""
        self._core.update_geometry(positions)

    def solve(self):
        """The map -> ``(positions on the unit sphere (n, 3), report)``."""
        return self._core.solve()
