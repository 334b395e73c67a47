// The Vulkan backend's Krylov solvers on lavapipe with validation: the fused device PCG (with
// refinement in double) against a direct solution of the hemisphere's Dirichlet problem, its
// determinism, warm start, iteration cap, breakdown and cancellation; MINRES on an indefinite
// system; the SparseSystemSolver the maps use (SPD and normal equations).
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <cmath>
#include <cstring>
#include <vector>

#include "backend/aggregation_hierarchy.h"
#include "backend/backend.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "kernels/kernel_test_data.h"
#include "kernels/vulkan_backend.h"
#include "solve/backend_selection.h"
#include "support/conditioning.h"
#include "support/test_support.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using detail::IterativeSettings;
using detail::SolveStats;
using vulkan::detail::VulkanBackend;

// The harmonic (cotangent) map of a hemisphere with the equator fixed where it is: L_II X = -L_IB
// X_B for the interior vertices, two right-hand sides (u and v).
struct DirichletProblem {
  RowMajorSparse interior;
  Eigen::MatrixXd rhs;
};

DirichletProblem hemisphere_dirichlet(int rings, WeightScheme scheme = WeightScheme::cotangent) {
  const Mesh mesh = hemisphere(rings);
  const Eigen::SparseMatrix<double> l = laplacian(mesh, scheme);
  const std::vector<int> loop = boundary_loops(mesh).front();
  std::vector<int> index(static_cast<std::size_t>(mesh.vertex_count()), 0);
  for (const int v : loop) index[v] = -1;
  int interior_count = 0;
  for (int& entry : index)
    if (entry == 0) entry = interior_count++;
  std::vector<Eigen::Triplet<double>> entries;
  DirichletProblem problem;
  problem.rhs = Eigen::MatrixXd::Zero(interior_count, 2);
  for (int column = 0; column < l.outerSize(); ++column) {
    for (Eigen::SparseMatrix<double>::InnerIterator entry(l, column); entry; ++entry) {
      const int row = index[entry.row()];
      if (row < 0) continue;
      if (index[column] >= 0)
        entries.emplace_back(row, index[column], entry.value());
      else
        problem.rhs.row(row) -= entry.value() * mesh.vertices.row(column).head<2>();
    }
  }
  problem.interior.resize(interior_count, interior_count);
  problem.interior.setFromTriplets(entries.begin(), entries.end());
  problem.interior.makeCompressed();
  return problem;
}

Eigen::MatrixXd direct_solution(const RowMajorSparse& a, const Eigen::MatrixXd& rhs) {
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(a);
  return lu.solve(rhs);
}

double relative_residual(const RowMajorSparse& a, const Eigen::MatrixXd& x,
                         const Eigen::MatrixXd& rhs) {
  double worst = 0.0;
  for (Eigen::Index c = 0; c < rhs.cols(); ++c)
    worst = std::max(worst, (rhs.col(c) - a * x.col(c)).norm() / rhs.col(c).norm());
  return worst;
}

double relative_difference(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference) {
  return (x - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

class VulkanSolvers : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(vulkan_test_context());
  }
  // Runs the backend's PCG from the warm start `start`; returns the solution.
  Eigen::MatrixXd pcg(const RowMajorSparse& a, const Eigen::MatrixXd& rhs,
                      const Eigen::MatrixXd& start, const IterativeSettings& settings,
                      SolveStats& stats, const ProgressCallback& progress = {}) {
    const auto matrix = gpu_->upload(a);
    const auto b = gpu_->upload(rhs);
    const auto x = gpu_->upload(start);
    stats = gpu_->pcg(*matrix, *b, *x, settings, progress);
    return x->download();
  }
  std::unique_ptr<VulkanBackend> gpu_;
};

TEST_F(VulkanSolvers, PcgMatchesTheDirectSolutionOfAHemisphere) {
  const DirichletProblem problem = hemisphere_dirichlet(30);
  const Eigen::MatrixXd reference = direct_solution(problem.interior, problem.rhs);
  const Eigen::MatrixXd zeros = Eigen::MatrixXd::Zero(problem.rhs.rows(), 2);
  // Within fp32's reach: one device solve, no refinement needed.
  IterativeSettings settings;
  settings.relative_tolerance = 1e-5;
  SolveStats stats;
  Eigen::MatrixXd x = pcg(problem.interior, problem.rhs, zeros, settings, stats);
  EXPECT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_GT(stats.iterations, 10);
  EXPECT_LE(stats.relative_residual, 1e-5);
  EXPECT_NEAR(relative_residual(problem.interior, x, problem.rhs), stats.relative_residual,
              harmonia::testing::residual_rounding(problem.interior, x, problem.rhs));
  EXPECT_LE(relative_difference(x, reference), 1e-3);
  // Below fp32's reach: refinement in double reaches the tolerance honestly.
  settings.relative_tolerance = 1e-10;
  x = pcg(problem.interior, problem.rhs, zeros, settings, stats);
  EXPECT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_LE(relative_residual(problem.interior, x, problem.rhs),
            1e-10 + harmonia::testing::residual_rounding(problem.interior, x, problem.rhs));
  EXPECT_LE(relative_difference(x, reference), 1e-8);
}

