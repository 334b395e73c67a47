#pragma once
// Internal: the segmentation of a surface into charts for a texture atlas (harmonia/texture_atlas.h).
//
// A chart is a set of faces connected across edges whose normals stay within a cone around the
// chart's mean normal (max_normal_deviation): such a region is close to a height field over the
// plane of that normal and flattens with little stretch, and the boundaries between charts fall
// where the surface bends, along creases.
//
//   Growing (first pass): from the flattest face not yet taken (the one whose neighbours' normals
//   differ least from its own), a chart takes, cheapest first, the faces across its border whose
//   normal lies within the cone around its current mean normal; then the next chart starts.
//   Relaxation (Lloyd rounds, as in variational shape approximation with normal proxies, and
//   D-Charts): every chart keeps its mean normal as its proxy and a new seed, the face that best
//   combines its proxy's normal with nearness to the chart's centre; all charts then grow again
//   together from their seeds, a face going to the chart that reaches it cheapest, at the cost
//   (1 - n . N) + compactness (d / R)^2 with d the path length from the seed over the face
//   centroids and R the radius of a disk of the chart's area. A face no chart may take within
//   its cone starts a new chart by the growing pass. The rounds make the charts compact and move
//   their seams onto the creases.
//   Elimination: the rounds keep as many charts as the growing pass made, which on a smooth
//   surface is more than the cone needs. Smallest first, a chart whose faces its neighbours can
//   take among themselves, each face within the cone of its taker's mean normal as that normal
//   moves, with every face of every grown neighbour still within its new cone, disappears; a
//   Lloyd round follows, and the elimination is tried again (three rounds at most).
//
// Everything is measured relative to the surface (normals, ratios of lengths and areas): the same
// charts at any scale. Ties are broken by FaceGeometry::rank: the same charts for any face order.

#include <vector>

#include "atlas/face_geometry.h"
#include "harmonia/types.h"

namespace harmonia::detail {

struct SegmentationOptions {
  double max_normal_deviation = 1.0471975511965976;  // radians (60 degrees)
  double compactness = 0.25;   // weight of (d / R)^2 against the normal term
  int relaxation_rounds = 3;
  // After the rounds, charts whose faces their neighbours can take within their cones disappear
  // (each elimination round followed by a Lloyd round).
  bool eliminate_charts = true;
  // Optional: asked between the passes (stage "segmentation", step and total the passes); false
  // stops the segmentation, which then returns Segmentation::cancelled.
  ProgressCallback progress;
};

struct Segmentation {
  std::vector<int> chart_of_face;  // -1 for the degenerate faces, which belong to no chart
  int chart_count = 0;
  // The face each chart grew from last (a face of that chart): it ranks the chart in the
  // tie-breaks, so that the charts do not depend on the face order.
  std::vector<int> seed_of_chart;
  bool cancelled = false;  // the progress callback stopped it (the rest is then empty)
};

[[nodiscard]] Segmentation segment_into_charts(const FaceGeometry& geometry,
                                               const SegmentationOptions& options);

// The cone within which a chart joins a neighbour after growing (small charts absorbed here,
// folds joined in flat_fold_merge.h): wider than the growing cone by half, at most 89 degrees (a
// joined chart must still be a height field over its normal's plane).
[[nodiscard]] double joining_cone(const SegmentationOptions& options);

}  // namespace harmonia::detail
