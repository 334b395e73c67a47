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

// A chart with holes is laid out by projection only where that keeps it this close to an
// isometry (L2 stretch - 1): a plane, up to the rounding of its file's coordinates (float32 moves
// a normal by about 1e-7 rad, which stretches by far less). A curved chart is cut open and
// flattened by the methods that spread its curvature best.
constexpr double kProjectionStretch = 1e-6;

// Rounds of the relaxation of linear ABF's layout (relaxed_layout). Its energy falls fastest in the
// first rounds: on the spheres and Suzanne of the wild set three rounds remove all but a tenth of
// the stretch that ten remove; five take a chart that float32 coordinates left 1e-5 off an
// isometry (7_8ths_cube.stl) to within 1e-10 of it.
constexpr int kRelaxationRounds = 5;

// A layout this close to an isometry (L2 stretch - 1) is left as it is: nothing to relax.
constexpr double kIsometricStretch = 1e-9;

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

// Linear ABF's valid layout `uv` relaxed toward an isometry (FreeBoundaryOptions::start_uv with
// fragments in their own frames: the local/global iteration), when that is valid and within the
// limit.
std::optional<FlattenedChart> relaxed_layout(const Mesh& mesh, const Eigen::MatrixX2d& uv, const SolverOptions& solver,
                                             double max_stretch) {
  FreeBoundaryOptions options;
  options.solver = solver;
  // One small system per chart, factorized once for its rounds: on the CPU also when a device
  // solves linear ABF's first rounds in batches (a solve per chart there would cost a dispatch
  // and a float iteration each round).
  options.solver.backend = BackendChoice::cpu;
  options.start_uv = uv;
  options.rotation = FragmentRotation::start_map_frame;
  options.stop_after = FreeBoundaryStop::conformal;
  options.conformal_rounds = kRelaxationRounds;
  const FreeBoundaryResult result = free_boundary_map(mesh, options);
  if (!result.report.ok()) return std::nullopt;
  return judged_layout(mesh, result.uv, ChartMethod::relaxed_linear_abf, max_stretch);
}

// The better of a judged linear ABF layout (`verdict` of `uv`) and its relaxation: the relaxed
// layout where the first is valid but stretches and the relaxation stretches less, also where it
// brings a layout above the limit within it (a chart fewer to split).
std::optional<FlattenedChart> relaxed_if_better(const Mesh& mesh, const Verdict& verdict, const Eigen::MatrixX2d& uv,
                                                const SolverOptions& solver, double max_stretch) {
  if (!verdict.valid || (verdict.chart && verdict.chart->l2_stretch <= 1.0 + kIsometricStretch)) return verdict.chart;
  std::optional<FlattenedChart> relaxed = relaxed_layout(mesh, uv, solver, max_stretch);
  if (relaxed && (!verdict.chart || relaxed->l2_stretch < verdict.chart->l2_stretch)) return relaxed;
  return verdict.chart;
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
      if (std::optional<FlattenedChart> best = relaxed_if_better(mesh, verdict, result.uv, solver, max_stretch))
        return {std::move(best), std::nullopt};
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
                                  ChartMethod method, double max_stretch, const SolverOptions* relax_with) {
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
  if (relax_with) verdict.chart = relaxed_if_better(piece.mesh, verdict, piece_uv, *relax_with, max_stretch);
  if (verdict.chart) verdict.chart->piece_of_a_cut = true;
  if (verdict.chart || verdict.valid) return {verdict.chart, std::nullopt};
  if (!piece_uv.allFinite()) return {};
  const FlipCount flips = count_flips(piece_uv, piece.mesh.faces);
  if (flips.flipped > 0 || flips.zero_area > 0) return {};
  std::optional<std::array<int, 2>> faces = crossing_faces(piece.mesh, piece_uv);
  if (!faces) return {};
  return {std::nullopt, CrossingLayout{std::move(piece_uv), *faces}};
}

std::optional<FlattenedChart> projected_layout(const ChartMesh& chart, double max_stretch) {
  const Mesh& mesh = chart.mesh;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // twice the area-weighted mean normal
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    normal += (Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, 1))) - a)
                  .cross(Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, 2))) - a);
  }
  if (!(normal.norm() > 0.0)) return std::nullopt;
  normal.normalize();
  // u, v and the normal right-handed: a face that faces the plane stays counter-clockwise.
  const Eigen::Vector3d u = normal.unitOrthogonal();
  const Eigen::Vector3d v = normal.cross(u);
  Eigen::MatrixX2d uv(mesh.vertices.rows(), 2);
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
    const Eigen::Vector3d p = mesh.vertices.row(i);
    uv.row(i) << p.dot(u), p.dot(v);
  }
  const FlipCount flips = count_flips(uv, mesh.faces);
  if (flips.flipped > 0 || flips.zero_area > 0) return std::nullopt;
  // Faces that all face the plane can still lie twice over it around a vertex (a ramp winding
  // past a full turn): the angles around each interior vertex must sum to one turn.
  const Eigen::Index vertex_count = uv.rows();
  std::vector<double> angle_sum(static_cast<std::size_t>(vertex_count), 0.0);
  std::vector<int> edge_balance(static_cast<std::size_t>(vertex_count), 0);  // boundary vertices: not 0
  std::unordered_map<long long, int> directed;  // edge (from, to) -> times used
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int at = mesh.faces(f, k), next = mesh.faces(f, (k + 1) % 3), previous = mesh.faces(f, (k + 2) % 3);
      const Eigen::Vector2d to_next = uv.row(next) - uv.row(at), to_previous = uv.row(previous) - uv.row(at);
      angle_sum[static_cast<std::size_t>(at)] +=
          std::atan2(to_next.x() * to_previous.y() - to_next.y() * to_previous.x(), to_next.dot(to_previous));
      ++directed[static_cast<long long>(at) * vertex_count + next];
    }
  for (const auto& [edge, count] : directed)
    if (!directed.contains((edge % vertex_count) * vertex_count + edge / vertex_count)) {
      ++edge_balance[static_cast<std::size_t>(edge / vertex_count)];  // a boundary edge leaves it
      ++edge_balance[static_cast<std::size_t>(edge % vertex_count)];
    }
  for (Eigen::Index i = 0; i < vertex_count; ++i)
    if (edge_balance[static_cast<std::size_t>(i)] == 0 && std::abs(angle_sum[static_cast<std::size_t>(i)] - 2.0 * M_PI) > M_PI)
      return std::nullopt;
  normalize_uv(mesh, mesh.faces, uv, UvNormalization::match_surface_area);
  return judge(mesh, uv, ChartMethod::projection, std::min(max_stretch, 1.0 + kProjectionStretch)).chart;
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
