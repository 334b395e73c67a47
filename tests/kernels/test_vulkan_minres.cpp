// The fused device MINRES (kernels/minres.h, VulkanBackend::minres) on lavapipe with validation:
// against a direct solve and the CPU MINRES (CpuBackend, the Eigen twin) on a mesh saddle point
// [D G^T; G 0] and a random symmetric indefinite matrix, on an SPD Laplacian, on a singular but
// consistent (Neumann) Laplacian; warm start, iteration cap, zero right-hand side, cancellation,
// bit-identical results for every check interval, the residual estimate |phibar| against the
// true residual, the submission count (k iterations share one submission), and the fp64 kernels
// to 1e-11.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <utility>
#include <vector>

#include "backend/backend.h"
#include "fallback/cpu_backend.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "kernels/context_impl.h"
#include "kernels/float64_test_context.h"
#include "kernels/kernel_test_data.h"
#include "kernels/minres.h"
#include "kernels/vulkan_backend.h"
#include "support/conditioning.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using detail::IterativeSettings;
using detail::SolveStats;
using vulkan::detail::VulkanBackend;

// The mixed (flux, potential) system of a resistor network on hemisphere(rings): edge fluxes f
// and vertex potentials p with D f + G^T p = g, G f = h, where D holds the edge lengths and G is
// the vertex-edge incidence without vertex 0 (grounded, so the system is nonsingular). The
// matrix [D G^T; G 0] is symmetric indefinite: #edges positive and #vertices - 1 negative
// eigenvalues.
RowMajorSparse mesh_saddle_point(int rings) {
  const Mesh mesh = hemisphere(rings);
  std::set<std::pair<int, int>> edges;
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces(f, k), b = mesh.faces(f, (k + 1) % 3);
      edges.emplace(std::min(a, b), std::max(a, b));
    }
  const int m = static_cast<int>(edges.size()), n = mesh.vertex_count();
  std::vector<Eigen::Triplet<double>> entries;
  int e = 0;
  for (const auto& [a, b] : edges) {
    entries.emplace_back(e, e, (mesh.vertices.row(a) - mesh.vertices.row(b)).norm());
    for (const auto& [vertex, sign] : {std::pair{a, 1.0}, std::pair{b, -1.0}}) {
      if (vertex == 0) continue;
      entries.emplace_back(m + vertex - 1, e, sign);
      entries.emplace_back(e, m + vertex - 1, sign);
    }
    ++e;
  }
  RowMajorSparse matrix(m + n - 1, m + n - 1);
  matrix.setFromTriplets(entries.begin(), entries.end());
  matrix.makeCompressed();
  return matrix;
}

// R + R^T with a diagonal of alternating sign and magnitude in [3, 4]: symmetric indefinite and
// well conditioned.
RowMajorSparse random_symmetric_indefinite(int rows, std::uint32_t seed) {
  const RowMajorSparse r = random_sparse(rows, rows, 3, seed);
  RowMajorSparse matrix = RowMajorSparse(r.transpose()) + r;
  const Eigen::MatrixXd shifts = random_block(rows, 1, seed + 1);
  for (int k = 0; k < rows; ++k)
    matrix.coeffRef(k, k) += (k % 2 == 0 ? 1.0 : -1.0) * (3.5 + 0.5 * shifts(k, 0));
  matrix.makeCompressed();
  return matrix;
}

// Counts of positive and negative eigenvalues (dense; small matrices only).
std::pair<int, int> inertia(const RowMajorSparse& a) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver{Eigen::MatrixXd(a)};
  const Eigen::VectorXd values = solver.eigenvalues();
  return {static_cast<int>((values.array() > 1e-9).count()),
          static_cast<int>((values.array() < -1e-9).count())};
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

// Runs `backend`'s MINRES from `start`; returns the solution.
Eigen::MatrixXd minres(detail::Backend& backend, const RowMajorSparse& a,
                       const Eigen::MatrixXd& rhs, const Eigen::MatrixXd& start,
                       const IterativeSettings& settings, SolveStats& stats,
                       const ProgressCallback& progress = {}) {
  const auto matrix = backend.upload(a);
  const auto b = backend.upload(rhs);
  const auto x = backend.upload(start);
  stats = backend.minres(*matrix, *b, *x, settings, progress);
  return x->download();
}

