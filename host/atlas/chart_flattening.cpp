#include "atlas/chart_flattening.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "harmonia/fixed_boundary_map.h"
#include "harmonia/free_boundary_map.h"
#include "harmonia/linear_abf.h"
#include "harmonia/metrics.h"

namespace harmonia::detail {
namespace {

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
  if (count_boundary_self_intersections(uv, mesh.faces) > 0) return verdict;
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

// The figures of a valid map within the limit, or nothing.
std::optional<FlattenedChart> judged(const Mesh& mesh, const Eigen::MatrixX2d& uv, ChartMethod method,
                                     double max_stretch) {
  return judge(mesh, uv, method, max_stretch).chart;
}

// The chain from linear ABF's result on; `given`: that result computed elsewhere, else computed
// here.
std::optional<FlattenedChart> flatten(const ChartMesh& chart, double max_stretch,
                                      const SolverOptions& solver, const AngleMapResult* given) {
  const Mesh& mesh = chart.mesh;
  if (mesh.faces.rows() == 1) {
    Eigen::MatrixX2d uv = single_triangle_layout(mesh);
    return judged(mesh, uv, ChartMethod::single_triangle, std::max(max_stretch, 1.0 + 1e-9));
  }
  {
    AngleMapResult computed;
    if (given == nullptr) {
      LinearAbfOptions options;
      options.solver_options = solver;
      computed = linear_abf(mesh, options);
    }
    const AngleMapResult& result = given != nullptr ? *given : computed;
    if (result.report.ok()) {
      const Verdict verdict = judge(mesh, result.uv, ChartMethod::linear_abf, max_stretch);
      if (verdict.chart) return verdict.chart;
      // A valid map that stretches too much: the others, made for validity, stretch more; split.
      if (verdict.valid) return std::nullopt;
    }
  }
  {
    FreeBoundaryOptions options;
    options.solver = solver;
    const FreeBoundaryResult result = free_boundary_map(mesh, options);
    if (result.report.ok())
      if (auto flattened = judged(mesh, result.uv, ChartMethod::free_boundary, max_stretch)) return flattened;
  }
  {
    FixedBoundaryOptions options;
    options.weights = WeightScheme::mean_value;
    options.solver = solver;
    MapResult result = fixed_boundary_map(mesh, options);
    if (result.report.ok())
      if (auto flattened = judged(mesh, result.uv, ChartMethod::tutte, max_stretch)) return flattened;
  }
  return std::nullopt;
}

}  // namespace

std::optional<FlattenedChart> flatten_chart(const ChartMesh& chart, double max_stretch,
                                            const SolverOptions& solver) {
  return flatten(chart, max_stretch, solver, nullptr);
}

std::optional<FlattenedChart> flatten_chart(const ChartMesh& chart, double max_stretch,
                                            const SolverOptions& solver,
                                            const AngleMapResult& linear_abf_result) {
  return flatten(chart, max_stretch, solver, &linear_abf_result);
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
