// The batched first round of linear ABF (abf/linear_abf_batch.h) on the device
// (BackendChoice::vulkan: lavapipe with the validation layer on, every validation message a
// failure) against the CPU backend: the same meshes' angles within the bound the residuals each
// reached and the reduced systems' conditioning allow, the same validity; and the texture atlas
// on the device, whose initial charts are flattened through one block PCG per batch: a valid
// atlas with the CPU atlas' charts.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "abf/linear_abf_batch.h"
#include "fallback/cpu_backend.h"
#include "harmonia/io.h"
#include "harmonia/linear_abf.h"
#include "harmonia/procedural.h"
#include "harmonia/texture_atlas.h"
#include "harmonia/topology.h"
#include "solve/backend_selection.h"
#include "support/angle_test_meshes.h"
#include "support/linear_abf_bounds.h"
#include "support/test_support.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

SolverOptions vulkan_solver() {
  SolverOptions solver;
  solver.backend = BackendChoice::vulkan;
  solver.vulkan_context = vulkan_test_context();
  return solver;
}

// Two triangles: a disk without interior vertices, whose block of the batch is empty.
Mesh quad() {
  Mesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0.2, 1, 1, 0, 0, 1, 0.1;
  mesh.faces.resize(2, 3);
  mesh.faces << 0, 1, 2, 0, 2, 3;
  return mesh;
}

// Curved disks of different sizes, disks whose systems have nothing to solve (a planar and a
// developable one: zero right-hand sides; a quad: an empty block), and a small corpus disk.
std::vector<std::pair<std::string, Mesh>> disks() {
  std::vector<std::pair<std::string, Mesh>> meshes;
  meshes.emplace_back("hemisphere(8)", hemisphere(8));
  meshes.emplace_back("spiked disk", spiked_disk(5, 0.6));
  meshes.emplace_back("hemisphere(4)", hemisphere(4));
  meshes.emplace_back("tilted planar disk", tilted_planar_disk());
  meshes.emplace_back("developable strip", developable_strip(12, 5, 3.0, 1.0, 0.8));
  meshes.emplace_back("quad", quad());
  const std::filesystem::path snail = shared_data_dir() / "disk" / "snail.obj";
  if (std::filesystem::exists(snail)) meshes.emplace_back("snail", read_mesh(snail));
  return meshes;
}

std::vector<const Mesh*> pointers(const std::vector<std::pair<std::string, Mesh>>& meshes) {
  std::vector<const Mesh*> list;
  for (const auto& entry : meshes) list.push_back(&entry.second);
  return list;
}

TEST(VulkanLinearAbfBatch, MatchesTheCpuBackend) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto meshes = disks();
  LinearAbfOptions options;
  options.rounds = 1;
  std::string why;
  const std::unique_ptr<detail::Backend> gpu = detail::make_backend(vulkan_solver(), &why);
  ASSERT_NE(gpu, nullptr) << why;
  ASSERT_EQ(gpu->kind(), BackendKind::vulkan);
  detail::CpuBackend cpu;
  const auto on_gpu = detail::linear_abf_first_rounds(pointers(meshes), options, *gpu);
  const auto on_cpu = detail::linear_abf_first_rounds(pointers(meshes), options, cpu);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const auto& [name, mesh] = meshes[i];
    SCOPED_TRACE(name);
    ASSERT_TRUE(on_cpu[i].has_value());
    // The device's fp32 block PCG, refined in double per block, reaches the default tolerance
    // (or stalls within linear ABF's accepted residual): the round is final there too.
    ASSERT_TRUE(on_gpu[i].has_value());
    const AngleMapResult& device = *on_gpu[i];
    const AngleMapResult& host = *on_cpu[i];
    ASSERT_TRUE(device.report.ok()) << device.report.message;
    EXPECT_EQ(device.report.backend, BackendKind::vulkan);
    EXPECT_EQ(device.report.rounds, 1);
    EXPECT_NE(device.report.solver.find("block-pcg"), std::string::npos) << device.report.solver;
    EXPECT_NE(device.report.solver.find(std::to_string(meshes.size()) + " meshes"),
              std::string::npos)
        << device.report.solver;
    // Both are within their own residual's bound of the exact solution of the reduced system:
    // the angles within the sum (the device's residual is what the refinement reached, the fp32
    // part only decides how many refinement steps that took).
    const double device_residual =
        std::max(options.solver_options.tolerance, device.report.residual);
    const double bound =
        first_round_angle_bound(mesh, device_residual + options.solver_options.tolerance);
    EXPECT_LE((device.angles - host.angles).norm(), bound);
    EXPECT_EQ(device.report.flipped_triangles, 0);
    EXPECT_EQ(device.report.flipped_triangles, host.report.flipped_triangles);
    EXPECT_EQ(device.report.degenerate_triangles, host.report.degenerate_triangles);
    EXPECT_EQ(device.report.boundary_self_intersections, 0);
  }
  EXPECT_EQ(vulkan_validation_messages(), 0);
}