TEST_F(VulkanSolvers, PcgIsBitIdenticalRunToRunAndForEveryCheckInterval) {
  const DirichletProblem problem = hemisphere_dirichlet(16);
  const Eigen::MatrixXd zeros = Eigen::MatrixXd::Zero(problem.rhs.rows(), 2);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-8;
  SolveStats first, second, every_iteration;
  const Eigen::MatrixXd a = pcg(problem.interior, problem.rhs, zeros, settings, first);
  const Eigen::MatrixXd b = pcg(problem.interior, problem.rhs, zeros, settings, second);
  settings.check_every = 1;  // Converged columns are frozen on the device, so the batch length
  const Eigen::MatrixXd c =  // does not change a single bit.
      pcg(problem.interior, problem.rhs, zeros, settings, every_iteration);
  ASSERT_EQ(first.status, Status::ok) << first.message;
  const auto bytes = sizeof(double) * static_cast<std::size_t>(a.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), bytes), 0);
  EXPECT_EQ(std::memcmp(a.data(), c.data(), bytes), 0);
  EXPECT_EQ(first.iterations, second.iterations);
  EXPECT_EQ(first.iterations, every_iteration.iterations);
  EXPECT_EQ(first.relative_residual, every_iteration.relative_residual);
}

TEST_F(VulkanSolvers, PcgWarmStartAndIterationCap) {
  const DirichletProblem problem = hemisphere_dirichlet(20);
  const Eigen::MatrixXd reference = direct_solution(problem.interior, problem.rhs);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-9;
  SolveStats stats;
  // Started at the solution: nothing to do.
  const Eigen::MatrixXd x = pcg(problem.interior, problem.rhs, reference, settings, stats);
  EXPECT_EQ(stats.status, Status::ok);
  EXPECT_EQ(stats.iterations, 0);
  EXPECT_EQ(x, reference);
  // Capped: not converged, honest residual, at most the cap.
  settings.max_iterations = 5;
  (void)pcg(problem.interior, problem.rhs, Eigen::MatrixXd::Zero(reference.rows(), 2), settings,
            stats);
  EXPECT_EQ(stats.status, Status::not_converged);
  EXPECT_LE(stats.iterations, 5);
  EXPECT_GT(stats.relative_residual, 1e-9);
  EXPECT_NE(stats.message.find("stopped after"), std::string::npos) << stats.message;
  // Its figures, read back, are the residual and the tolerance to the three digits it prints (a
  // fixed-point print made the tolerance "0.000000").
  EXPECT_NEAR(testing::figure_after(stats.message, "relative residual "), stats.relative_residual,
              5e-3 * stats.relative_residual)
      << stats.message;
  EXPECT_NEAR(testing::figure_after(stats.message, "(tolerance "), settings.relative_tolerance,
              5e-3 * settings.relative_tolerance)
      << stats.message;
}

