// The maps with BackendChoice::vulkan (lavapipe) against the CPU backend: fixed-boundary
// cotangent and mean value maps, LSCM, quasi-harmonic and free-boundary maps of a corpus mesh and a procedural mesh agree within
// 1e-4 of the layout's extent (the fp32 device solve is refined in double) with the same flips;
// the free-boundary map assembles its operators on the device.
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <string>

#include "harmonia/fixed_boundary_map.h"
#include "harmonia/free_boundary_map.h"
#include "harmonia/io.h"
#include "harmonia/lscm.h"
#include "harmonia/procedural.h"
#include "harmonia/quasi_harmonic_map.h"
#include "harmonia/topology.h"
#include "kernels/context_impl.h"
#include "kernels/pipelines.h"
#include "kernels/triangle_assembly.h"
#include "kernels/triangle_calculus.h"
#include "kernels/vulkan_fresh_context.h"
#include "planar/boundary_pins.h"
#include "planar/lscm_energy.h"
#include "support/conditioning.h"
#include "support/test_support.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

// Largest UV difference relative to the extent of the CPU layout's bounding box.
double relative_uv_difference(const Eigen::MatrixX2d& uv, const Eigen::MatrixX2d& reference) {
  const double extent =
      (reference.colwise().maxCoeff() - reference.colwise().minCoeff()).maxCoeff();
  return (uv - reference).cwiseAbs().maxCoeff() / extent;
}

// A small corpus mesh, and a jittered procedural disk (the test runs without the corpus too).
std::vector<std::pair<std::string, Mesh>> test_meshes() {
  std::vector<std::pair<std::string, Mesh>> meshes;
  const std::filesystem::path woody = shared_data_dir() / "disk" / "woody.obj";
  if (std::filesystem::exists(woody)) meshes.emplace_back("woody", read_mesh(woody));
  meshes.emplace_back("hemisphere(14)", hemisphere(14));
  meshes.emplace_back("planar_disk(12, jitter 0.3)", planar_disk(12, 0.3));
  return meshes;
}

// Vulkan through the caller's context (the test device); no normalization, so that the
// comparison sees the solve and not a rotation chosen from a nearly isotropic layout.
SolverOptions vulkan_solver() {
  SolverOptions solver;
  solver.backend = BackendChoice::vulkan;
  solver.vulkan_context = vulkan_test_context();
  return solver;
}

TEST(VulkanMaps, FixedBoundaryCotangentMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  // The default tolerance (refinement in double) and one within plain fp32's reach.
  for (const double tolerance : {SolverOptions{}.tolerance, 1e-6}) {
    for (const auto& [name, mesh] : test_meshes()) {
      FixedBoundaryOptions options;
      options.weights = WeightScheme::cotangent;
      options.normalization = UvNormalization::none;
      options.solver.backend = BackendChoice::cpu;
      const MapResult cpu = fixed_boundary_map(mesh, options);
      options.solver = vulkan_solver();
      options.solver.tolerance = tolerance;
      const MapResult gpu = fixed_boundary_map(mesh, options);
      ASSERT_TRUE(cpu.report.ok()) << name << ": " << cpu.report.message;
      ASSERT_EQ(gpu.report.status, cpu.report.status) << name << ": " << gpu.report.message;
      EXPECT_EQ(gpu.report.backend, BackendKind::vulkan) << name;
      EXPECT_GT(gpu.report.iterations, 0) << name;
      EXPECT_LE(gpu.report.residual, tolerance) << name;
      EXPECT_LE(relative_uv_difference(gpu.uv, cpu.uv), 1e-4)
          << name << ", tolerance " << tolerance;
      EXPECT_EQ(gpu.report.flipped_triangles, cpu.report.flipped_triangles) << name;
    }
  }
}

// Mean value weights give a non-symmetric system: the device solves its normal equations.
TEST(VulkanMaps, FixedBoundaryMeanValueMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  for (const auto& [name, mesh] : test_meshes()) {
    FixedBoundaryOptions options;
    options.weights = WeightScheme::mean_value;
    options.normalization = UvNormalization::none;
    options.solver.backend = BackendChoice::cpu;
    const MapResult cpu = fixed_boundary_map(mesh, options);
    options.solver = vulkan_solver();
    const MapResult gpu = fixed_boundary_map(mesh, options);
    ASSERT_TRUE(cpu.report.ok()) << name << ": " << cpu.report.message;
    ASSERT_EQ(gpu.report.status, cpu.report.status) << name << ": " << gpu.report.message;
    EXPECT_EQ(gpu.report.backend, BackendKind::vulkan) << name;
    EXPECT_LE(relative_uv_difference(gpu.uv, cpu.uv), 1e-4) << name;
    EXPECT_EQ(gpu.report.flipped_triangles, 0) << name;
  }
}