// A batch with nothing to solve on the device: only empty blocks, or no rows at all.
TEST(VulkanLinearAbfBatch, EmptyBlocksNeedNoSolve) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  std::string why;
  const std::unique_ptr<detail::Backend> gpu = detail::make_backend(vulkan_solver(), &why);
  ASSERT_NE(gpu, nullptr) << why;
  const Mesh a = quad(), b = quad(), planar = tilted_planar_disk();
  LinearAbfOptions options;
  options.solver_options.backend = BackendChoice::cpu;
  for (const std::vector<const Mesh*>& meshes :
       {std::vector<const Mesh*>{&a, &b}, std::vector<const Mesh*>{&a, &planar, &b}}) {
    const auto results = detail::linear_abf_first_rounds(meshes, options, *gpu);
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      ASSERT_TRUE(results[i].has_value());
      ASSERT_TRUE(results[i]->report.ok()) << results[i]->report.message;
      EXPECT_EQ(results[i]->report.iterations, 0);
      const AngleMapResult single = linear_abf(*meshes[i], options);
      EXPECT_LE((results[i]->angles - single.angles).norm(),
                first_round_angle_bound(*meshes[i], options.solver_options.tolerance));
    }
  }
  EXPECT_EQ(vulkan_validation_messages(), 0);
}

// A chart as it lies in the atlas: one vertex per surface vertex and UV position, at the surface
// vertex's 3D position (tests/atlas/test_texture_atlas.cpp checks its disks the same way).
Mesh laid_out_chart(const Mesh& mesh, const TextureAtlas& atlas, const AtlasChart& chart) {
  std::map<std::tuple<int, double, double>, int> vertex_of;
  std::vector<Eigen::Vector3d> positions;
  Mesh laid_out;
  laid_out.faces.resize(static_cast<Eigen::Index>(chart.faces.size()), 3);
  for (std::size_t i = 0; i < chart.faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int f = chart.faces[i];
      const int vertex = mesh.faces(f, k);
      const auto key =
          std::make_tuple(vertex, atlas.corner_uv(f, 2 * k), atlas.corner_uv(f, 2 * k + 1));
      const auto [entry, added] = vertex_of.emplace(key, static_cast<int>(positions.size()));
      if (added) positions.emplace_back(mesh.vertices.row(vertex));
      laid_out.faces(static_cast<Eigen::Index>(i), k) = entry->second;
    }
  laid_out.vertices.resize(static_cast<Eigen::Index>(positions.size()), 3);
  for (std::size_t v = 0; v < positions.size(); ++v)
    laid_out.vertices.row(static_cast<Eigen::Index>(v)) = positions[v];
  return laid_out;
}

