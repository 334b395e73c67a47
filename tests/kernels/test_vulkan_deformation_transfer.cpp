// Deformation transfer on the Vulkan backend (lavapipe, with the Khronos validation layer) against
// the CPU: the same matches and the same transferred pose within 1e-5 of the diagonal, for both
// methods.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "harmonia/deformation_transfer.h"
#include "harmonia/procedural.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

TEST(VulkanTransfer, DeformationTransferMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const Mesh source = unit_sphere(3);
  Mesh target = source;
  for (Eigen::Index v = 0; v < target.vertices.rows(); ++v)
    target.vertices.row(v) *= 1.0 + 0.15 * std::sin(3.0 * target.vertices(v, 0) + 2.0 * target.vertices(v, 1));
  std::vector<MarkerPair> markers;
  for (const int v : {0, 5, 11, 17, 23, 31, 40, 52, 77, 101}) markers.push_back({v, v});
  Eigen::MatrixX3d pose = source.vertices;
  for (Eigen::Index v = 0; v < pose.rows(); ++v)
    pose.row(v) = (Eigen::AngleAxisd(0.7 * pose(v, 1), Eigen::Vector3d::UnitZ()) *
                   Eigen::Vector3d(pose.row(v)))
                      .transpose();
  const double diagonal =
      (target.vertices.colwise().maxCoeff() - target.vertices.colwise().minCoeff()).norm();
  for (const TransferMethod method : {TransferMethod::correspondence, TransferMethod::quaternion}) {
    DeformationTransferOptions options;
    options.method = method;
    options.solver.backend = BackendChoice::cpu;
    DeformationTransfer on_cpu(source, target, markers, options);
    options.solver.backend = BackendChoice::vulkan;
    options.solver.vulkan_context = vulkan_test_context();
    DeformationTransfer on_gpu(source, target, markers, options);
    ASSERT_TRUE(on_cpu.setup_report().ok()) << on_cpu.setup_report().message;
    ASSERT_TRUE(on_gpu.setup_report().ok()) << on_gpu.setup_report().message;
    EXPECT_EQ(on_gpu.setup_report().backend, BackendKind::vulkan);
    const TransferResult cpu = on_cpu.transfer(pose);
    const TransferResult gpu = on_gpu.transfer(pose);
    ASSERT_TRUE(cpu.report.ok()) << cpu.report.message;
    ASSERT_TRUE(gpu.report.ok()) << gpu.report.message;
    EXPECT_LE((gpu.positions - cpu.positions).rowwise().norm().maxCoeff(), 1e-5 * diagonal);
    EXPECT_EQ(gpu.report.flipped_triangles, cpu.report.flipped_triangles);
  }
}

}  // namespace
}  // namespace harmonia::testing
