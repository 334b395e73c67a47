#include "detail/map_pipeline.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>

#include "detail/disk_boundary.h"
#include "harmonia/metrics.h"
#include "harmonia/normalize.h"

namespace harmonia::detail {

std::vector<int> validate_disk_input(const Mesh& mesh, SolveReport& report) {
  DiskInput disk = examine_disk(mesh);
  if (disk.status != Status::ok) {
    report.status = disk.status;
    report.message = std::move(disk.message);
    return {};
  }
  return std::move(disk.boundary_loop);
}

bool validate_boundary_options(const Mesh& mesh, const BoundaryOptions& options,
                               SolveReport& report) {
  if (options.shape != BoundaryShape::given) return true;
  const auto fail = [&report](std::string message) {
    report.status = Status::invalid_input;
    report.message = "given boundary: " + std::move(message);
    return false;
  };
  const Eigen::Index count = options.given_vertices.size();
  if (options.given_uv.rows() != count)
    return fail(std::to_string(count) + " vertices but " + std::to_string(options.given_uv.rows()) +
                " uv rows");
  std::set<int> distinct;
  for (Eigen::Index k = 0; k < count; ++k) {
    const int v = options.given_vertices[k];
    if (v < 0 || v >= mesh.vertex_count())
      return fail("vertex index " + std::to_string(v) + " (entry " + std::to_string(k) +
                  ") is out of range [0, " + std::to_string(mesh.vertex_count()) + ")");
    if (!distinct.insert(v).second) return fail("vertex " + std::to_string(v) + " is given twice");
    if (!options.given_uv.row(k).allFinite())
      return fail("the position of vertex " + std::to_string(v) + " is not finite");
  }
  if (distinct.size() < 2) return fail("at least 2 distinct fixed vertices are needed");
  return true;
}

std::unique_ptr<Backend> choose_backend(const SolverOptions& options, SolveReport& report) {
  std::string message;
  std::unique_ptr<Backend> backend = make_backend(options.backend, &message);
  if (!backend) {
    report.status = Status::unsupported;
    report.message = message;
    return nullptr;
  }
  report.backend = backend->kind();
  return backend;
}

bool PhaseClock::start(std::string_view phase, int step, int total) {
  stop();
  if (progress_ && !progress_(Progress{phase, step, total})) {
    report_.status = Status::cancelled;
    report_.message = "cancelled by the progress callback at \"" + std::string(phase) + "\"";
    return false;
  }
  phase_ = phase;
  started_ = std::chrono::steady_clock::now();
  running_ = true;
  return true;
}

void PhaseClock::stop() {
  if (!running_) return;
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - started_;
  report_.timings.push_back(PhaseTiming{phase_, elapsed.count()});
  running_ = false;
}

DirichletSystem::DirichletSystem(int vertex_count, const Eigen::MatrixX3i& faces,
                                 const Eigen::VectorXi& fixed_vertices, Backend& backend,
                                 MatrixKind kind, const SolverOptions& options)
    : backend_(backend), options_(options), fixed_vertices_(fixed_vertices), kind_(kind) {
  free_index_.assign(static_cast<std::size_t>(vertex_count), -1);
  fixed_index_.assign(static_cast<std::size_t>(vertex_count), -1);
  for (Eigen::Index k = 0; k < fixed_vertices.size(); ++k)
    fixed_index_[fixed_vertices[k]] = static_cast<int>(k);
  for (int v = 0; v < vertex_count; ++v) {
    if (fixed_index_[v] >= 0) continue;
    free_index_[v] = static_cast<int>(free_vertices_.size());
    free_vertices_.push_back(v);
  }
  // Pattern of L_II: the diagonal and every mesh edge between two free vertices (explicit zeros
  // are kept, so the pattern never depends on the values).
  std::vector<Eigen::Triplet<double>> pattern;
  for (int i = 0; i < free_count(); ++i) pattern.emplace_back(i, i, 0.0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = free_index_[faces(f, k)], b = free_index_[faces(f, (k + 1) % 3)];
      if (a < 0 || b < 0) continue;
      pattern.emplace_back(a, b, 0.0);
      pattern.emplace_back(b, a, 0.0);
    }
  }
  interior_.resize(free_count(), free_count());
  interior_.setFromTriplets(pattern.begin(), pattern.end(), [](double, double) { return 0.0; });
  interior_.makeCompressed();
  IterativeSettings settings;
  settings.relative_tolerance = options.tolerance;
  settings.max_iterations = options.max_iterations;
  analyze_with(make_system_solver(backend_, kind_, settings, options_.progress));
}

void DirichletSystem::analyze_with(std::unique_ptr<SparseSystemSolver> solver) {
  solver_ = std::move(solver);
  if (free_count() > 0) solver_->analyze(interior_);
  factorized_ = false;
}

