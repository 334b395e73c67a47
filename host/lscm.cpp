// Least-squares conformal maps (Levy et al. 2002) / discrete natural conformal maps (Desbrun et
// al. 2002; thesis section 6.2.2). Each triangle, written in its own orthonormal frame, should be
// mapped holomorphically: the Cauchy-Riemann residual grad u + rot90(grad v) vanishes. The energy
// sum_T area_T |grad u + rot90(grad v)|^2 is quadratic in (u, v); with two vertices pinned its
// normal equations are symmetric positive definite in the 2(V-2) free unknowns.

#include "harmonia/lscm.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "detail/map_pipeline.h"

namespace harmonia {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// Rows 2t and 2t+1 of the residual matrix M (2F by 2V; columns u_0..u_{V-1}, v_0..v_{V-1}), scaled
// by sqrt(area) so that |M x|^2 is the conformal energy. In the triangle's frame the gradient of
// the hat function of corner k is rot90(e_k) / (2A), e_k the edge opposite k, counter-clockwise.
void add_triangle_rows(const Mesh& mesh, int face, Triplets& entries) {
  const int vertex_count = mesh.vertex_count();
  const Eigen::Vector3d p0 = mesh.vertices.row(mesh.faces(face, 0));
  const Eigen::Vector3d p1 = mesh.vertices.row(mesh.faces(face, 1));
  const Eigen::Vector3d p2 = mesh.vertices.row(mesh.faces(face, 2));
  const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0);
  const double double_area = normal.norm();
  // A degenerate triangle carries no conformal energy; its entries stay (as zeros) so that the
  // sparsity pattern, analyzed once, never depends on the geometry.
  if (!(double_area > 0.0) || !std::isfinite(double_area)) {
    for (int k = 0; k < 3; ++k) {
      for (int row = 0; row < 2; ++row) {
        entries.emplace_back(2 * face + row, mesh.faces(face, k), 0.0);
        entries.emplace_back(2 * face + row, vertex_count + mesh.faces(face, k), 0.0);
      }
    }
    return;
  }
  const Eigen::Vector3d x_axis = (p1 - p0).normalized();
  const Eigen::Vector3d y_axis = normal.normalized().cross(x_axis);
  const Eigen::Vector2d local[3] = {Eigen::Vector2d::Zero(),
                                    Eigen::Vector2d((p1 - p0).dot(x_axis), 0.0),
                                    Eigen::Vector2d((p2 - p0).dot(x_axis), (p2 - p0).dot(y_axis))};
  const double scale = 1.0 / (2.0 * std::sqrt(0.5 * double_area));  // sqrt(A) / (2A)
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d edge = local[(k + 2) % 3] - local[(k + 1) % 3];
    const int vertex = mesh.faces(face, k);
    // sqrt(A) grad(phi_k) = scale * (-edge.y, edge.x); rot90 of it = scale * (-edge.x, -edge.y).
    entries.emplace_back(2 * face, vertex, -scale * edge.y());
    entries.emplace_back(2 * face + 1, vertex, scale * edge.x());
    entries.emplace_back(2 * face, vertex_count + vertex, -scale * edge.x());
    entries.emplace_back(2 * face + 1, vertex_count + vertex, -scale * edge.y());
  }
}

// The two boundary vertices farthest apart in 3D; ties go to the lexicographically first pair.
std::pair<int, int> farthest_boundary_pair(const Mesh& mesh, const std::vector<int>& loop) {
  std::pair<int, int> best{loop[0], loop[loop.size() > 1 ? 1 : 0]};
  double best_distance = -1.0;
  for (std::size_t a = 0; a < loop.size(); ++a) {
    for (std::size_t b = a + 1; b < loop.size(); ++b) {
      const double distance =
          (mesh.vertices.row(loop[a]) - mesh.vertices.row(loop[b])).squaredNorm();
      if (distance > best_distance) {
        best_distance = distance;
        best = {loop[a], loop[b]};
      }
    }
  }
  return best;
}

}  // namespace