class VulkanMinres : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(vulkan_test_context());
  }
  Eigen::MatrixXd solve(const RowMajorSparse& a, const Eigen::MatrixXd& rhs,
                        const IterativeSettings& settings, SolveStats& stats,
                        const ProgressCallback& progress = {}) {
    return minres(*gpu_, a, rhs, Eigen::MatrixXd::Zero(rhs.rows(), rhs.cols()), settings, stats,
                  progress);
  }
  std::unique_ptr<VulkanBackend> gpu_;
};

TEST_F(VulkanMinres, SolvesAMeshSaddlePointLikeTheDirectSolverAndTheCpu) {
  const RowMajorSparse a = mesh_saddle_point(6);
  const auto [positive, negative] = inertia(a);
  ASSERT_GT(negative, 10);  // Indefinite, and nonsingular:
  ASSERT_EQ(positive + negative, a.rows());
  const Eigen::MatrixXd rhs = random_block(static_cast<int>(a.rows()), 2, 7);
  const Eigen::MatrixXd reference = direct_solution(a, rhs);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;
  SolveStats stats;
  const Eigen::MatrixXd x = solve(a, rhs, settings, stats);
  ASSERT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_GT(stats.iterations, 20);
  EXPECT_LE(relative_residual(a, x, rhs),
            1e-10 + harmonia::testing::residual_rounding(a, x, rhs));
  EXPECT_NEAR(relative_residual(a, x, rhs), stats.relative_residual,
              harmonia::testing::residual_rounding(a, x, rhs));
  EXPECT_LE(relative_difference(x, reference), 1e-8);

  detail::CpuBackend cpu;
  SolveStats cpu_stats;
  const Eigen::MatrixXd cpu_x =
      minres(cpu, a, rhs, Eigen::MatrixXd::Zero(rhs.rows(), 2), settings, cpu_stats);
  ASSERT_EQ(cpu_stats.status, Status::ok) << cpu_stats.message;
  EXPECT_LE(relative_difference(x, cpu_x), 1e-8);
}

TEST_F(VulkanMinres, SolvesARandomSymmetricIndefiniteSystemLikeTheCpu) {
  const RowMajorSparse a = random_symmetric_indefinite(301, 11);
  const auto [positive, negative] = inertia(a);
  ASSERT_GT(positive, 50);
  ASSERT_GT(negative, 50);
  const Eigen::MatrixXd rhs = random_block(301, 2, 12);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;
  SolveStats stats;
  const Eigen::MatrixXd x = solve(a, rhs, settings, stats);
  ASSERT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_LE(relative_residual(a, x, rhs),
            1e-10 + harmonia::testing::residual_rounding(a, x, rhs));
  EXPECT_LE(relative_difference(x, direct_solution(a, rhs)), 1e-8);
  detail::CpuBackend cpu;
  SolveStats cpu_stats;
  const Eigen::MatrixXd cpu_x =
      minres(cpu, a, rhs, Eigen::MatrixXd::Zero(301, 2), settings, cpu_stats);
  ASSERT_EQ(cpu_stats.status, Status::ok) << cpu_stats.message;
  EXPECT_LE(relative_difference(x, cpu_x), 1e-8);
}

TEST_F(VulkanMinres, SolvesAnSpdLaplacian) {
  const RowMajorSparse a = hemisphere_laplacian(14);
  const Eigen::MatrixXd rhs = a * random_block(static_cast<int>(a.rows()), 2, 3);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-9;
  SolveStats stats;
  const Eigen::MatrixXd x = solve(a, rhs, settings, stats);
  ASSERT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_LE(relative_residual(a, x, rhs),
            1e-9 + harmonia::testing::residual_rounding(a, x, rhs));
  EXPECT_LE(relative_difference(x, direct_solution(a, rhs)), 1e-5);
}

