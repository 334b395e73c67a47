// Surface editing on the Vulkan backend (lavapipe, with the Khronos validation layer) against the
// CPU: the fields and every frame of a two-handle edit (rotation, scale, translation) agree within
// 1e-5 of the bounding-box diagonal, one matrix upload serves every frame, no triangle turns over.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "harmonia/procedural.h"
#include "harmonia/surface_editor.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

std::vector<int> vertices_with(const Mesh& mesh, int axis, double low, double high) {
  std::vector<int> vertices;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, axis) > low && mesh.vertices(v, axis) < high) vertices.push_back(v);
  return vertices;
}

TEST(VulkanEditing, SurfaceEditorMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  Mesh bumpy = unit_sphere(3);
  for (Eigen::Index v = 0; v < bumpy.vertices.rows(); ++v)
    bumpy.vertices.row(v) *= 1.0 + 0.1 * std::sin(2.0 * bumpy.vertices(v, 0) + 3.0 * bumpy.vertices(v, 2));
  bumpy.vertices.col(1) *= 2.0;
  const double diagonal =
      (bumpy.vertices.colwise().maxCoeff() - bumpy.vertices.colwise().minCoeff()).norm();
  EditRegions regions;
  regions.fixed = vertices_with(bumpy, 1, -10.0, -1.5);
  regions.handles = {vertices_with(bumpy, 1, 1.6, 10.0), vertices_with(bumpy, 0, 0.9, 10.0)};
  SimilarityTransform turn, push;
  turn.rotation = Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitX());
  turn.center = Eigen::Vector3d(0.0, 1.6, 0.0);
  turn.scale = 1.2;
  push.translation = Eigen::Vector3d(0.3, 0.1, -0.2);

  SurfaceEditOptions options;
  options.solver.backend = BackendChoice::cpu;
  SurfaceEditor cpu(bumpy, regions, options);
  options.solver.backend = BackendChoice::vulkan;
  options.solver.vulkan_context = vulkan_test_context();
  SurfaceEditor gpu(bumpy, regions, options);
  ASSERT_TRUE(cpu.setup_report().ok()) << cpu.setup_report().message;
  ASSERT_TRUE(gpu.setup_report().ok()) << gpu.setup_report().message;
  EXPECT_EQ(gpu.setup_report().backend, BackendKind::vulkan);
  // Fields in [0, 1]: the same to the solver's tolerance (1e-10 relative residual, refined in double).
  EXPECT_LE((gpu.handle_fields() - cpu.handle_fields()).cwiseAbs().maxCoeff(), 1e-6);
  for (int frame = 1; frame <= 3; ++frame) {
    const double t = frame / 3.0;
    const std::vector<SimilarityTransform> transforms = {turn.partial(t), push.partial(t)};
    const SurfaceEditResult on_cpu = cpu.deform(transforms);
    const SurfaceEditResult on_gpu = gpu.deform(transforms);
    ASSERT_TRUE(on_cpu.report.ok()) << on_cpu.report.message;
    ASSERT_TRUE(on_gpu.report.ok()) << on_gpu.report.message;
    EXPECT_EQ(on_gpu.report.backend, BackendKind::vulkan);
    EXPECT_EQ(on_gpu.report.flipped_triangles, 0) << "frame " << frame;
    EXPECT_EQ(on_cpu.report.flipped_triangles, 0) << "frame " << frame;
    EXPECT_LE((on_gpu.positions - on_cpu.positions).rowwise().norm().maxCoeff(), 1e-5 * diagonal)
        << "frame " << frame;
  }
  EXPECT_EQ(gpu.factorization_count(), 1);
}

}  // namespace
}  // namespace harmonia::testing