TEST(VulkanMaps, LscmMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  for (const auto& [name, mesh] : test_meshes()) {
    LscmOptions options;
    options.normalization = UvNormalization::none;
    options.solver.backend = BackendChoice::cpu;
    const MapResult cpu = lscm(mesh, options);
    options.solver = vulkan_solver();
    const MapResult gpu = lscm(mesh, options);
    ASSERT_TRUE(cpu.report.ok()) << name << ": " << cpu.report.message;
    ASSERT_EQ(gpu.report.status, cpu.report.status) << name << ": " << gpu.report.message;
    EXPECT_EQ(gpu.report.backend, BackendKind::vulkan) << name;
    EXPECT_LE(relative_uv_difference(gpu.uv, cpu.uv), 1e-4) << name;
    EXPECT_EQ(gpu.report.flipped_triangles, cpu.report.flipped_triangles) << name;
  }
}

// With the backend left to harmonia (BackendChoice::automatic) on a device, a device solve that
// fails (here: an iteration cap far too low for the tolerance) is done again on the CPU, with a
// notice; asked for the device explicitly, the same solve fails and says so with its figures.
struct CpuRetryRuns {
  MapResult cpu, automatic, explicit_device;
};

// `method(mesh, options)` on the CPU, then on the test device with 2 iterations at most, chosen
// automatically and asked for.
template <typename Options, typename Method>
CpuRetryRuns cpu_retry_runs(const Mesh& mesh, Options options, Method method) {
  CpuRetryRuns runs;
  options.normalization = UvNormalization::none;
  options.solver.backend = BackendChoice::cpu;
  runs.cpu = method(mesh, options);
  options.solver = vulkan_solver();
  options.solver.backend = BackendChoice::automatic;
  options.solver.max_iterations = 2;
  runs.automatic = method(mesh, options);
  options.solver.backend = BackendChoice::vulkan;
  runs.explicit_device = method(mesh, options);
  return runs;
}

// The automatic run moved to the CPU once and said why; the explicit one failed with figures.
void expect_moved_and_refused(const CpuRetryRuns& runs) {
  ASSERT_TRUE(runs.cpu.report.ok()) << runs.cpu.report.message;
  expect_moved_to_the_cpu(runs.automatic.report);
  EXPECT_EQ(runs.automatic.report.fallbacks.size(), 1U);
  expect_refused_with_figures(runs.explicit_device.report);
}

TEST(VulkanMaps, AnAutomaticChoiceSolvesOnTheCpuWhereTheDeviceSolveFails) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  FixedBoundaryOptions options;
  options.weights = WeightScheme::cotangent;
  const CpuRetryRuns runs = cpu_retry_runs(hemisphere(14), options, [](const Mesh& mesh, const FixedBoundaryOptions& o) {
    return fixed_boundary_map(mesh, o);
  });
  expect_moved_and_refused(runs);
  // Both are direct solves of one matrix (in different orders): they agree to its condition
  // number (below 1e4 for this Dirichlet Laplacian of 1,300 rows) times the rounding of a solve.
  EXPECT_LE(relative_uv_difference(runs.automatic.uv, runs.cpu.uv), 1e4 * 64.0 * std::numeric_limits<double>::epsilon());
}

// The same for the coupled u-v system of LSCM (solve/uv_system_solver.h): on the device it is
// one Jacobi-PCG over u and v; after the move the CPU solves it its own way (a direct
// factorization), as a CPU run does.
TEST(VulkanMaps, AnAutomaticChoiceSolvesLscmOnTheCpuWhereTheDeviceSolveFails) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const Mesh mesh = hemisphere(14);
  const CpuRetryRuns runs = cpu_retry_runs(mesh, LscmOptions{}, [](const Mesh& m, const LscmOptions& o) { return lscm(m, o); });
  expect_moved_and_refused(runs);
  // The CPU's own way (its solver's name, then why), and the same direct solve of the same
  // system as the CPU run's: equal up to the rounding of a backward-stable solve amplified by
  // the pinned system's condition number (computed here).
  EXPECT_EQ(runs.automatic.report.solver, runs.cpu.report.solver + " (after the device's pcg-jacobi failed)");
  const std::vector<int> loop = boundary_loops(mesh).front();
  const auto [first_pin, second_pin] = detail::farthest_boundary_pair(mesh, loop);
  const int vertices = mesh.vertex_count();
  const SpdSpectrum spectrum = spd_spectrum(without_rows_and_columns(
      detail::lscm_quadratic_form(mesh, loop), {first_pin, second_pin, vertices + first_pin, vertices + second_pin}));
  const double condition = spectrum.condition() * SpdSpectrum::kEstimateMargin;
  EXPECT_LE(relative_uv_difference(runs.automatic.uv, runs.cpu.uv), condition * 64.0 * std::numeric_limits<double>::epsilon());
}