bool DirichletSystem::factorize(const Eigen::SparseMatrix<double>& operator_matrix,
                                SolveReport& report) {
  if (operator_matrix.rows() != static_cast<Eigen::Index>(free_index_.size()) ||
      operator_matrix.cols() != operator_matrix.rows())
    throw std::invalid_argument("DirichletSystem: operator has the wrong size");
  // Scatter L into L_II (existing pattern entries only) and L_IB.
  std::fill(interior_.valuePtr(), interior_.valuePtr() + interior_.nonZeros(), 0.0);
  std::vector<Eigen::Triplet<double>> coupling;
  for (int column = 0; column < operator_matrix.outerSize(); ++column) {
    for (Eigen::SparseMatrix<double>::InnerIterator entry(operator_matrix, column); entry;
         ++entry) {
      const int row_free = free_index_[entry.row()];
      if (row_free < 0 || entry.value() == 0.0) continue;
      if (!std::isfinite(entry.value())) {
        report.status = Status::numerical_failure;
        report.message = "the operator has a non-finite entry at (" + std::to_string(entry.row()) +
                         ", " + std::to_string(column) + "): degenerate triangles near vertex " +
                         std::to_string(entry.row()) + "?";
        return false;
      }
      const int column_free = free_index_[column];
      if (column_free < 0) {
        coupling.emplace_back(row_free, fixed_index_[column], entry.value());
        continue;
      }
      // Binary search of the row within the column's stored rows.
      const int* rows = interior_.innerIndexPtr() + interior_.outerIndexPtr()[column_free];
      const int* rows_end = interior_.innerIndexPtr() + interior_.outerIndexPtr()[column_free + 1];
      const int* found = std::lower_bound(rows, rows_end, row_free);
      if (found == rows_end || *found != row_free)
        throw std::logic_error("DirichletSystem: operator entry outside the mesh-edge pattern");
      interior_.valuePtr()[found - interior_.innerIndexPtr()] += entry.value();
    }
  }
  coupling_.resize(free_count(), fixed_vertices_.size());
  coupling_.setFromTriplets(coupling.begin(), coupling.end());
  factorized_ = false;
  if (free_count() == 0) {
    factorized_ = true;
    return true;
  }
  SolveStats stats = solver_->factorize(interior_);
  if (stats.status != Status::ok && kind_ == MatrixKind::symmetric_positive_definite &&
      backend_.supports(Feature::direct_factorization)) {
    // Cotangent-type matrices are SPD for non-degenerate input; if Cholesky disagrees, LU decides.
    kind_ = MatrixKind::general;
    fell_back_to_lu_ = true;
    IterativeSettings settings;
    settings.relative_tolerance = options_.tolerance;
    settings.max_iterations = options_.max_iterations;
    const std::string failed = solver_->name();
    analyze_with(make_system_solver(backend_, kind_, settings, options_.progress));
    report.solver =
        solver_->name() + " (after " + failed + " found the matrix not positive definite)";
    stats = solver_->factorize(interior_);
  } else if (!fell_back_to_lu_) {
    report.solver = solver_->name();
  }
  if (stats.status != Status::ok) {
    report.status = stats.status;
    report.message = stats.message;
    return false;
  }
  factorized_ = true;
  return true;
}

bool DirichletSystem::solve(const Eigen::MatrixX2d& fixed_uv, Eigen::MatrixX2d& uv,
                            SolveReport& report) {
  if (!factorized_) {
    report.status = Status::numerical_failure;
    report.message = "solve without a successful factorization";
    return false;
  }
  const int vertex_count = static_cast<int>(free_index_.size());
  uv.resize(vertex_count, 2);
  for (Eigen::Index k = 0; k < fixed_vertices_.size(); ++k)
    uv.row(fixed_vertices_[k]) = fixed_uv.row(k);
  if (free_count() == 0) return true;

  const Eigen::MatrixXd rhs = -(coupling_ * fixed_uv);
  Eigen::MatrixXd solution = warm_start_.rows() == free_count() ? warm_start_ : Eigen::MatrixXd();
  const SolveStats stats = solver_->solve(rhs, solution);
  report.iterations += stats.iterations;
  if (stats.status != Status::ok) {
    report.status = stats.status;
    report.message = stats.message;
    return false;
  }
  // Residual of every column, measured here independently of the solver.
  const Eigen::MatrixXd residual = interior_ * solution - rhs;
  for (Eigen::Index c = 0; c < rhs.cols(); ++c) {
    const double rhs_norm = rhs.col(c).norm(), residual_norm = residual.col(c).norm();
    const double relative = rhs_norm > 0.0 ? residual_norm / rhs_norm : residual_norm;
    report.residual = std::max(report.residual, std::isfinite(relative) ? relative : INFINITY);
  }
  warm_start_ = solution;
  for (int i = 0; i < free_count(); ++i) uv.row(free_vertices_[i]) = solution.row(i);
  return true;
}

void finish_map(const Mesh& mesh, UvNormalization normalization, Eigen::MatrixX2d& uv,
                SolveReport& report, PhaseClock& clock) {
  if (!uv.allFinite()) {
    report.status = Status::numerical_failure;
    report.message = "the computed map has non-finite coordinates (degenerate input triangles?)";
    uv.resize(0, 2);
    return;
  }
  if (!clock.start("normalize")) {
    uv.resize(0, 2);
    return;
  }
  normalize_uv(mesh, mesh.faces, uv, normalization);
  if (!clock.start("validity")) {
    uv.resize(0, 2);
    return;
  }
  const FlipCount flips = count_flips(uv, mesh.faces);
  report.flipped_triangles = flips.flipped;
  report.degenerate_triangles = flips.zero_area;
  report.boundary_self_intersections = count_boundary_self_intersections(uv, mesh.faces);
  clock.stop();
  if (report.status == Status::ok && flips.flipped + flips.zero_area > 0) {
    report.status = Status::flipped_triangles;
    report.message = std::to_string(flips.flipped) + " flipped and " +
                     std::to_string(flips.zero_area) + " zero-area triangles in the map";
  }
}

}  // namespace harmonia::detail
