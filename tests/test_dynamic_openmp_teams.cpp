// DynamicOpenMpTeams: dynamic OpenMP teams for the calling thread while CHOLMOD factorizes, the
// caller's setting restored afterwards, and no other thread affected.
#include <thread>

#include <gtest/gtest.h>

#include "fallback/direct_solvers.h"
#include "fallback/dynamic_openmp_teams.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"

namespace harmonia {
namespace {

using detail::DynamicOpenMpTeams;

bool built_with_openmp() {
  const DynamicOpenMpTeams teams;
  return DynamicOpenMpTeams::dynamic_now();
}

TEST(DynamicOpenMpTeams, RestoresTheCallersSettingWhetherOnOrOff) {
  if (!built_with_openmp()) GTEST_SKIP() << "built without OpenMP";
  ASSERT_FALSE(DynamicOpenMpTeams::dynamic_now());
  {
    const DynamicOpenMpTeams outer;
    EXPECT_TRUE(DynamicOpenMpTeams::dynamic_now());
    {
      const DynamicOpenMpTeams inner;  // Already on: restored to on.
      EXPECT_TRUE(DynamicOpenMpTeams::dynamic_now());
    }
    EXPECT_TRUE(DynamicOpenMpTeams::dynamic_now());
  }
  EXPECT_FALSE(DynamicOpenMpTeams::dynamic_now());
}

TEST(DynamicOpenMpTeams, OtherThreadsDoNotSeeTheSetting) {
  if (!built_with_openmp()) GTEST_SKIP() << "built without OpenMP";
  const DynamicOpenMpTeams teams;
  bool seen_elsewhere = true;
  std::thread other([&seen_elsewhere] { seen_elsewhere = DynamicOpenMpTeams::dynamic_now(); });
  other.join();
  EXPECT_TRUE(DynamicOpenMpTeams::dynamic_now());
  EXPECT_FALSE(seen_elsewhere);
}

// A factorization leaves the calling thread as it found it, and solves correctly.
TEST(DynamicOpenMpTeams, CholeskyFactorizationLeavesTheThreadsSettingAlone) {
  const Mesh mesh = planar_disk(12, 0.0);
  Eigen::SparseMatrix<double> matrix = laplacian(mesh, WeightScheme::cotangent);
  for (Eigen::Index v = 0; v < matrix.rows(); ++v) matrix.coeffRef(v, v) += 1.0;  // SPD.
  const bool before = DynamicOpenMpTeams::dynamic_now();
  const std::unique_ptr<detail::SparseSystemSolver> solver = detail::make_cholesky_solver();
  solver->analyze(matrix);
  ASSERT_EQ(solver->factorize(matrix).status, Status::ok);
  EXPECT_EQ(DynamicOpenMpTeams::dynamic_now(), before);
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Ones(matrix.rows(), 1);
  Eigen::MatrixXd solution;
  ASSERT_EQ(solver->solve(rhs, solution).status, Status::ok);
  EXPECT_LT((matrix * solution - rhs).norm(), 1e-10 * rhs.norm());
}

}  // namespace
}  // namespace harmonia
