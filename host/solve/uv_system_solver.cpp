// The pinned [u; v] conformal system (uv_system_solver.h), by coupled blocks or by one Laplacian
// factor.
//
// One Laplacian factor. Number the free vertices with the coupled ones (B: those that N couples
// to another free vertex) last, and factor L_FF = P^T R R^T P in that order, so that
//     R = [ R_II  0    ]     R_BB R_BB^T = L_BB - L_BI L_II^-1 L_IB = S,
//         [ R_BI  R_BB ],
// S being the Schur complement of the uncoupled vertices I. As N vanishes outside B x B,
// eliminating u_I and v_I (the same L_II for both) leaves on B
//     [ S      N_BB ] [u_B]   [R_BB y_B^u]
//     [ N_BB^T S    ] [v_B] = [R_BB y_B^v],    y = R^-1 P [f g] (forward solve),
// a dense SPD system of 2|B| unknowns. Given u_B and v_B, the backward solve with y_B replaced by
// R_BB^T u_B (and R_BB^T v_B) returns u and v everywhere: its last block reproduces u_B, and its
// first gives u_I = L_II^-1 (f_I - L_IB u_B). The cost is one factorization of L_FF (with B last)
// plus (2|B|)^3 / 3 for the dense system, against two such factorizations for the coupled blocks
// ordered u, then v (uv_block_ordering.h). Chosen when the dense system is cheap next to the one
// factorization it saves; a mesh whose boundary is a large fraction of its vertices keeps the
// coupled blocks.

#include "solve/uv_system_solver.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include <Eigen/Cholesky>

#include "fallback/bordered_cholesky.h"
#include "fallback/direct_solvers.h"
#include "solve/backend_selection.h"
#include "solve/uv_block_ordering.h"

namespace harmonia::detail {
namespace {

// The one-factor way is taken when its dense border system costs less than this fraction of the
// Laplacian factorization it saves (flop counts; the dense factorization runs at a higher rate,
// so this is conservative).
constexpr double kBorderCostFraction = 0.5;
// Borders larger than this many times the square root of the free vertex count are not tried.
constexpr double kLargestBorderPerRootVertex = 4.0;

// A submatrix of `form` (compressed, column-major) that keeps, for each of its stored entries, the
// position of the entry in form's values: the values are refreshed by a gather per factorization.
struct GatheredMatrix {
  Eigen::SparseMatrix<double> matrix;
  std::vector<int> source;

  void gather(const Eigen::SparseMatrix<double>& form) {
    const double* values = form.valuePtr();
    double* target = matrix.valuePtr();
    for (std::size_t k = 0; k < source.size(); ++k) target[k] = values[source[k]];
  }
};

// The entries (row, column) of `form` with row_map[row] >= 0, column_map[column] >= 0 and
// row_map[row] >= column_map[column] (lower triangle) when `lower_only`, renumbered through the
// maps, which must increase with the index so that rows stay sorted.
GatheredMatrix gather_submatrix(const Eigen::SparseMatrix<double>& form,
                                const std::vector<int>& row_map, const std::vector<int>& column_map,
                                int size, bool lower_only) {
  GatheredMatrix result;
  std::vector<int> outer{0}, inner;
  inner.reserve(static_cast<std::size_t>(form.nonZeros()));
  result.source.reserve(inner.capacity());
  const int* form_outer = form.outerIndexPtr();
  const int* form_inner = form.innerIndexPtr();
  for (int column = 0; column < static_cast<int>(column_map.size()); ++column) {
    const int target_column = column_map[static_cast<std::size_t>(column)];
    if (target_column < 0) continue;
    for (int k = form_outer[column]; k < form_outer[column + 1]; ++k) {
      const int row = row_map[static_cast<std::size_t>(form_inner[k])];
      if (row < 0 || (lower_only && row < target_column)) continue;
      inner.push_back(row);
      result.source.push_back(k);
    }
    outer.push_back(static_cast<int>(inner.size()));
  }
  result.matrix.resize(size, size);
  result.matrix.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), result.matrix.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), result.matrix.innerIndexPtr());
  result.gather(form);
  return result;
}

}  // namespace

