#pragma once
// Internal: joining neighbouring flattened charts of a texture atlas whose union flattens within
// the atlas' stretch limit.
//
// The segmentation bounds each chart by a cone of normals (chart_segmentation.h), which on a
// smooth closed surface cuts more charts than stretch asks for: a sphere's caps of 60 degrees
// flatten far below the limit, and so does the union of two of them. Every chart boundary is a
// seam in the texture and padding in the atlas, so after the flattening two neighbouring charts
// are joined when the union, flattened afresh by the same methods (chart_flattening.h), is a
// valid map within the limit. A join is tried only where it can be worth a seam and is likely to
// hold, with the tests of the joins across flat folds (flat_fold_merge.h): a common border of one
// path, at least kLeastBorderShare of the shorter perimeter; the union about as compact as its
// parts; its normals within the joining cone. Pairs go longest common border first, in rounds
// until none joins; ties by the charts' lowest face rank, so the charts do not depend on the face
// order.

#include <vector>

#include "atlas/chart_flattening.h"
#include "atlas/face_geometry.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia::detail {

//! Joins charts of `charts` (finished charts of `surface`, whose faces `geometry` describes) as
//! above; `cone` is the joining cone (chart_segmentation.h), `max_stretch` the atlas' limit. Each
//! round's tries take no chart twice, so they are flattened side by side on `threads` threads;
//! the charts are the same for any count. The charts come back sorted by their first face.
//! solver.progress (if any) is asked before each round (stage "joining", step the round) and may
//! cancel: false is then returned, with `charts` as the rounds before left them.
[[nodiscard]] bool join_within_stretch(const Mesh& surface, const FaceGeometry& geometry, double cone,
                                       double max_stretch, const SolverOptions& solver, int threads,
                                       std::vector<FinishedChart>& charts);

}  // namespace harmonia::detail
