"""Spherical maps of closed genus-0 meshes (thesis chapter 7) and cutting a mesh open to a disk."""

from dataclasses import dataclass

from . import _core


@dataclass(frozen=True)
class SphereMap:
    """A map of a closed genus-0 mesh onto the unit sphere."""

    positions: object       #: (n, 3) float64, points of the unit sphere in the input's order
    angles: object          #: (n, 2) float64, (longitude in [0, 2 pi), polar angle in [0, pi])
    north_pole: int
    south_pole: int
    date_line: object       #: (k,) int32, the vertices from the north pole to the south pole
    round_area_distortion: list  #: the first map's, then each quasi-harmonic round's
    relaxed_vertices: int   #: vertices moved by the relaxation near the date line
    report: dict            #: status ("ok" or "flipped_triangles"), flipped_triangles, timings, ...


def sphere(positions, faces, *, method="curvilinear", poles=None, weights="cotangent", rounds=3,
           backend="auto", device=None, progress=None, cancel=None):
    """Map a closed genus-0 mesh onto the unit sphere -> :class:`SphereMap` (``harmonia sphere``).

    method: "curvilinear" (the thesis' method) or "relaxation" (the baseline it improves on);
    poles: two vertex indices, or None for the ends of a geodesic diameter; weights: "cotangent"
    or "mean-value"; rounds: quasi-harmonic rounds. Raises NotASphereError for any other
    topology. A map that still turns triangles over is returned with
    ``report["status"] == "flipped_triangles"`` and their count.
    """
    result = _core.sphere(positions, faces, method=method,
                          poles=None if poles is None else tuple(int(p) for p in poles),
                          weights=weights, rounds=rounds, backend=backend, device=device,
                          progress=progress, cancel=cancel)
    return SphereMap(**result)


def cut(positions, faces, *, from_vertex=None, to_vertex=None):
    """Cut a mesh open into a disk along shortest edge paths (``harmonia cut``).

    Returns ``(disk_positions, disk_faces, original_vertex, seam_edges)``: the disk's vertices
    (those on the cut duplicated) and faces (in the input's order), the input vertex each disk
    vertex copies, and how many input edges were cut open. A closed genus-0 mesh is cut along a
    path between two vertices (``from_vertex``, ``to_vertex``, or the ends of a diameter).
    """
    return _core.cut(positions, faces, from_vertex=from_vertex, to_vertex=to_vertex)
