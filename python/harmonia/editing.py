"""Surface editing along harmonic fields and deformation transfer (thesis chapter 8): set up once,
then frames or poses."""

from . import _core


class SurfaceEditor:
    """A surface editor: the mesh, its fixed vertices and its handles, factorized once.

    ``SurfaceEditor(positions, faces, fixed, handles, region_of_interest=None, *,
    rotation_clusters=None, refine=0, frame_budget_ms=0, check_orientation=True, backend="auto",
    device=None)``: ``fixed`` a list of vertex indices that stay, ``handles`` a list of lists of
    vertex indices, each moved rigidly by its handle's transformation, ``region_of_interest`` the
    vertices the edit may move (None: all). ``rotation_clusters``: where the handles' rotations
    act (None: 8 per handle and 8 more; 0: the thesis' blend alone). ``refine`` ARAP steps per
    frame, or as many as fit
    ``frame_budget_ms``. Raises InvalidInputError for a part of the region without a constrained
    vertex, and the like.

    Each frame reuses the factorization (``factorization_count`` stays 1) and copies nothing but
    its result. One editor runs one frame at a time (calls from several threads take turns); an
    editor per thread runs in parallel.
    """

    def __init__(self, positions, faces, fixed, handles, region_of_interest=None, *,
                 rotation_clusters=None, refine=0, frame_budget_ms=0.0, check_orientation=True,
                 backend="auto", device=None):
        self._core = _core.SurfaceEditor(positions, faces, fixed, list(handles), region_of_interest,
                                         rotation_clusters=rotation_clusters, refinement_steps=refine,
                                         frame_budget_seconds=frame_budget_ms / 1000.0,
                                         check_orientation=check_orientation, backend=backend,
                                         device=device)
        #: The report of the last frame (status, flipped_triangles, refinement_steps, frame_seconds, ...).
        self.last_report = None

    @property
    def setup_report(self):
        """Status, solver, backend and timings of the set-up."""
        return self._core.setup_report

    @property
    def handle_fields(self):
        """(n, handles) float64: each handle's harmonic field (1 on it, 0 on the fixed vertices)."""
        return self._core.handle_fields

    @property
    def factorization_count(self):
        """Numeric factorizations made so far: 1 after the set-up, and after any number of frames."""
        return self._core.factorization_count

    def deform(self, rotations=None, centers=None, scales=None, translations=None):
        """One frame -> (n, 3) float64 positions; constrained vertices exactly at their targets.

        Per handle, in the order of ``handles``: ``rotations`` (h, 4) unit quaternions (w, x, y, z),
        ``centers`` (h, 3) the fixed points of rotation and scale, ``scales`` (h,), ``translations``
        (h, 3), applied last. None: the identity's part.
        """
        positions, self.last_report = self._core.deform(rotations, centers, scales, translations)
        return positions

    def drag(self, translations):
        """One frame with each handle translated rigidly by its row of ``translations`` (h, 3)."""
        positions, self.last_report = self._core.drag(translations)
        return positions


class DeformationTransfer:
    """Makes a target mesh perform a source mesh's poses (``harmonia transfer``).

    ``DeformationTransfer(source_positions, source_faces, target_positions, target_faces,
    markers, *, method="correspondence", components=8, max_match_distance=0.25,
    smoothing_passes=2, fold_repair_rounds=3, backend="auto", device=None)``: ``markers`` an
    (k, 2) array of (source vertex, target vertex) pairs, at least 3. ``method``
    "correspondence" (8.4: triangles matched through the markers' harmonic fields) or
    "quaternion" (8.5). Built once (one factorization); ``transfer(source_pose)`` is one pose.
    """

    def __init__(self, source_positions, source_faces, target_positions, target_faces, markers, *,
                 method="correspondence", components=8, max_match_distance=0.25, smoothing_passes=2,
                 fold_repair_rounds=3, backend="auto", device=None):
        self._core = _core.DeformationTransfer(
            source_positions, source_faces, target_positions, target_faces, markers, method=method,
            components=components, max_match_distance=max_match_distance,
            smoothing_passes=smoothing_passes, fold_repair_rounds=fold_repair_rounds,
            backend=backend, device=device)
        #: The report of the last pose (folded_triangles, turned_over_triangles, timings, ...).
        self.last_report = None

    @property
    def setup_report(self):
        """Status, solver and timings of the set-up."""
        return self._core.setup_report

    @property
    def matched_triangles(self):
        """Target triangles matched to a source triangle (correspondence)."""
        return self._core.matched_triangles

    @property
    def unmatched_triangles(self):
        """Target triangles left without a match."""
        return self._core.unmatched_triangles

    def transfer(self, source_pose):
        """The target in the source's pose -> (n_target, 3) float64 positions.

        source_pose: (n_source, 3), the source's vertices in the pose, in its rest order.
        """
        positions, self.last_report = self._core.transfer(source_pose)
        return positions
