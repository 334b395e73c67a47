// Least-squares conformal maps (Levy et al. 2002) / discrete natural conformal maps (Desbrun et
// al. 2002; thesis section 6.2.2). Each triangle, written in its own orthonormal frame, should be
// mapped holomorphically: the Cauchy-Riemann residual grad u + rot90(grad v) vanishes. The energy
// sum_T area_T |grad u + rot90(grad v)|^2 is quadratic in (u, v); with two vertices pinned its
// normal equations are symmetric positive definite in the 2(V-2) free unknowns.
//
// The energy is assembled without forming the residual rows: per triangle, area |grad u|^2 +
// area |grad v|^2 is the cotangent Dirichlet energy, and the cross term
// 2 area grad u . rot90(grad v) is minus twice the triangle's signed uv area. Summed over the
// mesh the signed areas telescope onto the boundary (Desbrun, Meyer and Alliez 2002: the
// "discrete natural conformal" identity), so the matrix is two cotangent Laplacians plus a
// coupling between boundary neighbours: as sparse as a fixed-boundary map's, once per coordinate.

#include "harmonia/lscm.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "harmonia/laplacian.h"
#include "mesh/power_of_two_scale.h"
#include "planar/boundary_pins.h"
#include "planar/lscm_energy.h"
#include "planar/map_pipeline.h"
#include "solve/uv_system_solver.h"

namespace harmonia {
namespace {

// True for a triangle with zero (or non-finite) 3D area: it carries no conformal energy.
bool zero_area(const Mesh& mesh, int face) {
  const Eigen::Vector3d p0 = mesh.vertices.row(mesh.faces(face, 0));
  const Eigen::Vector3d p1 = mesh.vertices.row(mesh.faces(face, 1));
  const Eigen::Vector3d p2 = mesh.vertices.row(mesh.faces(face, 2));
  const double double_area = (p1 - p0).cross(p2 - p0).norm();
  return !(double_area > 0.0) || !std::isfinite(double_area);
}

}  // namespace

namespace detail {

Eigen::SparseMatrix<double> lscm_quadratic_form(const Mesh& mesh, const std::vector<int>& loop) {
  // A zero-area triangle gets zero cotangent weights, as the energy asks.
  const Eigen::SparseMatrix<double> dirichlet = laplacian(mesh, WeightScheme::cotangent);
  const int vertex_count = mesh.vertex_count();

  // N: per triangle with corners a -> b -> c (counter-clockwise), area grad u_a . rot90(grad v_b)
  // is -1/2 for b following a, +1/2 for b preceding a. Along an interior edge the two triangles
  // cancel exactly, leaving the boundary edges and the edges beside zero-area triangles: the sum
  // over all triangles (the boundary loop, mesh to its left) minus that of the zero-area ones.
  std::vector<std::vector<std::pair<int, double>>> coupling(static_cast<std::size_t>(vertex_count));
  const auto add_directed_edge = [&coupling](int from, int to, double sign) {
    coupling[static_cast<std::size_t>(to)].emplace_back(from, -0.5 * sign);   // N(from, to)
    coupling[static_cast<std::size_t>(from)].emplace_back(to, 0.5 * sign);    // N(to, from)
  };
  for (std::size_t k = 0; k < loop.size(); ++k)
    add_directed_edge(loop[k], loop[(k + 1) % loop.size()], 1.0);
  for (int f = 0; f < mesh.face_count(); ++f) {
    if (!zero_area(mesh, f)) continue;
    for (int k = 0; k < 3; ++k)
      add_directed_edge(mesh.faces(f, k), mesh.faces(f, (k + 1) % 3), -1.0);
  }
  // Column c of N as sorted (row, value) with repeated rows summed (sums of halves: exact) and
  // exact zeros dropped.
  for (auto& column : coupling) {
    std::sort(column.begin(), column.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    std::size_t kept = 0;
    for (std::size_t i = 0; i < column.size();) {
      double sum = 0.0;
      const int row = column[i].first;
      for (; i < column.size() && column[i].first == row; ++i) sum += column[i].second;
      if (sum != 0.0) column[kept++] = {row, sum};
    }
    column.resize(kept);
  }

  // Q = [L N; N^T L] with N^T = -N (N is antisymmetric), column by column.
  const Eigen::Index size = 2 * static_cast<Eigen::Index>(vertex_count);
  std::vector<int> outer{0}, inner;
  std::vector<double> values;
  const std::size_t estimate = 2 * static_cast<std::size_t>(dirichlet.nonZeros()) + 8 * loop.size();
  inner.reserve(estimate);
  values.reserve(estimate);
  const auto append_dirichlet = [&](int column, int row_offset) {
    for (Eigen::SparseMatrix<double>::InnerIterator entry(dirichlet, column); entry; ++entry) {
      inner.push_back(row_offset + static_cast<int>(entry.row()));
      values.push_back(entry.value());
    }
  };
  const auto append_coupling = [&](int column, int row_offset, double sign) {
    for (const auto& [row, value] : coupling[static_cast<std::size_t>(column)]) {
      inner.push_back(row_offset + row);
      values.push_back(sign * value);
    }
  };
  for (int c = 0; c < vertex_count; ++c) {  // Column u_c: L(:, c) over N^T(:, c) = -N(:, c).
    append_dirichlet(c, 0);
    append_coupling(c, vertex_count, -1.0);
    outer.push_back(static_cast<int>(inner.size()));
  }
  for (int c = 0; c < vertex_count; ++c) {  // Column v_c: N(:, c) over L(:, c).
    append_coupling(c, 0, 1.0);
    append_dirichlet(c, vertex_count);
    outer.push_back(static_cast<int>(inner.size()));
  }
  Eigen::SparseMatrix<double> form(size, size);
  form.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), form.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), form.innerIndexPtr());
  std::copy(values.begin(), values.end(), form.valuePtr());
  return form;
}

}  // namespace detail

