// SerialOpenMpRegions: the calling thread's OpenMP regions on that thread alone while CHOLMOD
// factorizes, the caller's setting restored afterwards, and no other thread affected.
#include <thread>

#include <gtest/gtest.h>

#include "fallback/direct_solvers.h"
#include "fallback/serial_openmp_regions.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"

namespace harmonia {
namespace {

using detail::SerialOpenMpRegions;

// Without OpenMP every region is serial and the guard changes nothing.
bool built_with_openmp() { return !SerialOpenMpRegions::serial_now(); }

TEST(SerialOpenMpRegions, RestoresTheCallersSettingWhenNested) {
  if (!built_with_openmp()) GTEST_SKIP() << "built without OpenMP";
  {
    const SerialOpenMpRegions outer;
    EXPECT_TRUE(SerialOpenMpRegions::serial_now());
    {
      const SerialOpenMpRegions inner;  // Already serial: restored to serial.
      EXPECT_TRUE(SerialOpenMpRegions::serial_now());
    }
    EXPECT_TRUE(SerialOpenMpRegions::serial_now());
  }
  EXPECT_FALSE(SerialOpenMpRegions::serial_now());
}

TEST(SerialOpenMpRegions, OtherThreadsDoNotSeeTheSetting) {
  if (!built_with_openmp()) GTEST_SKIP() << "built without OpenMP";
  const SerialOpenMpRegions serial_regions;
  bool seen_elsewhere = true;
  std::thread other([&seen_elsewhere] { seen_elsewhere = SerialOpenMpRegions::serial_now(); });
  other.join();
  EXPECT_TRUE(SerialOpenMpRegions::serial_now());
  EXPECT_FALSE(seen_elsewhere);
}

// A factorization leaves the calling thread as it found it, and solves correctly.
TEST(SerialOpenMpRegions, CholeskyFactorizationLeavesTheThreadsSettingAlone) {
  const Mesh mesh = planar_disk(12, 0.0);
  Eigen::SparseMatrix<double> matrix = laplacian(mesh, WeightScheme::cotangent);
  for (Eigen::Index v = 0; v < matrix.rows(); ++v) matrix.coeffRef(v, v) += 1.0;  // SPD.
  const bool before = SerialOpenMpRegions::serial_now();
  const std::unique_ptr<detail::SparseSystemSolver> solver = detail::make_cholesky_solver();
  solver->analyze(matrix);
  ASSERT_EQ(solver->factorize(matrix).status, Status::ok);
  EXPECT_EQ(SerialOpenMpRegions::serial_now(), before);
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Ones(matrix.rows(), 1);
  Eigen::MatrixXd solution;
  ASSERT_EQ(solver->solve(rhs, solution).status, Status::ok);
  EXPECT_LT((matrix * solution - rhs).norm(), 1e-10 * rhs.norm());
}

}  // namespace
}  // namespace harmonia