struct UvSystemSolver::Impl {
  Backend* backend;  // The caller's, or the CPU's after a failed device solve (cpu_backend).
  IterativeSettings settings;
  ProgressCallback progress;
  UvSystemStrategy strategy;
  bool cpu_retry_allowed = false;
  std::unique_ptr<Backend> cpu_backend;
  std::string failed_device_solver;  // The device's solver, once the system moved to the CPU.
  std::string cpu_retry_notice_text;
  std::vector<int> analyzed_vertex_ordering;

  // What was analyzed.
  std::vector<int> pattern_outer, pattern_inner;
  LayoutPins pins;
  int vertex_count = 0;
  int free_count = 0;                // Free vertices.
  std::vector<int> free_vertex;      // Vertex -> index among the free vertices, or -1.
  Eigen::SparseMatrix<double> form;  // The factorized Q (for the right-hand side and residual).
  bool direct = false;               // A direct factorization (CPU), not an iterative solver.
  bool one_factor = false;

  // Coupled blocks: Q_FF over the free unknowns (u then v) and its solver.
  std::vector<int> free_unknown;  // 2V unknowns -> free unknown, or -1.
  GatheredMatrix coupled;
  std::unique_ptr<SparseSystemSolver> coupled_solver;

  // One Laplacian factor: L_FF (lower), the border B (free vertices, elimination order) and the
  // dense border system.
  GatheredMatrix laplacian;
  std::vector<int> border;               // Free vertex of each border position.
  std::vector<int> border_position;      // Free vertex -> border position, or -1.
  std::vector<std::pair<int, int>> coupling_entries;  // (border u position, border v position).
  std::vector<int> coupling_source;      // Their positions in form's values.
  std::unique_ptr<BorderedCholesky> laplacian_factor;
  Eigen::MatrixXd border_factor;         // R_BB.
  Eigen::LLT<Eigen::MatrixXd> border_system;
  bool factorized = false;

  Impl(Backend& backend_in, const IterativeSettings& settings_in,
       const ProgressCallback& progress_in, UvSystemStrategy strategy_in)
      : backend(&backend_in), settings(settings_in), progress(progress_in), strategy(strategy_in) {}

  bool same_problem(const Eigen::SparseMatrix<double>& q, const LayoutPins& p) const {
    return p.first == pins.first && p.second == pins.second &&
           static_cast<std::size_t>(q.outerSize()) + 1 == pattern_outer.size() &&
           std::equal(pattern_outer.begin(), pattern_outer.end(), q.outerIndexPtr()) &&
           static_cast<std::size_t>(q.nonZeros()) == pattern_inner.size() &&
           std::equal(pattern_inner.begin(), pattern_inner.end(), q.innerIndexPtr());
  }

  void analyze(const Eigen::SparseMatrix<double>& q, const LayoutPins& p,
               const std::vector<int>& vertex_ordering) {
    const bool same = !pattern_outer.empty() && same_problem(q, p);
    pins = p;  // The distance may change without a new analysis.
    if (same) return;
    analyzed_vertex_ordering = vertex_ordering;
    pattern_outer.assign(q.outerIndexPtr(), q.outerIndexPtr() + q.outerSize() + 1);
    pattern_inner.assign(q.innerIndexPtr(), q.innerIndexPtr() + q.nonZeros());
    vertex_count = static_cast<int>(q.rows() / 2);
    free_vertex.assign(static_cast<std::size_t>(vertex_count), -1);
    free_count = 0;
    for (int v = 0; v < vertex_count; ++v)
      if (v != pins.first && v != pins.second) free_vertex[static_cast<std::size_t>(v)] = free_count++;
    factorized = false;
    direct = backend->supports(Feature::direct_factorization);
    std::vector<int> ordering = vertex_ordering;
    if (direct && ordering.size() != static_cast<std::size_t>(vertex_count))
      ordering = vertex_graph_ordering(q);
    one_factor = direct && strategy != UvSystemStrategy::coupled_blocks &&
                 analyze_one_factor(q, ordering);
    if (!one_factor) analyze_coupled_blocks(q, direct ? ordering : std::vector<int>{});
  }