struct LscmSolver::Impl {
  Mesh mesh;
  LscmOptions options;
  SolveReport setup;
  std::vector<int> loop;
  int pin_first = -1, pin_second = -1;
  std::vector<int> free_index;  // 2V unknowns -> index among the free ones, or -1 for pinned.
  std::unique_ptr<detail::Backend> backend;
  std::unique_ptr<detail::SparseSystemSolver> solver;
  Eigen::SparseMatrix<double> normal_free;    // Q_FF
  Eigen::SparseMatrix<double> normal_pinned;  // Q_FP, pinned columns (u_a, u_b, v_a, v_b)
  Eigen::Vector4d pinned_values = Eigen::Vector4d::Zero();

  Impl(const Mesh& input, const LscmOptions& lscm_options) : mesh(input), options(lscm_options) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("validation")) return;
    loop = detail::validate_disk_input(mesh, setup);
    if (!setup.ok() || !choose_pins()) return;
    backend = detail::choose_backend(options.solver, setup);
    if (!backend) return;
    if (!clock.start("analysis")) return;
    const int vertex_count = mesh.vertex_count();
    free_index.assign(2 * static_cast<std::size_t>(vertex_count), -1);
    int next = 0;
    for (int unknown = 0; unknown < 2 * vertex_count; ++unknown) {
      const int vertex = unknown % vertex_count;
      if (vertex != pin_first && vertex != pin_second) free_index[unknown] = next++;
    }
    detail::IterativeSettings settings;
    settings.relative_tolerance = options.solver.tolerance;
    settings.max_iterations = options.solver.max_iterations;
    solver = detail::make_system_solver(*backend, detail::MatrixKind::symmetric_positive_definite,
                                        settings, options.solver.progress);
    clock.stop();
    assemble_and_factorize(true);
  }

  bool choose_pins() {
    const int vertex_count = mesh.vertex_count();
    const auto [far_a, far_b] = farthest_boundary_pair(mesh, loop);
    pin_first = options.pin_first.value_or(far_a);
    pin_second = options.pin_second.value_or(far_b);
    // One pin given: the other is the end of the farthest pair that differs from it.
    if (options.pin_first && !options.pin_second) pin_second = far_a != pin_first ? far_a : far_b;
    if (!options.pin_first && options.pin_second) pin_first = far_a != pin_second ? far_a : far_b;
    for (const int pin : {pin_first, pin_second}) {
      if (pin < 0 || pin >= vertex_count) {
        setup.status = Status::invalid_input;
        setup.message = "lscm: pinned vertex " + std::to_string(pin) + " is out of range [0, " +
                        std::to_string(vertex_count) + ")";
        return false;
      }
    }
    if (pin_first == pin_second) {
      setup.status = Status::invalid_input;
      setup.message =
          "lscm: the two pinned vertices must differ (both are " + std::to_string(pin_first) + ")";
      return false;
    }
    // Pins at (0,0) and (d,0), d their 3D distance, so the raw output has the surface's scale.
    const double distance = (mesh.vertices.row(pin_first) - mesh.vertices.row(pin_second)).norm();
    pinned_values << 0.0, distance, 0.0, 0.0;
    return true;
  }

  void assemble_and_factorize(bool first_time) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("assembly")) return;
    const int vertex_count = mesh.vertex_count();
    Triplets entries;
    entries.reserve(12 * static_cast<std::size_t>(mesh.face_count()));
    for (int f = 0; f < mesh.face_count(); ++f) add_triangle_rows(mesh, f, entries);
    Eigen::SparseMatrix<double> residual_matrix(2 * mesh.face_count(), 2 * vertex_count);
    residual_matrix.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SparseMatrix<double> normal = residual_matrix.transpose() * residual_matrix;
    // Split the normal matrix into free-free and free-pinned blocks.
    const int pinned_column[4] = {pin_first, pin_second, vertex_count + pin_first,
                                  vertex_count + pin_second};
    Triplets free_entries, pinned_entries;
    for (int column = 0; column < normal.outerSize(); ++column) {
      for (Eigen::SparseMatrix<double>::InnerIterator entry(normal, column); entry; ++entry) {
        const int row = free_index[entry.row()];
        if (row < 0) continue;
        if (free_index[column] >= 0) {
          free_entries.emplace_back(row, free_index[column], entry.value());
        } else {
          const int pinned =
              static_cast<int>(std::find(pinned_column, pinned_column + 4, column) - pinned_column);
          pinned_entries.emplace_back(row, pinned, entry.value());
        }
      }
    }
    const int free_count = 2 * vertex_count - 4;
    normal_free.resize(free_count, free_count);
    normal_free.setFromTriplets(free_entries.begin(), free_entries.end());
    normal_pinned.resize(free_count, 4);
    normal_pinned.setFromTriplets(pinned_entries.begin(), pinned_entries.end());
    if (!clock.start("factorization")) return;
    // The pattern only depends on the faces (M^T M of the same face set), so analyze once.
    if (first_time) solver->analyze(normal_free);
    const detail::SolveStats stats = solver->factorize(normal_free);
    setup.solver = solver->name();
    if (stats.status != Status::ok) {
      setup.status = stats.status;
      setup.message = "lscm: " + stats.message;
    }
  }

  MapResult solve() {
    MapResult result;
    result.report = setup;
    SolveReport& report = result.report;
    if (!report.ok()) return result;
    detail::PhaseClock clock(report, options.solver.progress);
    if (!clock.start("solve")) return result;
    const Eigen::VectorXd rhs = -(normal_pinned * pinned_values);
    Eigen::MatrixXd solution;
    const detail::SolveStats stats = solver->solve(rhs, solution);
    report.iterations += stats.iterations;
    if (stats.status != Status::ok) {
      report.status = stats.status;
      report.message = "lscm: " + stats.message;
      return result;
    }
    const double rhs_norm = rhs.norm();
    const double residual = (normal_free * solution - rhs).norm();
    report.residual = std::max(report.residual, rhs_norm > 0.0 ? residual / rhs_norm : residual);
    const int vertex_count = mesh.vertex_count();
    result.uv.resize(vertex_count, 2);
    for (int unknown = 0; unknown < 2 * vertex_count; ++unknown) {
      const int vertex = unknown % vertex_count, coordinate = unknown / vertex_count;
      result.uv(vertex, coordinate) =
          free_index[unknown] >= 0 ? solution(free_index[unknown], 0) : 0.0;
    }
    result.uv.row(pin_first) << pinned_values[0], pinned_values[2];
    result.uv.row(pin_second) << pinned_values[1], pinned_values[3];
    detail::finish_map(mesh, options.normalization, result.uv, report, clock);
    return result;
  }
};

