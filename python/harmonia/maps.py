"""Spherical maps of closed genus-0 meshes (thesis chapter 7); cleaning a mesh up and cutting it
open to a disk (what ``harmonia unwrap --cleanup repair --cut`` does before it maps)."""

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


@dataclass(frozen=True)
class Cleanup:
    """A mesh cleaned up, with the maps between its elements and the input's."""

    positions: object        #: (n', 3) float64
    faces: object            #: (m', 3) int32
    vertex_map: object       #: (n,) int32: each input vertex's index here, or -1 if removed
    original_vertex: object  #: (n',) int32: the input vertex each vertex came from
    original_face: object    #: (m',) int32: the input face each face came from
    merged_vertices: int
    removed_unreferenced_vertices: int
    removed_degenerate_faces: int
    removed_duplicate_faces: int
    flipped_faces: int       #: faces reversed to make the orientation consistent
    changes: list            #: one line per kind of change


def cleanup(positions, faces, *, mode="repair", merge_tolerance=0.0, keep_non_manifold=False):
    """Check or repair a mesh (``harmonia unwrap --cleanup``) -> :class:`Cleanup`.

    mode "strict": change nothing, raise NonManifoldError or InvalidInputError naming the first
    problem; "repair": merge duplicate vertices (within ``merge_tolerance`` of the bounding-box
    diagonal), drop unreferenced vertices and degenerate or duplicate faces, make the orientation
    consistent, and list each kind of change. ``keep_non_manifold`` keeps what repair cannot fix
    (non-manifold edges and vertices) instead of raising.
    """
    return Cleanup(**_core.cleanup(positions, faces, mode=mode, merge_tolerance=merge_tolerance,
                                   keep_non_manifold=keep_non_manifold))