TEST_F(VulkanSolvers, PcgZeroRightHandSideGivesZero) {
  const DirichletProblem problem = hemisphere_dirichlet(8);
  Eigen::MatrixXd rhs = problem.rhs;
  rhs.col(0).setZero();
  IterativeSettings settings;
  SolveStats stats;
  const Eigen::MatrixXd x =
      pcg(problem.interior, rhs, Eigen::MatrixXd::Ones(rhs.rows(), 2), settings, stats);
  EXPECT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_EQ(x.col(0).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LE(relative_residual(problem.interior, x.col(1), rhs.col(1)),
            1e-10 + harmonia::testing::residual_rounding(problem.interior, x.col(1), rhs.col(1)));
}

TEST_F(VulkanSolvers, PcgReportsAMatrixThatIsNotPositiveDefinite) {
  const DirichletProblem problem = hemisphere_dirichlet(8);
  const RowMajorSparse negative = -problem.interior;  // Negative definite: p^T A p < 0 at once.
  SolveStats stats;
  (void)pcg(negative, problem.rhs, Eigen::MatrixXd::Zero(problem.rhs.rows(), 2), {}, stats);
  EXPECT_EQ(stats.status, Status::numerical_failure);
  EXPECT_NE(stats.message.find("not positive definite"), std::string::npos) << stats.message;
}

TEST_F(VulkanSolvers, PcgCancelsFromTheProgressCallback) {
  const DirichletProblem problem = hemisphere_dirichlet(20);
  int calls = 0;
  SolveStats stats;
  (void)pcg(problem.interior, problem.rhs, Eigen::MatrixXd::Zero(problem.rhs.rows(), 2), {}, stats,
            [&calls](const Progress& progress) {
              EXPECT_EQ(progress.stage, "pcg");
              return ++calls < 2;
            });
  EXPECT_EQ(stats.status, Status::cancelled);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(stats.iterations, 2 * IterativeSettings{}.check_every);
}

TEST_F(VulkanSolvers, MinresSolvesAnIndefiniteSystem) {
  const DirichletProblem problem = hemisphere_dirichlet(12);
  RowMajorSparse indefinite = problem.interior;
  const double shift = 0.5 * indefinite.diagonal().mean();  // Inside the spectrum.
  for (int k = 0; k < indefinite.rows(); ++k) indefinite.coeffRef(k, k) -= shift;
  const Eigen::MatrixXd reference = direct_solution(indefinite, problem.rhs);
  const auto matrix = gpu_->upload(indefinite);
  const auto b = gpu_->upload(problem.rhs);
  const auto x = gpu_->allocate(static_cast<int>(problem.rhs.rows()), 2);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-9;
  const SolveStats stats = gpu_->minres(*matrix, *b, *x, settings, {});
  EXPECT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_LE(relative_residual(indefinite, x->download(), problem.rhs),
            1e-9 + harmonia::testing::residual_rounding(indefinite, x->download(), problem.rhs));
  EXPECT_LE(relative_difference(x->download(), reference), 1e-6);
}

TEST_F(VulkanSolvers, SystemSolversOfTheMapsMatchTheDirectSolution) {
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;
  // Symmetric cotangent system: PCG. Non-symmetric mean value system: PCG on the normal equations.
  for (const WeightScheme scheme : {WeightScheme::cotangent, WeightScheme::mean_value}) {
    const DirichletProblem problem = hemisphere_dirichlet(10, scheme);
    const detail::MatrixKind kind = is_symmetric(scheme)
                                        ? detail::MatrixKind::symmetric_positive_definite
                                        : detail::MatrixKind::general;
    auto solver = detail::make_system_solver(*gpu_, kind, settings, {});
    const Eigen::SparseMatrix<double> a(problem.interior);
    solver->analyze(a);
    ASSERT_EQ(solver->factorize(a).status, Status::ok);
    EXPECT_EQ(solver->name(), is_symmetric(scheme) ? "pcg-multilevel"
                                                   : "pcg-multilevel-normal-equations");
    Eigen::MatrixXd x;
    const SolveStats stats = solver->solve(problem.rhs, x);
    EXPECT_EQ(stats.status, Status::ok) << to_string(scheme) << ": " << stats.message;
    EXPECT_LE(relative_difference(x, direct_solution(problem.interior, problem.rhs)), 1e-7)
        << to_string(scheme);
  }
}

// The multilevel V-cycle made of the device's own SpMV and vector kernels, refined in double:
// the direct solution in a few dozen iterations where Jacobi needs hundreds.
TEST_F(VulkanSolvers, MultilevelPcgMatchesTheDirectSolutionInFewIterations) {
  const DirichletProblem problem = hemisphere_dirichlet(40);
  const Eigen::MatrixXd reference = direct_solution(problem.interior, problem.rhs);
  const detail::AggregationHierarchy hierarchy{Eigen::SparseMatrix<double>(problem.interior)};
  ASSERT_GE(hierarchy.level_rows().size(), 2U);
  const auto cycle = gpu_->multilevel_preconditioner(hierarchy);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;
  const auto matrix = gpu_->upload(problem.interior);
  const auto b = gpu_->upload(problem.rhs);
  const auto x = gpu_->upload(Eigen::MatrixXd::Zero(problem.rhs.rows(), 2));
  const SolveStats stats = gpu_->preconditioned_pcg(*matrix, *cycle, *b, *x, settings, {});
  ASSERT_EQ(stats.status, Status::ok) << stats.message;
  const Eigen::MatrixXd solution = x->download();
  EXPECT_LE(relative_residual(problem.interior, solution, problem.rhs),
            1e-10 + harmonia::testing::residual_rounding(problem.interior, solution, problem.rhs));
  EXPECT_LE(relative_difference(solution, reference), 1e-8);
  SolveStats jacobi;
  (void)pcg(problem.interior, problem.rhs, Eigen::MatrixXd::Zero(problem.rhs.rows(), 2), settings,
            jacobi);
  ASSERT_EQ(jacobi.status, Status::ok) << jacobi.message;
  EXPECT_LE(stats.iterations, 50);
  EXPECT_LT(3 * stats.iterations, jacobi.iterations);
}

}  // namespace
}  // namespace harmonia::testing