LscmSolver::LscmSolver(const Mesh& mesh, const LscmOptions& options)
    : impl_(std::make_unique<Impl>(mesh, options)) {}
LscmSolver::~LscmSolver() = default;
LscmSolver::LscmSolver(LscmSolver&&) noexcept = default;
LscmSolver& LscmSolver::operator=(LscmSolver&&) noexcept = default;

const SolveReport& LscmSolver::setup_report() const { return impl_->setup; }

void LscmSolver::update_geometry(const Eigen::MatrixX3d& vertices) {
  Impl& impl = *impl_;
  if (!impl.solver) return;
  impl.setup.status = Status::ok;
  impl.setup.message.clear();
  impl.setup.timings.clear();
  if (vertices.rows() != impl.mesh.vertex_count() || !vertices.allFinite()) {
    impl.setup.status = Status::invalid_input;
    impl.setup.message = "update_geometry: expected " + std::to_string(impl.mesh.vertex_count()) +
                         " finite vertex rows, got " + std::to_string(vertices.rows());
    return;
  }
  impl.mesh.vertices = vertices;
  const double distance = (vertices.row(impl.pin_first) - vertices.row(impl.pin_second)).norm();
  impl.pinned_values[1] = distance;
  impl.assemble_and_factorize(false);
}

MapResult LscmSolver::solve() { return impl_->solve(); }

MapResult lscm(const Mesh& mesh, const LscmOptions& options) {
  LscmSolver solver(mesh, options);
  return solver.solve();
}

}  // namespace harmonia