TEST_F(VulkanMinres, SolvesASingularButConsistentSystem) {
  // The Neumann cotangent Laplacian: constants span its null space; b = L y is in its range.
  const RowMajorSparse a(laplacian(hemisphere(10), WeightScheme::cotangent));
  const Eigen::MatrixXd y = random_block(static_cast<int>(a.rows()), 1, 21);
  const Eigen::MatrixXd rhs = a * y;
  IterativeSettings settings;
  settings.relative_tolerance = 1e-9;
  SolveStats stats;
  const Eigen::MatrixXd x = solve(a, rhs, settings, stats);
  ASSERT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_LE(relative_residual(a, x, rhs),
            1e-9 + harmonia::testing::residual_rounding(a, x, rhs));
  // The solution is y up to a constant.
  const Eigen::VectorXd centred_x = x.col(0).array() - x.col(0).mean();
  const Eigen::VectorXd centred_y = y.col(0).array() - y.col(0).mean();
  EXPECT_LE(relative_difference(centred_x, centred_y), 1e-6);
}

TEST_F(VulkanMinres, WarmStartAndIterationCap) {
  const RowMajorSparse a = mesh_saddle_point(5);
  const Eigen::MatrixXd rhs = random_block(static_cast<int>(a.rows()), 2, 31);
  const Eigen::MatrixXd reference = direct_solution(a, rhs);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-9;
  SolveStats stats;
  // Started at the solution: nothing to do, x untouched.
  Eigen::MatrixXd x = minres(*gpu_, a, rhs, reference, settings, stats);
  EXPECT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_EQ(stats.iterations, 0);
  EXPECT_EQ(x, reference);
  // Started near the solution: fewer iterations than from zero.
  SolveStats cold;
  (void)solve(a, rhs, settings, cold);
  ASSERT_EQ(cold.status, Status::ok) << cold.message;
  const Eigen::MatrixXd near = reference + 1e-4 * random_block(static_cast<int>(a.rows()), 2, 32);
  x = minres(*gpu_, a, rhs, near, settings, stats);
  EXPECT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_LE(relative_residual(a, x, rhs),
            1e-9 + harmonia::testing::residual_rounding(a, x, rhs));
  EXPECT_LT(stats.iterations, cold.iterations);
  // Capped: not converged, honest residual, at most the cap.
  settings.max_iterations = 5;
  x = solve(a, rhs, settings, stats);
  EXPECT_EQ(stats.status, Status::not_converged);
  EXPECT_LE(stats.iterations, 5);
  EXPECT_GT(stats.relative_residual, 1e-9);
  EXPECT_NEAR(relative_residual(a, x, rhs), stats.relative_residual,
              harmonia::testing::residual_rounding(a, x, rhs));
  EXPECT_NE(stats.message.find("minres"), std::string::npos) << stats.message;
  EXPECT_NE(stats.message.find("stopped after"), std::string::npos) << stats.message;
}

