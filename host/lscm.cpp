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

#include "detail/lscm_energy.h"
#include "detail/boundary_pins.h"
#include "detail/map_pipeline.h"
#include "detail/uv_block_ordering.h"
#include "harmonia/laplacian.h"

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
  std::vector<int> analyzed_outer, analyzed_inner;  // The pattern the solver analyzed.
  std::vector<int> vertex_ordering;  // Fill-reducing (AMD) ordering of the vertices.

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
    vertex_ordering = detail::operator_pattern(mesh).vertex_ordering;
    clock.stop();
    assemble_and_factorize(true);
  }

  bool choose_pins() {
    const int vertex_count = mesh.vertex_count();
    const auto [far_a, far_b] = detail::farthest_boundary_pair(mesh, loop);
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

  // Q_FF (free rows and columns, in unknown order: the u block, then the v block) and Q_FP (free
  // rows; pinned columns u_a, u_b, v_a, v_b). The free index increases with the unknown, so the
  // rows of every column stay sorted.
  void split_free_and_pinned(const Eigen::SparseMatrix<double>& normal) {
    const int vertex_count = mesh.vertex_count();
    const int pinned_column[4] = {pin_first, pin_second, vertex_count + pin_first,
                                  vertex_count + pin_second};
    std::vector<int> free_outer{0}, free_inner, pinned_outer{0}, pinned_inner;
    std::vector<double> free_values, pinned_values_list;
    const auto take_column = [&](int column, std::vector<int>& rows, std::vector<double>& values,
                                 std::vector<int>& starts) {
      for (Eigen::SparseMatrix<double>::InnerIterator entry(normal, column); entry; ++entry) {
        const int row = free_index[entry.row()];
        if (row < 0) continue;
        rows.push_back(row);
        values.push_back(entry.value());
      }
      starts.push_back(static_cast<int>(rows.size()));
    };
    free_inner.reserve(static_cast<std::size_t>(normal.nonZeros()));
    free_values.reserve(static_cast<std::size_t>(normal.nonZeros()));
    for (int column = 0; column < normal.outerSize(); ++column)
      if (free_index[column] >= 0) take_column(column, free_inner, free_values, free_outer);
    for (const int column : pinned_column)
      take_column(column, pinned_inner, pinned_values_list, pinned_outer);
    const auto assign = [](Eigen::SparseMatrix<double>& matrix, Eigen::Index rows,
                           const std::vector<int>& starts, const std::vector<int>& row_indices,
                           const std::vector<double>& values) {
      matrix.resize(rows, static_cast<Eigen::Index>(starts.size()) - 1);
      matrix.resizeNonZeros(static_cast<Eigen::Index>(row_indices.size()));
      std::copy(starts.begin(), starts.end(), matrix.outerIndexPtr());
      std::copy(row_indices.begin(), row_indices.end(), matrix.innerIndexPtr());
      std::copy(values.begin(), values.end(), matrix.valuePtr());
    };
    const int free_count = 2 * vertex_count - 4;
    assign(normal_free, free_count, free_outer, free_inner, free_values);
    assign(normal_pinned, free_count, pinned_outer, pinned_inner, pinned_values_list);
  }

  void assemble_and_factorize(bool first_time) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("assembly")) return;
    const Eigen::SparseMatrix<double> normal = detail::lscm_quadratic_form(mesh, loop);
    split_free_and_pinned(normal);
    if (!clock.start("factorization")) return;
    // The pattern depends on the faces and, through the coupling around zero-area triangles, on
    // which triangles are degenerate: analyzed again only when it changes.
    const bool same_pattern =
        !first_time && analyzed_outer == std::vector<int>(normal_free.outerIndexPtr(),
                                                          normal_free.outerIndexPtr() +
                                                              normal_free.outerSize() + 1) &&
        analyzed_inner == std::vector<int>(normal_free.innerIndexPtr(),
                                           normal_free.innerIndexPtr() + normal_free.nonZeros());
    if (!same_pattern) {
      // u and v meet only through the boundary terms of the area (and around zero-area
      // triangles): ordered block by block along one vertex ordering, those v last, the factor
      // is about two Laplacian factors plus a dense boundary block, without the seconds
      // CHOLMOD's own analysis of the 2V-unknown graph takes (face x16: analysis and
      // factorization 3.0 s before, 2.8 s this way).
      const std::vector<int> ordering =
          detail::uv_block_ordering(vertex_ordering, free_index, normal_free);
      if (ordering.empty())
        solver->analyze(normal_free);
      else
        solver->analyze_with_ordering(normal_free, ordering);
      analyzed_outer.assign(normal_free.outerIndexPtr(),
                            normal_free.outerIndexPtr() + normal_free.outerSize() + 1);
      analyzed_inner.assign(normal_free.innerIndexPtr(),
                            normal_free.innerIndexPtr() + normal_free.nonZeros());
    }
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
    report.cross_check_error = backend->cross_check_error();
    detail::finish_map(mesh, loop, options.normalization, result.uv, report, clock);
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
