#pragma once
// Internal: one chart of a texture atlas flattened without a fold (harmonia/texture_atlas.h).
//
// The methods in the order tried, the first valid result within the stretch limit kept:
//   linear ABF (angles first: the least angle distortion), the free-boundary quasi-harmonic map
//   (chapter 6), and a Tutte embedding with mean-value weights on a circle (positive weights on a
//   convex boundary: no fold, by Tutte's and Floater's theorems, at the price of stretch). Valid
//   means no flipped or zero-area triangle and a boundary that does not cross itself. A valid
//   linear ABF map above the stretch limit ends the search (the others, made for validity,
//   stretch more): the chart is split. A single triangle is laid out exactly.
//
// A valid linear ABF layout that is not an isometry is relaxed toward one (the free-boundary step
// 6.2 repeated from it with the fragments in their own triangles' frames, the local/global
// iteration of Liu et al. 2008): conformal layouts vary in scale over a curved chart, which the
// L2 stretch measures. The relaxed layout is kept where it stretches less, also where that brings
// a layout above the limit within it.
//
// A linear ABF layout whose only fault is a boundary that crosses itself (a tongue of the chart
// laid over another part of it) ends the search too: the chart is to be cut between the two
// boundary edges that cross, each piece keeping its part of the layout (texture_atlas.cpp).
// Linear ABF's own remedy, rounds with boundary control (2.6) that re-solve the whole chart, is
// not used here: it bends the boundary to convex angle sums at the price of stretch, and on the
// charts of cow and bunny x16 (40 charts whose first layout crossed its boundary) it never came
// out within the atlas' limit, then 1.006 (L2 1.0061 to 69,000), at about the cost of the first
// layout again.

#include <array>
#include <optional>

#include <Eigen/Core>

#include "atlas/chart_mesh.h"
#include "harmonia/abf.h"
#include "harmonia/linear_abf.h"
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
  bool piece_of_a_cut = false;    // its part of a larger chart's layout (restricted_layout)
};

// A chart that is done: its faces (increasing), its copy of their vertices, and their layout.
struct FinishedChart {
  ChartMesh mesh;
  FlattenedChart layout;
};

// Linear ABF's layout of a chart whose boundary crosses itself, valid otherwise (no flipped or
// zero-area triangle), and one pair of its boundary edges that cross, by their faces (chart face
// indices, distinct).
struct CrossingLayout {
  Eigen::MatrixX2d uv;
  std::array<int, 2> faces{};
};

// A chart's layout, or nothing (the chart is to be split), with the layout that crosses its
// boundary where that is why.
struct ChartFlattening {
  std::optional<FlattenedChart> chart;
  std::optional<CrossingLayout> crossing;
};

// The first method's valid map with L2 stretch at most `max_stretch`, or nothing: the chart is to
// be split (around `crossing`'s faces where given). `chart` must be a disk (is_disk).
[[nodiscard]] ChartFlattening flatten_chart(const ChartMesh& chart, double max_stretch,
                                            const SolverOptions& solver);

// The same with the chart's linear ABF result computed elsewhere (linear_abf(chart.mesh) with
// `solver`, or the batched first round of abf/linear_abf_batch.h): judged as flatten_chart judges
// its own, then the free-boundary map and Tutte where it is not a valid map. A single triangle is
// laid out exactly, whatever the result.
[[nodiscard]] ChartFlattening flatten_chart(const ChartMesh& chart, double max_stretch,
                                            const SolverOptions& solver,
                                            const AngleMapResult& linear_abf_result);

// The linear ABF options of the flattening (no boundary control; the solver's backend).
[[nodiscard]] LinearAbfOptions chart_linear_abf_options(const SolverOptions& solver);

// `uv` (one row per vertex of `mesh`, at the mesh's 3D area) as a flattened chart, when it is a
// valid map with L2 stretch at most `max_stretch`.
[[nodiscard]] std::optional<FlattenedChart> judged_layout(const Mesh& mesh, Eigen::MatrixX2d uv,
                                                          ChartMethod method, double max_stretch);

// The part of `chart`'s layout `uv` (one row per chart vertex) on the faces of `piece` (a disk made
// of some of the chart's faces), scaled to the piece's own 3D area and turned to its principal
// axis: the piece's layout when it is a valid map with L2 stretch at most `max_stretch`
// (`method`: the chart's), or the part itself as a crossing layout when its only fault is a
// boundary that crosses itself (to be cut again), or nothing. With `relax_with`, a part that
// stretches is relaxed as flatten_chart relaxes linear ABF's layouts, with that solver.
[[nodiscard]] ChartFlattening restricted_layout(const ChartMesh& chart, const Eigen::MatrixX2d& uv,
                                                const ChartMesh& piece, ChartMethod method, double max_stretch,
                                                const SolverOptions* relax_with = nullptr);

// A planar chart that is not a disk (a plate with holes, a wall with windows): its orthogonal
// projection onto the plane of its mean normal, scaled to its 3D area, when that is a valid map
// within 1e-6 of an isometry (L2 stretch) and the stretch limit: every face facing the plane,
// every interior vertex turned around once, and every boundary (the holes' too) clear of the
// others. Cutting the holes open to make a disk would lay the cuts' two sides on top of each other
// and the chart would be split. Nothing otherwise (a curved chart with holes is cut open).
[[nodiscard]] std::optional<FlattenedChart> projected_layout(const ChartMesh& chart, double max_stretch);

// A face of zero area drawn as a right isosceles triangle, counter-clockwise, with legs as long as
// its longest edge (or 1 when its corners coincide), so that it keeps a place in the atlas. Its
// distortion figures stay at their neutral values: without 3D area there is nothing to measure.
[[nodiscard]] FlattenedChart degenerate_face_layout(const Mesh& surface, int face);

}  // namespace harmonia::detail