TEST(VulkanMaps, QuasiHarmonicMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  for (const auto& [name, mesh] : test_meshes()) {
    QuasiHarmonicOptions options;
    options.normalization = UvNormalization::none;
    options.max_rounds = 3;
    options.solver.backend = BackendChoice::cpu;
    const QuasiHarmonicResult cpu = quasi_harmonic_map(mesh, options);
    options.solver = vulkan_solver();
    const QuasiHarmonicResult gpu = quasi_harmonic_map(mesh, options);
    ASSERT_TRUE(cpu.report.ok()) << name << ": " << cpu.report.message;
    ASSERT_EQ(gpu.report.status, cpu.report.status) << name << ": " << gpu.report.message;
    EXPECT_EQ(gpu.report.backend, BackendKind::vulkan) << name;
    EXPECT_EQ(gpu.report.rounds, cpu.report.rounds) << name;
    EXPECT_LE(relative_uv_difference(gpu.uv, cpu.uv), 1e-4) << name;
    EXPECT_EQ(gpu.report.flipped_triangles, cpu.report.flipped_triangles) << name;
  }
}

TEST(VulkanMaps, FreeBoundaryMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  // Every step's solves (the circle map, the rotation fields, the two Poisson problems) run on the
  // device by conjugate gradients refined in double; the steps taken must be the same.
  for (const auto& [name, mesh] : test_meshes()) {
    for (const bool polish : {false, true}) {
      FreeBoundaryOptions options;
      options.normalization = UvNormalization::none;
      options.polish = polish;
      options.solver.backend = BackendChoice::cpu;
      const FreeBoundaryResult cpu = free_boundary_map(mesh, options);
      options.solver = vulkan_solver();
      const FreeBoundaryResult gpu = free_boundary_map(mesh, options);
      ASSERT_TRUE(cpu.report.ok()) << name << ": " << cpu.report.message;
      ASSERT_EQ(gpu.report.status, cpu.report.status) << name << ": " << gpu.report.message;
      EXPECT_EQ(gpu.report.backend, BackendKind::vulkan) << name;
      ASSERT_EQ(gpu.steps.size(), cpu.steps.size()) << name;
      for (std::size_t k = 0; k < cpu.steps.size(); ++k)
        EXPECT_EQ(gpu.steps[k].step, cpu.steps[k].step) << name << ", " << cpu.steps[k].name;
      EXPECT_LE(relative_uv_difference(gpu.uv, cpu.uv), 1e-4) << name;
      EXPECT_EQ(gpu.report.flipped_triangles, cpu.report.flipped_triangles) << name;
    }
  }
}

// The free-boundary map's operators are assembled by the triangle kernels and P1's load gathered
// by the corner kernels: on a context of its own, the map leaves their pipelines built (a pipeline
// is built the first time its kernel is recorded).
TEST(VulkanMaps, FreeBoundaryAssemblesOnTheDevice) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const std::shared_ptr<vulkan::Context> context = fresh_vulkan_context();
  vulkan::detail::PipelineLibrary& pipelines = *context->impl().pipelines;
  const vulkan::detail::KernelProgram* assembly_kernels[] = {
      &vulkan::detail::triangle_stiffness_program, &vulkan::detail::slot_gather_program,
      &vulkan::detail::corner_terms_program, &vulkan::detail::vertex_gather_program};
  for (const auto* program : assembly_kernels)
    ASSERT_FALSE(pipelines.built(*program)) << program->name << " before the map";
  FreeBoundaryOptions options;
  options.solver.backend = BackendChoice::vulkan;
  options.solver.vulkan_context = context;
  const FreeBoundaryResult result = free_boundary_map(hemisphere(10), options);
  ASSERT_TRUE(result.report.ok()) << result.report.message;
  for (const auto* program : assembly_kernels)
    EXPECT_TRUE(pipelines.built(*program)) << program->name;
}

}  // namespace
}  // namespace harmonia::testing