TEST_F(VulkanMinres, ZeroRightHandSideGivesZeroAndTheOtherColumnConverges) {
  const RowMajorSparse a = random_symmetric_indefinite(97, 41);
  Eigen::MatrixXd rhs = random_block(97, 2, 42);
  rhs.col(0).setZero();
  IterativeSettings settings;
  SolveStats stats;
  const Eigen::MatrixXd x =
      minres(*gpu_, a, rhs, Eigen::MatrixXd::Ones(97, 2), settings, stats);
  ASSERT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_EQ(x.col(0).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LE(relative_residual(a, x.col(1), rhs.col(1)),
            1e-10 + harmonia::testing::residual_rounding(a, x.col(1), rhs.col(1)));
}

TEST_F(VulkanMinres, IsBitIdenticalRunToRunAndForEveryCheckInterval) {
  const RowMajorSparse a = mesh_saddle_point(5);
  Eigen::MatrixXd rhs = random_block(static_cast<int>(a.rows()), 2, 51);
  rhs.col(1) *= 1e-3;  // The columns converge at different iterations.
  IterativeSettings settings;
  settings.relative_tolerance = 1e-8;
  SolveStats first, second, every_iteration;
  const Eigen::MatrixXd x1 = solve(a, rhs, settings, first);
  const Eigen::MatrixXd x2 = solve(a, rhs, settings, second);
  settings.check_every = 1;  // Converged columns are frozen on the device.
  const Eigen::MatrixXd x3 = solve(a, rhs, settings, every_iteration);
  ASSERT_EQ(first.status, Status::ok) << first.message;
  const auto bytes = sizeof(double) * static_cast<std::size_t>(x1.size());
  EXPECT_EQ(std::memcmp(x1.data(), x2.data(), bytes), 0);
  EXPECT_EQ(std::memcmp(x1.data(), x3.data(), bytes), 0);
  EXPECT_EQ(first.iterations, second.iterations);
  EXPECT_EQ(first.iterations, every_iteration.iterations);
  EXPECT_EQ(first.relative_residual, every_iteration.relative_residual);
}

TEST_F(VulkanMinres, CancelsFromTheProgressCallback) {
  const RowMajorSparse a = mesh_saddle_point(6);
  const Eigen::MatrixXd rhs = random_block(static_cast<int>(a.rows()), 2, 61);
  int calls = 0;
  SolveStats stats;
  (void)solve(a, rhs, {}, stats, [&calls](const Progress& progress) {
    EXPECT_EQ(progress.stage, "minres");
    return ++calls < 2;
  });
  EXPECT_EQ(stats.status, Status::cancelled);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(stats.iterations, 2 * IterativeSettings{}.check_every);
}

// Runs the device MINRES directly (no refinement) on the backend's context.
struct DirectRun {
  vulkan::detail::DeviceMinresResult result;
  Eigen::MatrixXd x;
  std::uint64_t submissions = 0;
};
DirectRun run_direct(VulkanBackend& backend, const RowMajorSparse& a, const Eigen::MatrixXd& rhs,
                     double relative_tolerance, int max_iterations, int check_every) {
  vulkan::Context::Impl& context = backend.context().impl();
  const auto matrix = backend.upload(a);
  const auto b = backend.upload(rhs);
  const auto x = backend.allocate(static_cast<int>(rhs.rows()), static_cast<int>(rhs.cols()));
  const Eigen::VectorXd thresholds =
      relative_tolerance * rhs.colwise().norm().transpose().array();
  DirectRun run;
  const std::uint64_t before = context.submission_count();
  run.result = vulkan::detail::run_device_minres(
      context, dynamic_cast<const vulkan::detail::VulkanMatrix&>(*matrix),
      dynamic_cast<const vulkan::detail::VulkanVectors&>(*b),
      dynamic_cast<vulkan::detail::VulkanVectors&>(*x), thresholds, max_iterations, check_every,
      {}, 0, max_iterations);
  run.submissions = context.submission_count() - before;
  run.x = x->download();
  return run;
}

TEST_F(VulkanMinres, KIterationsShareOneSubmission) {
  const RowMajorSparse a = mesh_saddle_point(6);
  const Eigen::MatrixXd rhs = random_block(static_cast<int>(a.rows()), 2, 71);
  const bool unified = gpu_->context().device().unified_memory;
  for (const int k : {1, 8, 32}) {
    const DirectRun run = run_direct(*gpu_, a, rhs, 1e-5, 2000, k);
    ASSERT_EQ(run.result.failure, vulkan::detail::MinresFailure::none);
    ASSERT_GT(run.result.iterations, 64);
    const std::uint64_t batches = (run.result.iterations + k - 1) / k;
    // One submission starts the solve and one runs each batch of k iterations (lavapipe has
    // unified memory; elsewhere the staging copies of the flags' read-backs come on top).
    if (unified)
      EXPECT_EQ(run.submissions, 1 + batches) << "k = " << k;
    else
      EXPECT_LE(run.submissions, 2 * (1 + batches) + 2) << "k = " << k;
  }
  // Through the backend (with refinement): far fewer submissions with k = 16 than with k = 1.
  const auto count = [&](int k) {
    IterativeSettings settings;
    settings.check_every = k;
    SolveStats stats;
    const std::uint64_t before = gpu_->context().impl().submission_count();
    (void)solve(a, rhs, settings, stats);
    EXPECT_EQ(stats.status, Status::ok) << stats.message;
    return std::pair{gpu_->context().impl().submission_count() - before, stats.iterations};
  };
  const auto [every, iterations] = count(1);
  const auto [batched, same_iterations] = count(16);
  EXPECT_EQ(iterations, same_iterations);
  EXPECT_GE(every, static_cast<std::uint64_t>(iterations));
  EXPECT_LE(batched * 8, every);
}

TEST_F(VulkanMinres, ResidualEstimateTracksTheTrueResidualInFloat32) {
  const RowMajorSparse a = random_symmetric_indefinite(211, 81);
  const Eigen::MatrixXd rhs = random_block(211, 2, 82);
  const DirectRun run = run_direct(*gpu_, a, rhs, 0.0, 12, 4);  // Stops at the cap.
  EXPECT_EQ(run.result.iterations, 12);
  for (int c = 0; c < 2; ++c) {
    const double truth = (rhs.col(c) - a * run.x.col(c)).norm();
    EXPECT_LT(truth, 0.9 * rhs.col(c).norm());  // Progress was made ...
    EXPECT_NEAR(run.result.residual_estimates[c], truth, 1e-4 * rhs.col(c).norm());  // ... and seen.
  }
}

class VulkanMinresFloat64 : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_FLOAT64_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(float64_test_context(), DevicePrecision::float64);
  }
  std::unique_ptr<VulkanBackend> gpu_;
};