  // AMD on L's pattern (the vertex graph), for callers without an ordering of their own.
  std::vector<int> vertex_graph_ordering(const Eigen::SparseMatrix<double>& q) const {
    std::vector<int> u_block(static_cast<std::size_t>(q.rows()), -1);
    std::iota(u_block.begin(), u_block.begin() + vertex_count, 0);
    return fill_reducing_ordering(gather_submatrix(q, u_block, u_block, vertex_count, true).matrix);
  }

  bool analyze_one_factor(const Eigen::SparseMatrix<double>& q,
                          const std::vector<int>& vertex_ordering) {
    laplacian_factor = make_bordered_cholesky();
    if (!laplacian_factor || vertex_ordering.size() != static_cast<std::size_t>(vertex_count))
      return false;
    // L_FF from the u-u block, and the coupled free vertices from the u-v block.
    std::vector<int> u_rows(static_cast<std::size_t>(q.rows()), -1);
    std::vector<int> u_columns(static_cast<std::size_t>(q.cols()), -1);
    std::copy(free_vertex.begin(), free_vertex.end(), u_rows.begin());
    std::copy(free_vertex.begin(), free_vertex.end(), u_columns.begin());
    laplacian = gather_submatrix(q, u_rows, u_columns, free_count, true);
    std::vector<char> coupled_vertex(static_cast<std::size_t>(free_count), 0);
    std::vector<std::pair<int, int>> free_coupling;  // (free u vertex, free v vertex)
    std::vector<int> free_coupling_source;
    for (int c = 0; c < vertex_count; ++c) {
      const int column = free_vertex[static_cast<std::size_t>(c)];
      if (column < 0) continue;
      for (int k = q.outerIndexPtr()[vertex_count + c]; k < q.outerIndexPtr()[vertex_count + c + 1];
           ++k) {
        const int row_unknown = q.innerIndexPtr()[k];
        if (row_unknown >= vertex_count) break;  // Rows are sorted: the v-v block follows.
        const int row = free_vertex[static_cast<std::size_t>(row_unknown)];
        if (row < 0) continue;
        coupled_vertex[static_cast<std::size_t>(row)] = 1;
        coupled_vertex[static_cast<std::size_t>(column)] = 1;
        free_coupling.emplace_back(row, column);
        free_coupling_source.push_back(k);
      }
    }
    // Elimination order: the uncoupled free vertices along the vertex ordering, then the border.
    std::vector<int> ordering;
    ordering.reserve(static_cast<std::size_t>(free_count));
    border.clear();
    for (const int v : vertex_ordering) {
      const int f = free_vertex[static_cast<std::size_t>(v)];
      if (f < 0) continue;
      (coupled_vertex[static_cast<std::size_t>(f)] ? border : ordering).push_back(f);
    }
    ordering.insert(ordering.end(), border.begin(), border.end());
    const int border_size = static_cast<int>(border.size());
    // A mesh's factorization costs about c n^1.5 flops (c about 10 for nested dissection of a
    // surface mesh's graph, more for AMD): a border far above sqrt(n) cannot pay off, and is
    // turned down before the analysis.
    if (strategy == UvSystemStrategy::automatic &&
        border_size > kLargestBorderPerRootVertex * std::sqrt(static_cast<double>(free_count)))
      return false;
    if (!laplacian_factor->analyze(laplacian.matrix, ordering, border_size)) return false;
    const double dense_flops = std::pow(2.0 * border_size, 3) / 3.0;
    if (strategy == UvSystemStrategy::automatic &&
        dense_flops > kBorderCostFraction * laplacian_factor->factorization_flops())
      return false;
    border_position.assign(static_cast<std::size_t>(free_count), -1);
    for (int b = 0; b < border_size; ++b)
      border_position[static_cast<std::size_t>(border[static_cast<std::size_t>(b)])] = b;
    coupling_entries.clear();
    for (const auto& [row, column] : free_coupling)
      coupling_entries.emplace_back(border_position[static_cast<std::size_t>(row)],
                                    border_position[static_cast<std::size_t>(column)]);
    coupling_source = std::move(free_coupling_source);
    coupled_solver.reset();
    return true;
  }