void expect_valid_atlas(const Mesh& mesh, const TextureAtlas& atlas) {
  ASSERT_TRUE(atlas.report.ok()) << atlas.report.message;
  ASSERT_EQ(atlas.chart_of_face.size(), static_cast<std::size_t>(mesh.faces.rows()));
  for (std::size_t c = 0; c < atlas.charts.size(); ++c) {
    std::string problem;
    EXPECT_EQ(check_disk(laid_out_chart(mesh, atlas, atlas.charts[c]), &problem), Status::ok)
        << "chart " << c << ": " << problem;
  }
  for (const int chart : atlas.chart_of_face) EXPECT_GE(chart, 0);
  EXPECT_EQ(atlas.metrics.dropped_faces, 0);
  EXPECT_EQ(atlas.metrics.flipped_triangles, 0);
  EXPECT_EQ(atlas.metrics.mirrored_charts, 0);
  EXPECT_EQ(atlas.metrics.overlapping_texels, 0);
  EXPECT_EQ(atlas.metrics.boundary_crossings, 0);
}

// Small closed surfaces: the segmentation's charts go through the device in one batch, and the
// halves of those split (beyond the stretch limit) in the next wave's batch; those whose batched
// round is not final are flattened one by one, as on the CPU (spot has both kinds). On lavapipe
// spot's per-chart device solves take 2 to 5 s.
TEST(VulkanLinearAbfBatch, TextureAtlasOnTheDeviceMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  std::vector<std::pair<std::string, Mesh>> meshes;
  meshes.emplace_back("unit_sphere(2)", unit_sphere(2));
  const std::filesystem::path spot = shared_data_dir() / "closed" / "spot.obj";
  if (std::filesystem::exists(spot)) meshes.emplace_back("spot", read_mesh(spot));
  for (const auto& [name, mesh] : meshes) {
    SCOPED_TRACE(name);
    TextureAtlasOptions options;
    options.resolution = 512;
    options.solver.backend = BackendChoice::cpu;
    const TextureAtlas on_cpu = texture_atlas(mesh, options);
    expect_valid_atlas(mesh, on_cpu);
    EXPECT_EQ(on_cpu.report.solver.find("block-pcg"), std::string::npos) << on_cpu.report.solver;
    options.solver = vulkan_solver();
    const TextureAtlas on_gpu = texture_atlas(mesh, options);
    expect_valid_atlas(mesh, on_gpu);
    EXPECT_EQ(on_gpu.report.backend, BackendKind::vulkan);
    // "linear abf first rounds by block-pcg-jacobi (reduced) on the device: N charts in B
    // batch(es) over W wave(s) of splits, F final", with N > 0 and F > 0.
    const std::string& solver = on_gpu.report.solver;
    int batched = 0, batches = 0, waves = 0, final_rounds = 0;
    const std::size_t numbers = solver.find(": ");
    ASSERT_NE(solver.find("block-pcg"), std::string::npos) << solver;
    ASSERT_NE(numbers, std::string::npos) << solver;
    ASSERT_EQ(std::sscanf(solver.c_str() + numbers,
                          ": %d charts in %d batch(es) over %d wave(s) of splits, %d final",
                          &batched, &batches, &waves, &final_rounds),
              4)
        << solver;
    EXPECT_GT(batched, 0) << solver;
    EXPECT_GT(final_rounds, 0) << solver;
    EXPECT_GE(batches, waves) << solver;
    if (name == "unit_sphere(2)") {
      EXPECT_EQ(final_rounds, batched) << solver;
    }
    // The same charts: the device's angles differ from the CPU's by the solve's tolerance
    // (about 1e-10 in the angles, the test above), far from moving a verdict (a flip, a
    // crossing, the stretch limit 1.01).
    ASSERT_EQ(on_gpu.charts.size(), on_cpu.charts.size());
    for (std::size_t c = 0; c < on_gpu.charts.size(); ++c) {
      EXPECT_EQ(on_gpu.charts[c].faces, on_cpu.charts[c].faces) << "chart " << c;
      EXPECT_EQ(on_gpu.charts[c].method, on_cpu.charts[c].method) << "chart " << c;
      EXPECT_NEAR(on_gpu.charts[c].l2_stretch, on_cpu.charts[c].l2_stretch, 1e-6) << "chart " << c;
    }
  }
  EXPECT_EQ(vulkan_validation_messages(), 0);
}

}  // namespace
}  // namespace harmonia::testing