TEST_F(VulkanMinresFloat64, ReachesOneHundredBillionthOnIndefiniteSystems) {
  detail::CpuBackend cpu;
  for (const RowMajorSparse& a : {mesh_saddle_point(6), random_symmetric_indefinite(301, 91)}) {
    const Eigen::MatrixXd rhs = random_block(static_cast<int>(a.rows()), 2, 92);
    IterativeSettings settings;
    settings.relative_tolerance = 1e-11;
    SolveStats stats;
    const Eigen::MatrixXd zeros = Eigen::MatrixXd::Zero(rhs.rows(), 2);
    const Eigen::MatrixXd x = minres(*gpu_, a, rhs, zeros, settings, stats);
    ASSERT_EQ(stats.status, Status::ok) << stats.message;
    EXPECT_LE(relative_residual(a, x, rhs),
            1e-11 + harmonia::testing::residual_rounding(a, x, rhs));
    EXPECT_LE(relative_difference(x, direct_solution(a, rhs)), 1e-9);
    // The device iterates like the CPU MINRES in double (same recurrences, same arithmetic up to
    // the order of the sums).
    SolveStats cpu_stats;
    const Eigen::MatrixXd cpu_x = minres(cpu, a, rhs, zeros, settings, cpu_stats);
    ASSERT_EQ(cpu_stats.status, Status::ok) << cpu_stats.message;
    EXPECT_NEAR(stats.iterations, cpu_stats.iterations, 0.1 * cpu_stats.iterations + 2);
    EXPECT_LE(relative_difference(x, cpu_x), 1e-9);
  }
}

TEST_F(VulkanMinresFloat64, ResidualEstimateMatchesTheTrueResidual) {
  const RowMajorSparse a = mesh_saddle_point(5);
  const Eigen::MatrixXd rhs = random_block(static_cast<int>(a.rows()), 2, 93);
  const DirectRun run = run_direct(*gpu_, a, rhs, 0.0, 30, 8);
  EXPECT_EQ(run.result.iterations, 30);
  for (int c = 0; c < 2; ++c) {
    const double truth = (rhs.col(c) - a * run.x.col(c)).norm();
    EXPECT_LT(truth, 0.9 * rhs.col(c).norm());
    EXPECT_NEAR(run.result.residual_estimates[c], truth, 1e-12 * rhs.col(c).norm());
  }
}

}  // namespace
}  // namespace harmonia::testing