  void analyze_coupled_blocks(const Eigen::SparseMatrix<double>& q,
                              const std::vector<int>& vertex_ordering) {
    laplacian_factor.reset();
    free_unknown.assign(static_cast<std::size_t>(q.rows()), -1);
    int next = 0;
    for (int unknown = 0; unknown < 2 * vertex_count; ++unknown)
      if (free_vertex[static_cast<std::size_t>(unknown % vertex_count)] >= 0)
        free_unknown[static_cast<std::size_t>(unknown)] = next++;
    coupled = gather_submatrix(q, free_unknown, free_unknown, next, false);
    // The coupled u-v system's near-kernel is not a constant per unknown (translations and the
    // quarter turn (u, v) -> (-v, u) mix the two blocks), which scalar aggregation assumes: on
    // camel_b's linear ABF it took ten times Jacobi's time. Jacobi until a 2x2-block
    // aggregation exists.
    IterativeSettings coupled_settings = settings;
    coupled_settings.preconditioner = IterativePreconditioner::jacobi;
    coupled_solver = make_system_solver(*backend, MatrixKind::symmetric_positive_definite,
                                        coupled_settings, progress);
    const std::vector<int> ordering =
        uv_block_ordering(vertex_ordering, free_unknown, coupled.matrix);
    if (ordering.empty())
      coupled_solver->analyze(coupled.matrix);
    else
      coupled_solver->analyze_with_ordering(coupled.matrix, ordering);
  }

  SolveStats factorize(Eigen::SparseMatrix<double>&& q) {
    const SolveStats stats = factorize_on_active_backend(std::move(q));
    if (stats.status != Status::ok && may_move_to_cpu(stats)) return move_to_cpu(stats);
    return stats;
  }

  [[nodiscard]] bool may_move_to_cpu(const SolveStats& failed) const {
    return cpu_retry_allowed && !cpu_backend &&
           may_retry_on_cpu(BackendChoice::automatic, *backend, failed);
  }

  // Analyzes and factorizes the form again on the CPU, which keeps the system from now on (there
  // the one-factor way may be taken).
  SolveStats move_to_cpu(const SolveStats& failed) {
    failed_device_solver = name();
    cpu_backend = make_backend(BackendChoice::cpu, nullptr);
    backend = cpu_backend.get();
    pattern_outer.clear();  // A new analysis, for the CPU's solvers.
    Eigen::SparseMatrix<double> q = form;
    analyze(q, pins, analyzed_vertex_ordering);
    SolveStats stats = factorize_on_active_backend(std::move(q));
    if (stats.status == Status::ok) {
      cpu_retry_notice_text = cpu_retry_notice(failed_device_solver, failed, *cpu_backend);
    } else {
      stats.message += " (on the CPU, after the device's " + failed_device_solver + " failed: " + failed.message + ")";
    }
    return stats;
  }

