#include "atlas/chart_flattening.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include "harmonia/fixed_boundary_map.h"
#include "harmonia/free_boundary_map.h"
#include "harmonia/linear_abf.h"
#include "harmonia/metrics.h"
#include "harmonia/normalize.h"
#include "planar/boundary_crossings.h"

namespace harmonia::detail {
namespace {

// A chart's boundary must keep this far from itself, relative to the chart's extent: the two sides
// of a slit (a flat ring cut open, as on CAD parts) come out of the solve on top of each other,
// apart or crossing by rounding alone, and the chart's placement in the atlas (a scale and a
// shift, rounded) can make them cross. Such a chart is cut there like a crossing one. 2^-24 is far
// above that rounding (about 2^-40 of the extent) and far below any gap a texel can show.
constexpr double kBoundaryClearance = 0x1p-24;

// The one face of `mesh` laid out exactly: corner 0 at the origin, corner 1 on the u axis, corner
// 2 above it (counter-clockwise).
Eigen::MatrixX2d single_triangle_layout(const Mesh& mesh) {
  const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(0, 0));
  const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(0, 1));
  const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(0, 2));
  const Eigen::Vector3d along = b - a;
  const double length = along.norm();
  const Eigen::Vector3d axis = along / length;
  const double u = (c - a).dot(axis);
  const double v = ((c - a) - u * axis).norm();
  Eigen::MatrixX2d uv(mesh.vertices.rows(), 2);
  uv.row(mesh.faces(0, 0)) << 0.0, 0.0;
  uv.row(mesh.faces(0, 1)) << length, 0.0;
  uv.row(mesh.faces(0, 2)) << u, v;
  return uv;
}

// Whether a map is valid (no fold, no crossing boundary), and its figures when it also keeps
// within the stretch limit.
struct Verdict {
  bool valid = false;
  std::optional<FlattenedChart> chart;
};

Verdict judge(const Mesh& mesh, const Eigen::MatrixX2d& uv, ChartMethod method, double max_stretch) {
  Verdict verdict;
  if (uv.rows() != mesh.vertices.rows() || !uv.allFinite()) return verdict;
  const FlipCount flips = count_flips(uv, mesh.faces);
  if (flips.flipped > 0 || flips.zero_area > 0) return verdict;
  if (first_boundary_contact(uv, mesh.faces, kBoundaryClearance)) return verdict;
  verdict.valid = true;
  const DistortionMetrics metrics = evaluate_map(mesh, uv, mesh.faces);
  if (!(metrics.l2_stretch <= max_stretch)) return verdict;
  FlattenedChart chart;
  chart.uv = uv;
  chart.method = method;
  chart.l2_stretch = metrics.l2_stretch;
  chart.angle_distortion = metrics.conformal_distortion_mean;
  chart.area_distortion = metrics.area_distortion_mean;
  verdict.chart = std::move(chart);
  return verdict;
}

// The two chart faces of the first pair of boundary edges of `uv` that cross, if any.
std::optional<std::array<int, 2>> crossing_faces(const Mesh& mesh, const Eigen::MatrixX2d& uv) {
  const std::optional<BoundaryCrossing> crossing = first_boundary_contact(uv, mesh.faces, kBoundaryClearance);
  if (!crossing) return std::nullopt;
  // The face of a boundary edge: the one face with both of its ends, in this order.
  const auto face_of = [&mesh](const std::array<int, 2>& edge) {
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        if (mesh.faces(f, k) == edge[0] && mesh.faces(f, (k + 1) % 3) == edge[1]) return static_cast<int>(f);
    return -1;
  };
  // uv_boundary_edges keeps each edge as (smaller, larger): either direction may be the face's.
  const auto either_way = [&](const std::array<int, 2>& edge) {
    const int forward = face_of(edge);
    return forward >= 0 ? forward : face_of({edge[1], edge[0]});
  };
  const int first = either_way(crossing->first), second = either_way(crossing->second);
  if (first < 0 || second < 0 || first == second) return std::nullopt;
  return std::array<int, 2>{first, second};
}

