// Spherical maps on the Vulkan backend (lavapipe, with the Khronos validation layer) against the
// CPU: the same steps taken, no triangle turned over, the same points within 1e-4.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "harmonia/procedural.h"
#include "harmonia/spherical_map.h"
#include "harmonia/spherical_metrics.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

// Closed meshes on which the cotangent maps of the rectangle do not fold, so that every solve is
// symmetric positive definite (conjugate gradients on the device; mean-value systems would go
// through the normal equations, correct but slow on a software device).
std::vector<std::pair<std::string, Mesh>> sphere_test_meshes() {
  std::vector<std::pair<std::string, Mesh>> meshes;
  meshes.emplace_back("unit_sphere(3)", unit_sphere(3));
  Mesh bumpy = unit_sphere(3);
  for (Eigen::Index v = 0; v < bumpy.vertices.rows(); ++v)
    bumpy.vertices.row(v) *= 1.0 + 0.1 * std::sin(2.0 * bumpy.vertices(v, 0) + 3.0 * bumpy.vertices(v, 2));
  bumpy.vertices.col(0) *= 1.5;
  meshes.emplace_back("bumpy ellipsoid", bumpy);
  return meshes;
}

TEST(VulkanMaps, SphericalMapMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  for (const auto& [name, mesh] : sphere_test_meshes()) {
    SphericalMapOptions options;
    options.weights = WeightScheme::cotangent;
    options.solver.backend = BackendChoice::cpu;
    const SphericalMapResult cpu = spherical_map(mesh, options);
    options.solver.backend = BackendChoice::vulkan;
    options.solver.vulkan_context = vulkan_test_context();
    const SphericalMapResult gpu = spherical_map(mesh, options);
    ASSERT_TRUE(cpu.report.ok()) << name << ": " << cpu.report.message;
    ASSERT_TRUE(gpu.report.ok()) << name << ": " << gpu.report.message;
    EXPECT_EQ(gpu.report.backend, BackendKind::vulkan) << name;
    for (const std::string& fallback : cpu.report.fallbacks)
      ASSERT_EQ(fallback.find("mean-value"), std::string::npos)
          << name << ": the test wants cotangent maps throughout (" << fallback << ")";
    EXPECT_EQ(gpu.report.fallbacks, cpu.report.fallbacks) << name;
    EXPECT_EQ(gpu.report.rounds, cpu.report.rounds) << name;
    EXPECT_EQ(gpu.north_pole, cpu.north_pole) << name;
    EXPECT_EQ(gpu.date_line, cpu.date_line) << name;
    const SphericalMetrics metrics = spherical_metrics(mesh, gpu.positions);
    EXPECT_EQ(metrics.flipped_triangles, 0) << name;
    EXPECT_EQ(metrics.degenerate_triangles, 0) << name;
    EXPECT_EQ(gpu.report.flipped_triangles, cpu.report.flipped_triangles) << name;
    // Points of the unit sphere: the difference is an angle, at most 1e-4 radians.
    EXPECT_LE((gpu.positions - cpu.positions).cwiseAbs().maxCoeff(), 1e-4) << name;
  }
}

}  // namespace
}  // namespace harmonia::testing