  SolveStats factorize_on_active_backend(Eigen::SparseMatrix<double>&& q) {
    SolveStats stats;
    factorized = false;
    form.swap(q);  // Eigen 3.4's sparse matrices have no move assignment.
    if (!one_factor) {
      coupled.gather(form);
      stats = coupled_solver->factorize(coupled.matrix);
      factorized = stats.status == Status::ok;
      return stats;
    }
    laplacian.gather(form);
    const auto fail = [this, &stats](const std::string& message) {
      stats.status = Status::numerical_failure;
      stats.message = std::string(laplacian_factor->name()) + ": " + message;
      return stats;
    };
    if (!laplacian_factor->factorize(laplacian.matrix))
      return fail("numeric factorization failed (the Laplacian is not positive definite)");
    border_factor = laplacian_factor->border_factor();
    const auto border_size = static_cast<Eigen::Index>(border.size());
    Eigen::MatrixXd system(2 * border_size, 2 * border_size);
    const Eigen::MatrixXd schur = border_factor * border_factor.transpose();
    Eigen::MatrixXd coupling = Eigen::MatrixXd::Zero(border_size, border_size);
    for (std::size_t k = 0; k < coupling_entries.size(); ++k)
      coupling(coupling_entries[k].first, coupling_entries[k].second) +=
          form.valuePtr()[coupling_source[k]];
    system << schur, coupling, coupling.transpose(), schur;
    border_system.compute(system);
    if (border_system.info() != Eigen::Success)
      return fail("the boundary system of u and v is not positive definite");
    factorized = true;
    return stats;
  }

  // -Q_FP x_P as (f, g) over the free vertices: only the second pin is away from the origin.
  Eigen::MatrixX2d pinned_right_hand_side() const {
    Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(free_count, 2);
    for (Eigen::SparseMatrix<double>::InnerIterator entry(form, pins.second); entry; ++entry) {
      const int vertex = static_cast<int>(entry.row()) % vertex_count;
      const int coordinate = static_cast<int>(entry.row()) / vertex_count;
      const int row = free_vertex[static_cast<std::size_t>(vertex)];
      if (row >= 0) rhs(row, coordinate) -= pins.distance * entry.value();
    }
    return rhs;
  }

  // Q_FF x = rhs (two columns: the u and v parts) with the factorization; false when a solve
  // failed (stats says why).
  bool solve_free(const Eigen::MatrixX2d& rhs, Eigen::MatrixX2d& free_uv, SolveStats& stats) const {
    free_uv.resize(free_count, 2);
    if (one_factor) {
      Eigen::MatrixXd forward = laplacian_factor->forward(rhs);
      const auto border_size = static_cast<Eigen::Index>(border.size());
      if (forward.rows() != free_count) return failed_solve(stats);
      if (border_size > 0) {
        const Eigen::MatrixXd reduced = border_factor * forward.bottomRows(border_size);
        Eigen::VectorXd stacked(2 * border_size);
        stacked << reduced.col(0), reduced.col(1);
        const Eigen::VectorXd border_uv = border_system.solve(stacked);
        forward.bottomRows(border_size).col(0) =
            border_factor.transpose() * border_uv.head(border_size);
        forward.bottomRows(border_size).col(1) =
            border_factor.transpose() * border_uv.tail(border_size);
      }
      free_uv = laplacian_factor->backward(forward);
      if (free_uv.rows() != free_count) return failed_solve(stats);
      return true;
    }
    Eigen::VectorXd stacked(2 * free_count);
    stacked << rhs.col(0), rhs.col(1);
    Eigen::MatrixXd solution;
    stats = coupled_solver->solve(stacked, solution);
    if (stats.status != Status::ok) return false;
    free_uv.col(0) = solution.col(0).head(free_count);
    free_uv.col(1) = solution.col(0).tail(free_count);
    return true;
  }

  // All vertices' positions from the free ones, with the pins in place.
  Eigen::MatrixX2d with_pins(const Eigen::MatrixX2d& free_uv) const {
    Eigen::MatrixX2d uv(vertex_count, 2);
    for (int v = 0; v < vertex_count; ++v) {
      const int f = free_vertex[static_cast<std::size_t>(v)];
      if (f >= 0) uv.row(v) = free_uv.row(f);
    }
    uv.row(pins.first) << 0.0, 0.0;
    uv.row(pins.second) << pins.distance, 0.0;
    return uv;
  }

