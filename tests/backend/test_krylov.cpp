// The Krylov solvers (PCG, MINRES) on the CPU backend's primitives, checked against direct sparse
// factorizations; the iterative SparseSystemSolver; the backend and solver factories.
#include <random>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <gtest/gtest.h>

#include "backend/backend.h"
#include "backend/iterative_system_solver.h"
#include "fallback/cpu_backend.h"
#include "fallback/direct_solvers.h"
#include "harmonia/boundary.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "solve/backend_selection.h"
#include "solve/dirichlet_system.h"
#include "support/test_support.h"

namespace harmonia::detail {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

// A random sparse SPD matrix: B^T B + I with about `per_row` entries per row of B.
Sparse random_spd(int n, int per_row, unsigned seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> column(0, n - 1);
  std::vector<Eigen::Triplet<double>> entries;
  for (int row = 0; row < n; ++row) {
    for (int k = 0; k < per_row; ++k)
      entries.emplace_back(row, column(generator), value(generator));
  }
  Sparse b(n, n);
  b.setFromTriplets(entries.begin(), entries.end());
  Sparse identity(n, n);
  identity.setIdentity();
  return Sparse(b.transpose() * b) + identity;
}

// A symmetric indefinite matrix: a random SPD matrix shifted by its mean diagonal.
Sparse random_indefinite(int n, unsigned seed) {
  Sparse a = random_spd(n, 3, seed);
  const double shift = a.diagonal().mean();
  Sparse identity(n, n);
  identity.setIdentity();
  return a - shift * identity;
}

Eigen::MatrixXd random_block(int rows, int cols, unsigned seed) {
  std::mt19937 generator(seed);
  std::normal_distribution<double> value;
  Eigen::MatrixXd block(rows, cols);
  for (int c = 0; c < cols; ++c)
    for (int r = 0; r < rows; ++r) block(r, c) = value(generator);
  return block;
}

// Interior block of the cotangent Laplacian of a hemisphere (the Dirichlet matrix of a map).
Sparse hemisphere_interior_laplacian(int rings) {
  const Mesh mesh = hemisphere(rings);
  const int interior = 1 + 3 * rings * (rings - 1);  // Vertices before the equator ring.
  return laplacian(mesh, WeightScheme::cotangent).topLeftCorner(interior, interior);
}

struct KrylovRun {
  SolveStats stats;
  Eigen::MatrixXd solution;
};

enum class Method { pcg, minres };

KrylovRun run(Method method, const Sparse& a, const Eigen::MatrixXd& b,
              const Eigen::MatrixXd& start, IterativeSettings settings = {}) {
  CpuBackend backend;
  const auto matrix = backend.upload(RowMajorSparse(a));
  const auto rhs = backend.upload(b);
  const auto x = backend.upload(start);
  KrylovRun result;
  result.stats = method == Method::pcg ? backend.pcg(*matrix, *rhs, *x, settings, {})
                                       : backend.minres(*matrix, *rhs, *x, settings, {});
  result.solution = x->download();
  return result;
}

double relative_difference(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference) {
  return (x - reference).norm() / reference.norm();
}

TEST(Krylov, PcgMatchesCholeskyOnRandomSpdMatrix) {
  const Sparse a = random_spd(400, 4, 1);
  const Eigen::MatrixXd b = random_block(400, 2, 2);
  const Eigen::SimplicialLDLT<Sparse> direct(a);
  const Eigen::MatrixXd reference = direct.solve(b);
  const KrylovRun result = run(Method::pcg, a, b, Eigen::MatrixXd::Zero(400, 2));
  EXPECT_EQ(result.stats.status, Status::ok) << result.stats.message;
  EXPECT_LE(result.stats.relative_residual, 1e-10);
  EXPECT_GT(result.stats.iterations, 1);
  EXPECT_LT(relative_difference(result.solution, reference), 1e-7);
}

TEST(Krylov, MinresMatchesLuOnRandomIndefiniteMatrix) {
  const Sparse a = random_indefinite(300, 3);
  const Eigen::VectorXd diagonal = a.diagonal();
  ASSERT_LT(diagonal.minCoeff(), 0.0);  // Really indefinite (negative and positive diagonal).
  ASSERT_GT(diagonal.maxCoeff(), 0.0);
  const Eigen::MatrixXd b = random_block(300, 2, 4);
  Eigen::SparseLU<Sparse> lu(a);
  ASSERT_EQ(lu.info(), Eigen::Success);
  const Eigen::MatrixXd reference = lu.solve(b);
  IterativeSettings settings;
  settings.max_iterations = 5000;
  const KrylovRun result = run(Method::minres, a, b, Eigen::MatrixXd::Zero(300, 2), settings);
  EXPECT_EQ(result.stats.status, Status::ok) << result.stats.message;
  EXPECT_LE(result.stats.relative_residual, 1e-10);
  // The residual bound turns into an error bound through the condition number; 1e-6 is ample.
  EXPECT_LT(relative_difference(result.solution, reference), 1e-6);
}

TEST(Krylov, PcgAndMinresSolveAMeshLaplacian) {
  const Sparse a = hemisphere_interior_laplacian(12);
  const Eigen::MatrixXd b = random_block(static_cast<int>(a.rows()), 2, 5);
  auto cholesky = make_cholesky_solver();
  cholesky->analyze(a);
  ASSERT_EQ(cholesky->factorize(a).status, Status::ok);
  Eigen::MatrixXd reference;
  ASSERT_EQ(cholesky->solve(b, reference).status, Status::ok);
  for (const Method method : {Method::pcg, Method::minres}) {
    const KrylovRun result = run(method, a, b, Eigen::MatrixXd::Zero(a.rows(), 2));
    EXPECT_EQ(result.stats.status, Status::ok) << result.stats.message;
    EXPECT_LT(relative_difference(result.solution, reference), 1e-8);
  }
}

TEST(Krylov, WarmStartNeedsFewerIterations) {
  const Sparse a = hemisphere_interior_laplacian(12);
  const Eigen::MatrixXd b = random_block(static_cast<int>(a.rows()), 2, 6);
  const KrylovRun cold = run(Method::pcg, a, b, Eigen::MatrixXd::Zero(a.rows(), 2));
  ASSERT_EQ(cold.stats.status, Status::ok);
  // A nearby right-hand side (as in successive rounds of an iteration) started from the old answer.
  const Eigen::MatrixXd nearby = b + 1e-4 * random_block(static_cast<int>(a.rows()), 2, 7);
  const KrylovRun from_zero = run(Method::pcg, a, nearby, Eigen::MatrixXd::Zero(a.rows(), 2));
  const KrylovRun warm = run(Method::pcg, a, nearby, cold.solution);
  ASSERT_EQ(warm.stats.status, Status::ok);
  EXPECT_LT(warm.stats.iterations, from_zero.stats.iterations);
  const KrylovRun warm_minres = run(Method::minres, a, nearby, cold.solution);
  const KrylovRun cold_minres = run(Method::minres, a, nearby, Eigen::MatrixXd::Zero(a.rows(), 2));
  EXPECT_LT(warm_minres.stats.iterations, cold_minres.stats.iterations);
  // An exact start needs no iteration at all.
  EXPECT_EQ(run(Method::pcg, a, b, cold.solution).stats.iterations, 0);
}

TEST(Krylov, IterationCapGivesNotConverged) {
  const Sparse a = hemisphere_interior_laplacian(12);
  const Eigen::MatrixXd b = random_block(static_cast<int>(a.rows()), 1, 8);
  IterativeSettings settings;
  settings.max_iterations = 3;
  for (const Method method : {Method::pcg, Method::minres}) {
    const KrylovRun result = run(method, a, b, Eigen::MatrixXd::Zero(a.rows(), 1), settings);
    EXPECT_EQ(result.stats.status, Status::not_converged);
    EXPECT_EQ(result.stats.iterations, 3);
    EXPECT_GT(result.stats.relative_residual, 1e-10);
    EXPECT_NE(result.stats.message.find("3 iterations"), std::string::npos) << result.stats.message;
    // The figures the message is about, read back from it, are the residual and the tolerance
    // to the three digits it prints (a fixed-point print made the tolerance "0.000000").
    EXPECT_NEAR(testing::figure_after(result.stats.message, "relative residual "), result.stats.relative_residual,
                5e-3 * result.stats.relative_residual)
        << result.stats.message;
    EXPECT_NEAR(testing::figure_after(result.stats.message, "(tolerance "), settings.relative_tolerance,
                5e-3 * settings.relative_tolerance)
        << result.stats.message;
  }
}

TEST(Krylov, ZeroRightHandSideColumnGivesZeroSolution) {
  const Sparse a = random_spd(100, 3, 9);
  Eigen::MatrixXd b = random_block(100, 2, 10);
  b.col(1).setZero();
  const KrylovRun result = run(Method::pcg, a, b, Eigen::MatrixXd::Ones(100, 2));
  EXPECT_EQ(result.stats.status, Status::ok);
  EXPECT_EQ(result.solution.col(1).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Krylov, PcgRejectsAnIndefiniteMatrix) {
  const Sparse a = random_indefinite(200, 11);
  const KrylovRun result =
      run(Method::pcg, a, random_block(200, 1, 12), Eigen::MatrixXd::Zero(200, 1));
  EXPECT_NE(result.stats.status, Status::ok);
}

TEST(Krylov, ProgressCallbackCancels) {
  const Sparse a = hemisphere_interior_laplacian(12);
  CpuBackend backend;
  const auto matrix = backend.upload(RowMajorSparse(a));
  const auto rhs = backend.upload(random_block(static_cast<int>(a.rows()), 1, 13));
  const auto x = backend.allocate(static_cast<int>(a.rows()), 1);
  int calls = 0;
  const ProgressCallback stop_at_second = [&calls](const Progress&) { return ++calls < 2; };
  IterativeSettings settings;
  settings.check_every = 1;
  EXPECT_EQ(backend.pcg(*matrix, *rhs, *x, settings, stop_at_second).status, Status::cancelled);
  EXPECT_EQ(calls, 2);
}

TEST(SystemSolvers, IterativeSolverMatchesDirectSolversForEveryKind) {
  CpuBackend backend;
  IterativeSettings settings;
  settings.relative_tolerance = 1e-12;
  settings.max_iterations = 20000;
  // A non-symmetric but well-conditioned matrix for the normal-equations path.
  Sparse general = random_spd(150, 3, 14);
  general.coeffRef(0, 5) += 0.5;
  general.coeffRef(7, 2) -= 0.3;
  const struct {
    MatrixKind kind;
    Sparse matrix;
  } cases[] = {{MatrixKind::symmetric_positive_definite, random_spd(150, 3, 15)},
               {MatrixKind::symmetric_indefinite, random_indefinite(150, 16)},
               {MatrixKind::general, general}};
  for (const auto& test_case : cases) {
    const Eigen::MatrixXd b = random_block(150, 2, 17);
    Eigen::SparseLU<Sparse> lu(test_case.matrix);
    const Eigen::MatrixXd reference = lu.solve(b);
    auto solver = make_iterative_solver(backend, test_case.kind, settings, {});
    solver->analyze(test_case.matrix);
    ASSERT_EQ(solver->factorize(test_case.matrix).status, Status::ok);
    Eigen::MatrixXd solution;
    const SolveStats stats = solver->solve(b, solution);
    EXPECT_EQ(stats.status, Status::ok) << solver->name() << ": " << stats.message;
    EXPECT_LT(relative_difference(solution, reference), 1e-7) << solver->name();
  }
}

TEST(SystemSolvers, DirectSolversReuseTheSymbolicAnalysis) {
  const Sparse a = hemisphere_interior_laplacian(8);
  const Eigen::MatrixXd b = random_block(static_cast<int>(a.rows()), 2, 18);
  std::unique_ptr<SparseSystemSolver> solvers[] = {make_cholesky_solver(), make_lu_solver()};
  for (auto& solver : solvers) {
    solver->analyze(a);
    for (const double scale : {1.0, 3.0}) {  // Same pattern, new values: numeric refactorization.
      const Sparse scaled = scale * a;
      ASSERT_EQ(solver->factorize(scaled).status, Status::ok) << solver->name();
      Eigen::MatrixXd x;
      ASSERT_EQ(solver->solve(b, x).status, Status::ok);
      EXPECT_LT((scaled * x - b).norm() / b.norm(), 1e-12) << solver->name();
    }
  }
}

TEST(SystemSolvers, CholeskyReportsAMatrixThatIsNotPositiveDefinite) {
  const Sparse a = random_indefinite(100, 19);
  auto solver = make_cholesky_solver();
  solver->analyze(a);
  if (solver->name().find("cholmod") == std::string::npos)
    GTEST_SKIP() << "built without CHOLMOD: LDLT factorizes indefinite matrices without complaint";
  const SolveStats stats = solver->factorize(a);
  EXPECT_EQ(stats.status, Status::numerical_failure) << solver->name();
  EXPECT_NE(stats.message.find(solver->name()), std::string::npos);
}

TEST(Backends, FactoriesChooseABackend) {
  std::string message;
  auto cpu = make_backend(BackendChoice::cpu, &message);
  ASSERT_NE(cpu, nullptr);
  EXPECT_EQ(cpu->kind(), BackendKind::cpu);
  EXPECT_TRUE(message.empty());
  auto automatic = make_backend(BackendChoice::automatic, &message);
  ASSERT_NE(automatic, nullptr);
  // With the Vulkan backend, automatic picks a hardware GPU where there is one; on the CPU it
  // says why (tests/kernels/test_vulkan_context.cpp covers the Vulkan cases).
  if (automatic->kind() == BackendKind::cpu) {
    EXPECT_NE(message.find("CPU"), std::string::npos) << message;
  }
#ifndef HARMONIA_HAVE_VULKAN
  EXPECT_EQ(automatic->kind(), BackendKind::cpu);
  EXPECT_EQ(make_backend(BackendChoice::vulkan, &message), nullptr);
  EXPECT_NE(message.find("--backend cpu"), std::string::npos) << message;
#endif
  EXPECT_NE(make_system_solver(*cpu, MatrixKind::general, {}, {})->name().find("lu"),
            std::string::npos);
}

// The Dirichlet system of a disk: its boundary loop on the unit circle.
struct DiskDirichlet {
  Mesh mesh = demo_surface(14);
  std::vector<int> loop = boundary_loops(mesh).front();
  BoundaryPlacement placement = place_boundary(mesh, loop, BoundaryOptions{});
};

SolverOptions cpu_solver_options() {
  SolverOptions options;
  options.backend = BackendChoice::cpu;
  return options;
}

TEST(DirichletSystem, OperatorsWithAndWithoutThePatternSolveAlike) {
  // The index-map path (operator in the analyzed pattern) and the search path (any pattern inside
  // it) load the same L_II and L_IB. The operator: the Laplacian without the edge between two
  // interior vertices, once with explicit zeros there and once with the entries pruned away.
  const DiskDirichlet disk;
  CpuBackend backend;
  const Eigen::SparseMatrix<double> laplace = laplacian(disk.mesh, WeightScheme::cotangent);
  std::vector<bool> fixed(static_cast<std::size_t>(disk.mesh.vertex_count()), false);
  for (const int v : disk.loop) fixed[static_cast<std::size_t>(v)] = true;
  int a = 0, b = 0;
  for (int column = 0; column < laplace.outerSize() && b == 0; ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(laplace, column); entry; ++entry)
      if (entry.row() != column && !fixed[entry.row()] && !fixed[column]) {
        a = static_cast<int>(entry.row());
        b = column;
        break;
      }
  ASSERT_NE(a, b);
  Eigen::SparseMatrix<double> with_zeros = laplace;
  with_zeros.coeffRef(a, a) += laplace.coeff(a, b);
  with_zeros.coeffRef(b, b) += laplace.coeff(a, b);
  with_zeros.coeffRef(a, b) = 0.0;
  with_zeros.coeffRef(b, a) = 0.0;
  with_zeros.makeCompressed();
  Eigen::SparseMatrix<double> pruned = with_zeros;
  pruned.prune(0.0);
  ASSERT_EQ(pruned.nonZeros(), laplace.nonZeros() - 2);
  const Eigen::SparseMatrix<double>& restored = pruned;
  const Eigen::SparseMatrix<double>& in_pattern_operator = with_zeros;
  Eigen::MatrixX2d in_pattern, searched;
  SolveReport report;
  DirichletSystem first(laplace, disk.placement.vertices, backend,
                        MatrixKind::symmetric_positive_definite, cpu_solver_options());
  ASSERT_TRUE(first.factorize(in_pattern_operator, report) &&
              first.solve(disk.placement.uv, in_pattern, report));
  DirichletSystem second(laplace, disk.placement.vertices, backend,
                         MatrixKind::symmetric_positive_definite, cpu_solver_options());
  ASSERT_TRUE(second.factorize(restored, report) &&
              second.solve(disk.placement.uv, searched, report));
  EXPECT_EQ(report.status, Status::ok) << report.message;
  EXPECT_LT((in_pattern - searched).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT(report.residual, 1e-12);
}

TEST(DirichletSystem, StaleFactorSolvesANearbyOperatorAndRefusesAFarOne) {
  const DiskDirichlet disk;
  CpuBackend backend;
  const Eigen::SparseMatrix<double> factored = laplacian(disk.mesh, WeightScheme::cotangent);
  SolveReport report;
  DirichletSystem system(factored, disk.placement.vertices, backend,
                         MatrixKind::symmetric_positive_definite, cpu_solver_options());
  Eigen::MatrixX2d uv;
  ASSERT_TRUE(system.factorize(factored, report) && system.solve(disk.placement.uv, uv, report));
  ASSERT_TRUE(system.has_reusable_factor());

  // Nearby: 3% more of the uniform Laplacian. CG with the old factor reaches the direct answer.
  const Eigen::SparseMatrix<double> uniform = laplacian(disk.mesh, WeightScheme::uniform);
  const Eigen::SparseMatrix<double> nearby = factored + 0.03 * uniform;
  Eigen::MatrixX2d iterated, direct;
  ASSERT_TRUE(system.load(nearby, report));
  ASSERT_EQ(system.solve_with_stale_factor(disk.placement.uv, 1e-10, 1e-12, 10, iterated, report),
            StaleFactorOutcome::converged);
  EXPECT_GT(report.iterations, 0);
  EXPECT_LE(report.iterations, 10);
  SolveReport direct_report;
  DirichletSystem exact(nearby, disk.placement.vertices, backend,
                        MatrixKind::symmetric_positive_definite, cpu_solver_options());
  ASSERT_TRUE(exact.factorize(nearby, direct_report) &&
              exact.solve(disk.placement.uv, direct, direct_report));
  EXPECT_LT((iterated - direct).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(report.residual, 1e-11);

  // Far: a uniform Laplacian 50 times stronger converges too slowly for 3 iterations; the output
  // is left alone so the caller can factorize instead.
  const Eigen::SparseMatrix<double> far = factored + 50.0 * uniform;
  Eigen::MatrixX2d untouched = Eigen::MatrixX2d::Constant(3, 2, 7.0);
  ASSERT_TRUE(system.load(far, report));
  EXPECT_EQ(system.solve_with_stale_factor(disk.placement.uv, 1e-10, 1e-12, 3, untouched, report),
            StaleFactorOutcome::too_slow);
  EXPECT_EQ(untouched, Eigen::MatrixX2d::Constant(3, 2, 7.0));
}

}  // namespace
}  // namespace harmonia::detail