// The chain from linear ABF's result on; `given`: that result computed elsewhere, else computed
// here.
ChartFlattening flatten(const ChartMesh& chart, double max_stretch, const SolverOptions& solver,
                        const AngleMapResult* given) {
  const Mesh& mesh = chart.mesh;
  if (mesh.faces.rows() == 1) {
    Eigen::MatrixX2d uv = single_triangle_layout(mesh);
    return {judged_layout(mesh, std::move(uv), ChartMethod::single_triangle, std::max(max_stretch, 1.0 + 1e-9)),
            std::nullopt};
  }
  {
    AngleMapResult computed;
    if (given == nullptr) computed = linear_abf(mesh, chart_linear_abf_options(solver));
    const AngleMapResult& result = given != nullptr ? *given : computed;
    if (result.report.ok()) {
      const Verdict verdict = judge(mesh, result.uv, ChartMethod::linear_abf, max_stretch);
      if (verdict.chart) return {verdict.chart, std::nullopt};
      // A valid map that stretches too much: the others, made for validity, stretch more; split.
      if (verdict.valid) return {};
      // Valid but for a boundary that crosses itself: cut between the crossing edges.
      if (result.uv.rows() == mesh.vertices.rows() && result.uv.allFinite()) {
        const FlipCount flips = count_flips(result.uv, mesh.faces);
        if (flips.flipped == 0 && flips.zero_area == 0)
          if (const std::optional<std::array<int, 2>> faces = crossing_faces(mesh, result.uv))
            return {std::nullopt, CrossingLayout{result.uv, *faces}};
      }
    }
  }
  {
    FreeBoundaryOptions options;
    options.solver = solver;
    const FreeBoundaryResult result = free_boundary_map(mesh, options);
    if (result.report.ok())
      if (auto flattened = judged_layout(mesh, result.uv, ChartMethod::free_boundary, max_stretch))
        return {std::move(flattened), std::nullopt};
  }
  {
    FixedBoundaryOptions options;
    options.weights = WeightScheme::mean_value;
    options.solver = solver;
    MapResult result = fixed_boundary_map(mesh, options);
    if (result.report.ok())
      if (auto flattened = judged_layout(mesh, result.uv, ChartMethod::tutte, max_stretch))
        return {std::move(flattened), std::nullopt};
  }
  return {};
}

}  // namespace

LinearAbfOptions chart_linear_abf_options(const SolverOptions& solver) {
  LinearAbfOptions options;
  options.solver_options = solver;
  options.avoid_boundary_crossings = false;  // a crossing chart is cut instead (see the header)
  return options;
}

std::optional<FlattenedChart> judged_layout(const Mesh& mesh, Eigen::MatrixX2d uv, ChartMethod method,
                                            double max_stretch) {
  return judge(mesh, uv, method, max_stretch).chart;
}

ChartFlattening flatten_chart(const ChartMesh& chart, double max_stretch, const SolverOptions& solver) {
  return flatten(chart, max_stretch, solver, nullptr);
}

ChartFlattening flatten_chart(const ChartMesh& chart, double max_stretch, const SolverOptions& solver,
                              const AngleMapResult& linear_abf_result) {
  return flatten(chart, max_stretch, solver, &linear_abf_result);
}

ChartFlattening restricted_layout(const ChartMesh& chart, const Eigen::MatrixX2d& uv, const ChartMesh& piece,
                                  ChartMethod method, double max_stretch) {
  std::unordered_map<int, int> chart_face_of;  // surface face -> chart face
  for (std::size_t f = 0; f < chart.surface_face.size(); ++f)
    chart_face_of.emplace(chart.surface_face[f], static_cast<int>(f));
  Eigen::MatrixX2d piece_uv(piece.mesh.vertices.rows(), 2);
  std::vector<bool> placed(static_cast<std::size_t>(piece_uv.rows()), false);
  for (Eigen::Index f = 0; f < piece.mesh.faces.rows(); ++f) {
    const auto found = chart_face_of.find(piece.surface_face[static_cast<std::size_t>(f)]);
    if (found == chart_face_of.end()) return {};
    for (int k = 0; k < 3; ++k) {
      // Both meshes keep the surface face's corner order.
      const Eigen::RowVector2d corner = uv.row(chart.mesh.faces(found->second, k));
      const int vertex = piece.mesh.faces(f, k);
      if (placed[static_cast<std::size_t>(vertex)] && piece_uv.row(vertex) != corner) return {};
      piece_uv.row(vertex) = corner;
      placed[static_cast<std::size_t>(vertex)] = true;
    }
  }
  normalize_uv(piece.mesh, piece.mesh.faces, piece_uv, UvNormalization::match_surface_area);
  Verdict verdict = judge(piece.mesh, piece_uv, method, max_stretch);
  if (verdict.chart) verdict.chart->piece_of_a_cut = true;
  if (verdict.chart || verdict.valid) return {verdict.chart, std::nullopt};
  if (!piece_uv.allFinite()) return {};
  const FlipCount flips = count_flips(piece_uv, piece.mesh.faces);
  if (flips.flipped > 0 || flips.zero_area > 0) return {};
  std::optional<std::array<int, 2>> faces = crossing_faces(piece.mesh, piece_uv);
  if (!faces) return {};
  return {std::nullopt, CrossingLayout{std::move(piece_uv), *faces}};
}

FlattenedChart degenerate_face_layout(const Mesh& surface, int face) {
  double longest = 0.0;
  for (int k = 0; k < 3; ++k)
    longest = std::max(longest, (surface.vertices.row(surface.faces(face, (k + 1) % 3)) -
                                 surface.vertices.row(surface.faces(face, k))).norm());
  if (!(longest > 0.0) || !std::isfinite(longest)) longest = 1.0;
  FlattenedChart chart;
  chart.method = ChartMethod::degenerate;
  chart.uv.resize(3, 2);
  chart.uv << 0.0, 0.0, longest, 0.0, 0.0, longest;
  return chart;
}

}  // namespace harmonia::detail
