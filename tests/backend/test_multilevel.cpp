// The smoothed-aggregation hierarchy and its V-cycle as the preconditioner of the conjugate
// gradients, on the CPU backend's primitives: checked against direct factorizations, against
// Jacobi's iteration counts, and against exact properties (a scaled matrix gives the same
// iterations; a matrix small enough to be the coarsest level is solved in one iteration).
#include <gtest/gtest.h>

#include "backend/aggregation_hierarchy.h"
#include "backend/backend.h"
#include "backend/iterative_system_solver.h"
#include "fallback/cpu_backend.h"
#include "fallback/direct_solvers.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "support/test_support.h"

namespace harmonia::detail {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

// The fixed-boundary cotangent system of a hemisphere (equator fixed): L_II X = -L_IB X_B.
struct Problem {
  Sparse matrix;
  Eigen::MatrixXd rhs;
};

Problem hemisphere_problem(int rings) {
  const Mesh mesh = hemisphere(rings);
  const Sparse l = laplacian(mesh, WeightScheme::cotangent);
  const int interior = 1 + 3 * rings * (rings - 1);  // Vertices before the equator ring.
  Problem problem;
  problem.matrix = l.topLeftCorner(interior, interior);
  const Eigen::Index fixed = l.rows() - interior;
  problem.rhs = -Sparse(l.bottomLeftCorner(fixed, interior)).transpose() *
                mesh.vertices.bottomRows(fixed).leftCols(2);
  return problem;
}

Eigen::MatrixXd direct_solution(const Problem& problem) {
  auto cholesky = make_cholesky_solver();
  cholesky->analyze(problem.matrix);
  EXPECT_EQ(cholesky->factorize(problem.matrix).status, Status::ok);
  Eigen::MatrixXd x;
  EXPECT_EQ(cholesky->solve(problem.rhs, x).status, Status::ok);
  return x;
}

struct SolveRun {
  SolveStats stats;
  Eigen::MatrixXd solution;
};

// PCG from zero, preconditioned by the hierarchy's V-cycle (or by Jacobi without one).
SolveRun solve(const Problem& problem, const AggregationHierarchy* hierarchy, double tolerance) {
  CpuBackend backend;
  const auto a = backend.upload(RowMajorSparse(problem.matrix));
  const auto b = backend.upload(problem.rhs);
  const auto x = backend.allocate(static_cast<int>(problem.rhs.rows()),
                                  static_cast<int>(problem.rhs.cols()));
  IterativeSettings settings;
  settings.relative_tolerance = tolerance;
  SolveRun run;
  if (hierarchy != nullptr) {
    const auto cycle = backend.multilevel_preconditioner(*hierarchy);
    run.stats = backend.preconditioned_pcg(*a, *cycle, *b, *x, settings, {});
  } else {
    run.stats = backend.pcg(*a, *b, *x, settings, {});
  }
  run.solution = x->download();
  return run;
}

double relative_difference(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference) {
  return (x - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

TEST(Multilevel, LevelsShrinkAndEachGalerkinMatrixIsPositiveDefinite) {
  const Problem problem = hemisphere_problem(60);
  const AggregationHierarchy hierarchy(problem.matrix);
  const std::vector<int> rows = hierarchy.level_rows();
  ASSERT_GE(rows.size(), 3U);
  EXPECT_EQ(rows.front(), problem.matrix.rows());
  for (std::size_t l = 1; l < rows.size(); ++l) EXPECT_LT(rows[l] * 3, rows[l - 1]) << l;
  EXPECT_LE(rows.back(), AggregationSettings{}.coarsest_rows);
  // Operator complexity of smoothed aggregation on a surface mesh stays well under 2.
  EXPECT_LT(hierarchy.operator_complexity(), 2.0);
  for (const AggregationLevel& level : hierarchy.levels()) {
    const Eigen::MatrixXd restricted_identity =
        Eigen::MatrixXd(level.restriction) - Eigen::MatrixXd(level.prolongation).transpose();
    EXPECT_EQ(restricted_identity.cwiseAbs().maxCoeff(), 0.0);
  }
  // The coarsest inverse really inverts the coarsest matrix, the Galerkin chain P^T A P formed
  // here from the prolongations alone.
  Sparse chain = problem.matrix;
  for (const AggregationLevel& level : hierarchy.levels()) {
    const Sparse p(level.prolongation);
    chain = Sparse(p.transpose()) * chain * p;
  }
  const Eigen::MatrixXd coarse(chain);
  const Eigen::MatrixXd product = Eigen::MatrixXd(hierarchy.coarsest_inverse()) * coarse;
  const double condition = coarse.norm() * Eigen::MatrixXd(hierarchy.coarsest_inverse()).norm();
  EXPECT_LE((product - Eigen::MatrixXd::Identity(coarse.rows(), coarse.cols())).cwiseAbs().maxCoeff(),
            1e3 * std::numeric_limits<double>::epsilon() * condition);
}

TEST(Multilevel, PcgMatchesCholeskyInFewIterationsThatHardlyGrowWithTheMesh) {
  int previous_iterations = 0;
  for (const int rings : {30, 60}) {
    const Problem problem = hemisphere_problem(rings);
    const Eigen::MatrixXd reference = direct_solution(problem);
    const AggregationHierarchy hierarchy(problem.matrix);
    const SolveRun multilevel = solve(problem, &hierarchy, 1e-10);
    const SolveRun jacobi = solve(problem, nullptr, 1e-10);
    ASSERT_EQ(multilevel.stats.status, Status::ok) << multilevel.stats.message;
    ASSERT_EQ(jacobi.stats.status, Status::ok) << jacobi.stats.message;
    // A residual of 1e-10 bounds the error by 1e-10 times the condition number (about 1e4 for
    // these Laplacians): 1e-6 leaves room.
    EXPECT_LE(relative_difference(multilevel.solution, reference), 1e-6) << rings;
    EXPECT_LE(multilevel.stats.iterations, 40) << rings;
    EXPECT_LT(3 * multilevel.stats.iterations, jacobi.stats.iterations) << rings;
    // Four times the unknowns: Jacobi's count doubles (it grows with sqrt(cond) ~ h^-1), the
    // multilevel count stays nearly where it was.
    if (previous_iterations > 0)
      EXPECT_LE(multilevel.stats.iterations, previous_iterations + previous_iterations / 2) << rings;
    previous_iterations = multilevel.stats.iterations;
  }
}

TEST(Multilevel, RefreshKeepsTheAggregatesAndAScaledMatrixTakesTheSameIterations) {
  const Problem problem = hemisphere_problem(30);
  AggregationHierarchy hierarchy(problem.matrix);
  const SolveRun original = solve(problem, &hierarchy, 1e-9);
  Problem scaled = problem;
  scaled.matrix *= 4.0;  // A power of two: every product of the set-up scales exactly.
  ASSERT_TRUE(hierarchy.refresh(scaled.matrix));
  const SolveRun refreshed = solve(scaled, &hierarchy, 1e-9);
  ASSERT_EQ(refreshed.stats.status, Status::ok) << refreshed.stats.message;
  EXPECT_EQ(refreshed.stats.iterations, original.stats.iterations);
  EXPECT_LE(relative_difference(4.0 * refreshed.solution, original.solution), 1e-12);
  // Another pattern is not refreshed.
  EXPECT_FALSE(hierarchy.refresh(hemisphere_problem(29).matrix));
}

TEST(Multilevel, ASmallMatrixIsItsOwnCoarsestLevelAndIsSolvedInOneIteration) {
  const Problem problem = hemisphere_problem(6);
  ASSERT_LE(problem.matrix.rows(), AggregationSettings{}.coarsest_rows);
  const AggregationHierarchy hierarchy(problem.matrix);
  EXPECT_EQ(hierarchy.level_rows().size(), 1U);
  const SolveRun run = solve(problem, &hierarchy, 1e-10);
  ASSERT_EQ(run.stats.status, Status::ok) << run.stats.message;
  EXPECT_EQ(run.stats.iterations, 1);
  EXPECT_LE(relative_difference(run.solution, direct_solution(problem)), 1e-10);
}

TEST(Multilevel, ANonPositiveDiagonalIsRefusedNamingTheRow) {
  Problem problem = hemisphere_problem(30);
  problem.matrix.coeffRef(17, 17) = -1.0;
  try {
    const AggregationHierarchy hierarchy(problem.matrix);
    FAIL() << "a negative diagonal entry was accepted";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::numerical_failure);
    EXPECT_NE(std::string(error.what()).find("row 17"), std::string::npos) << error.what();
  }
}

TEST(Multilevel, TheIterativeSystemSolverUsesItByDefaultAndJacobiOnRequest) {
  const Problem problem = hemisphere_problem(30);
  const Eigen::MatrixXd reference = direct_solution(problem);
  CpuBackend backend;
  for (const IterativePreconditioner choice :
       {IterativePreconditioner::multilevel, IterativePreconditioner::jacobi}) {
    IterativeSettings settings;
    settings.relative_tolerance = 1e-10;
    settings.preconditioner = choice;
    auto solver =
        make_iterative_solver(backend, MatrixKind::symmetric_positive_definite, settings, {});
    solver->analyze(problem.matrix);
    ASSERT_EQ(solver->factorize(problem.matrix).status, Status::ok);
    Eigen::MatrixXd x;
    const SolveStats stats = solver->solve(problem.rhs, x);
    ASSERT_EQ(stats.status, Status::ok) << stats.message;
    EXPECT_LE(relative_difference(x, reference), 1e-6);
    EXPECT_EQ(solver->name(), choice == IterativePreconditioner::multilevel ? "pcg-multilevel"
                                                                              : "pcg-jacobi");
  }
}

}  // namespace
}  // namespace harmonia::detail
