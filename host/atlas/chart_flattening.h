#pragma once
// Internal: one chart of a texture atlas flattened without a fold (harmonia/texture_atlas.h).
//
// The methods in the order tried, the first valid result within the stretch limit kept:
//   linear ABF (angles first: the least angle distortion, and its own rounds against a boundary
//   that crosses itself), the free-boundary quasi-harmonic map (chapter 6), and a Tutte embedding
//   with mean-value weights on a circle (positive weights on a convex boundary: no fold, by
//   Tutte's and Floater's theorems, at the price of stretch). Valid means no flipped or zero-area
//   triangle and a boundary that does not cross itself. A valid linear ABF map above the stretch
//   limit ends the search (the others, made for validity, stretch more): the chart is split. A
//   single triangle is laid out exactly.

#include <optional>

#include <Eigen/Core>

#include "atlas/chart_mesh.h"
#include "harmonia/abf.h"
#include "harmonia/solver_options.h"
#include "harmonia/texture_atlas.h"

namespace harmonia::detail {

struct FlattenedChart {
  // Per chart vertex; faces counter-clockwise; scaled so that the chart's UV area equals its 3D
  // area (what the packer expects).
  Eigen::MatrixX2d uv;
  ChartMethod method = ChartMethod::single_triangle;
  double l2_stretch = 1.0;        // Sander L2, the chart at its own area
  double angle_distortion = 1.0;  // 3D-area-weighted mean sigma1 / sigma2
  double area_distortion = 0.0;   // 3D-area-weighted mean |log(uv area / 3D area)|
};

// Nothing when no method gives a valid map with L2 stretch at most `max_stretch`: the chart is to
// be split. `chart` must be a disk (is_disk).
[[nodiscard]] std::optional<FlattenedChart> flatten_chart(const ChartMesh& chart, double max_stretch,
                                                          const SolverOptions& solver);

// The same with the chart's linear ABF result computed elsewhere (linear_abf(chart.mesh) with
// `solver`, or the batched first round of abf/linear_abf_batch.h): judged as flatten_chart judges
// its own, then the free-boundary map and Tutte where it is not a valid map. A single triangle is
// laid out exactly, whatever the result.
[[nodiscard]] std::optional<FlattenedChart> flatten_chart(const ChartMesh& chart, double max_stretch,
                                                          const SolverOptions& solver,
                                                          const AngleMapResult& linear_abf_result);

// A face of zero area drawn as a right isosceles triangle, counter-clockwise, with legs as long as
// its longest edge (or 1 when its corners coincide), so that it keeps a place in the atlas. Its
// distortion figures stay at their neutral values: without 3D area there is nothing to measure.
[[nodiscard]] FlattenedChart degenerate_face_layout(const Mesh& surface, int face);

}  // namespace harmonia::detail