struct LscmSolver::Impl {
  Mesh mesh;           // The input scaled to unit size (mesh/power_of_two_scale.h) ...
  double scale = 1.0;  // ... by this power of two.
  LscmOptions options;
  SolveReport setup;
  std::vector<int> loop;
  detail::LayoutPins pins;  // At (0, 0) and (d, 0), d their 3D distance: the surface's scale.
  std::unique_ptr<detail::Backend> backend;
  std::unique_ptr<detail::UvSystemSolver> solver;

  Impl(const Mesh& input, const LscmOptions& lscm_options)
      : Impl(detail::unit_scaled(input), lscm_options) {}

  Impl(detail::ScaledMesh unit, const LscmOptions& lscm_options)
      : mesh(std::move(unit.mesh)), scale(unit.scale), options(lscm_options) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("validation")) return;
    loop = detail::validate_disk_input(mesh, setup);
    if (!setup.ok() || !choose_pins()) return;
    backend = detail::choose_backend(options.solver, setup);
    if (!backend) return;
    solver = std::make_unique<detail::UvSystemSolver>(*backend, detail::iterative_settings(options.solver),
                                                      options.solver.progress);
    if (options.solver.backend == BackendChoice::automatic) solver->allow_cpu_retry();
    clock.stop();
    assemble_and_factorize();
  }

  bool choose_pins() {
    const int vertex_count = mesh.vertex_count();
    const auto [far_a, far_b] = detail::farthest_boundary_pair(mesh, loop);
    pins.first = options.pin_first.value_or(far_a);
    pins.second = options.pin_second.value_or(far_b);
    // One pin given: the other is the end of the farthest pair that differs from it.
    if (options.pin_first && !options.pin_second) pins.second = far_a != pins.first ? far_a : far_b;
    if (!options.pin_first && options.pin_second) pins.first = far_a != pins.second ? far_a : far_b;
    for (const int pin : {pins.first, pins.second}) {
      if (pin < 0 || pin >= vertex_count) {
        setup.status = Status::invalid_input;
        setup.message = "lscm: pinned vertex " + std::to_string(pin) + " is out of range [0, " +
                        std::to_string(vertex_count) + ")";
        return false;
      }
    }
    if (pins.first == pins.second) {
      setup.status = Status::invalid_input;
      setup.message =
          "lscm: the two pinned vertices must differ (both are " + std::to_string(pins.first) + ")";
      return false;
    }
    pins.distance = (mesh.vertices.row(pins.first) - mesh.vertices.row(pins.second)).norm();
    return true;
  }

  void assemble_and_factorize() {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("assembly")) return;
    Eigen::SparseMatrix<double> form = detail::lscm_quadratic_form(mesh, loop);
    if (!clock.start("analysis")) return;
    // The pattern depends on the faces and, through the coupling around zero-area triangles, on
    // which triangles are degenerate: the solver analyzes it again only when it changes.
    solver->analyze(form, pins, {});
    if (!clock.start("factorization")) return;
    const detail::SolveStats stats = solver->factorize(std::move(form));
    setup.solver = solver->name();
    if (std::string notice = solver->take_cpu_retry_notice(); !notice.empty()) setup.fallbacks.push_back(notice);
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
    const detail::SolveStats stats = solver->solve(result.uv);
    report.iterations += stats.iterations;
    if (std::string notice = solver->take_cpu_retry_notice(); !notice.empty()) {
      // The solver stays on the CPU: later solves report it too.
      setup.fallbacks.push_back(notice);
      setup.solver = solver->name();
      report.fallbacks.push_back(notice);
      report.solver = setup.solver;
    }
    if (stats.status != Status::ok) {
      report.status = stats.status;
      report.message = "lscm: " + stats.message;
      return result;
    }
    report.residual = std::max(report.residual, stats.relative_residual);
    report.cross_check_error = backend->cross_check_error();
    detail::finish_map(mesh, loop, options.normalization, result.uv, report, clock);
    detail::to_model_units(result.uv, scale, options.normalization, true);
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
  if (!detail::accept_new_geometry(impl.mesh, vertices, impl.setup)) return;
  impl.mesh.vertices = vertices * impl.scale;
  impl.pins.distance =
      (impl.mesh.vertices.row(impl.pins.first) - impl.mesh.vertices.row(impl.pins.second)).norm();
  impl.assemble_and_factorize();
}

MapResult LscmSolver::solve() { return impl_->solve(); }

MapResult lscm(const Mesh& mesh, const LscmOptions& options) {
  LscmSolver solver(mesh, options);
  return solver.solve();
}

}  // namespace harmonia