  // The free rows' residual rhs - Q_FF x_F = -(Q x)_F (x with the pins), as (u, v) columns.
  Eigen::MatrixX2d free_residual(const Eigen::MatrixX2d& uv) const {
    Eigen::VectorXd all(2 * static_cast<Eigen::Index>(vertex_count));
    all << uv.col(0), uv.col(1);
    const Eigen::VectorXd product = form * all;
    Eigen::MatrixX2d residual(free_count, 2);
    for (Eigen::Index unknown = 0; unknown < product.size(); ++unknown) {
      const int f = free_vertex[static_cast<std::size_t>(unknown % vertex_count)];
      if (f >= 0) residual(f, unknown / vertex_count) = -product[unknown];
    }
    return residual;
  }

  SolveStats solve(Eigen::MatrixX2d& uv, int refinement_steps) {
    SolveStats stats;
    if (!factorized) {
      stats.status = Status::numerical_failure;
      stats.message = "uv system: solve called without a successful factorization";
      return stats;
    }
    const Eigen::MatrixX2d rhs = pinned_right_hand_side();
    Eigen::MatrixX2d free_uv;
    if (!solve_free(rhs, free_uv, stats)) {
      if (!may_move_to_cpu(stats)) return stats;
      const SolveStats failed = stats;
      stats = move_to_cpu(failed);
      if (stats.status != Status::ok || !solve_free(rhs, free_uv, stats)) return stats;
    }
    uv = with_pins(free_uv);
    Eigen::MatrixX2d residual = free_residual(uv);
    const double rhs_norm = rhs.norm();
    const auto relative = [rhs_norm](const Eigen::MatrixX2d& r) {
      return rhs_norm > 0.0 ? r.norm() / rhs_norm : r.norm();
    };
    // Refinement needs an exact solve with the factor; an iterative solver's accuracy is its
    // tolerance, which a second solve would only buy again.
    for (int step = 0; direct && step < refinement_steps; ++step) {
      Eigen::MatrixX2d correction;
      if (!solve_free(residual, correction, stats)) return stats;
      free_uv += correction;
      uv = with_pins(free_uv);
      residual = free_residual(uv);
    }
    stats.relative_residual = relative(residual);
    return stats;
  }

  bool failed_solve(SolveStats& stats) const {
    stats.status = Status::numerical_failure;
    stats.message = name() + ": back-substitution failed";
    return false;
  }

  std::string name() const {
    const std::string after_device =
        failed_device_solver.empty() ? "" : " (after the device's " + failed_device_solver + " failed)";
    if (one_factor)
      return std::string(laplacian_factor->name()) + " (one Laplacian factor for u and v" +
             std::string(laplacian_factor->on_two_threads() ? " on two subtrees" : "") + ", " +
             std::to_string(border.size()) + " coupled vertices)" + after_device;
    return (coupled_solver ? coupled_solver->name() : std::string("uv system")) + after_device;
  }
};

UvSystemSolver::UvSystemSolver(Backend& backend, const IterativeSettings& settings,
                               const ProgressCallback& progress, UvSystemStrategy strategy)
    : impl_(std::make_unique<Impl>(backend, settings, progress, strategy)) {}

UvSystemSolver::~UvSystemSolver() = default;

void UvSystemSolver::analyze(const Eigen::SparseMatrix<double>& form, const LayoutPins& pins,
                             const std::vector<int>& vertex_ordering) {
  impl_->analyze(form, pins, vertex_ordering);
}

SolveStats UvSystemSolver::factorize(Eigen::SparseMatrix<double>&& form) {
  return impl_->factorize(std::move(form));
}

SolveStats UvSystemSolver::solve(Eigen::MatrixX2d& uv, int refinement_steps) {
  return impl_->solve(uv, refinement_steps);
}

void UvSystemSolver::allow_cpu_retry() { impl_->cpu_retry_allowed = true; }

std::string UvSystemSolver::take_cpu_retry_notice() { return std::exchange(impl_->cpu_retry_notice_text, {}); }

std::string UvSystemSolver::name() const { return impl_->name(); }

}  // namespace harmonia::detail
