// Device failures provoked through the context's fault injection seam (kernels/fault_injection.h):
// out of device memory, device loss at a submission, a hung submission. Each one is a
// harmonia::Error with Status::device_failure and a clear message, never a crash or a hang; a
// lost device stays lost, BackendChoice::automatic then falls back to the CPU, and the context
// is still destroyable. A buffer beyond maxStorageBufferRange names the limit.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <string>

#include "harmonia/fixed_boundary_map.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "kernels/context_impl.h"
#include "kernels/kernel_test_data.h"
#include "kernels/vulkan_backend.h"
#include "kernels/vulkan_fresh_context.h"
#include "solve/backend_selection.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using vulkan::detail::VulkanBackend;

// The Error an action throws (status and message); ok and empty when it throws none.
std::pair<Status, std::string> error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& error) {
    return {error.status(), error.what()};
  }
  return {Status::ok, {}};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

Eigen::MatrixXd product(VulkanBackend& backend, const RowMajorSparse& a, const Eigen::MatrixXd& x) {
  const auto matrix = backend.upload(a);
  const auto input = backend.upload(x);
  const auto output = backend.allocate(static_cast<int>(a.rows()), static_cast<int>(x.cols()));
  backend.spmv(*matrix, *input, *output);
  return output->download();
}

TEST(VulkanFaults, OutOfDeviceMemoryIsAClearErrorAndPasses) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto context = fresh_vulkan_context();
  VulkanBackend backend(context);
  const RowMajorSparse a = hemisphere_laplacian(10);
  const Eigen::MatrixXd x = random_block(static_cast<int>(a.rows()), 2, 3u);
  context->impl().faults.fail_allocation(1);
  const auto [status, message] = error_of([&] { (void)backend.upload(a); });
  EXPECT_EQ(status, Status::device_failure);
  EXPECT_TRUE(contains(message, "VK_ERROR_OUT_OF_DEVICE_MEMORY")) << message;
  EXPECT_TRUE(contains(message, "allocating the")) << message;
  EXPECT_TRUE(contains(message, "CPU backend")) << message;
  // Out of memory is not fatal: the next allocations succeed and the device computes.
  const Eigen::MatrixXd expected = a * x;
  EXPECT_LE((product(backend, a, x) - expected).cwiseAbs().maxCoeff(),
            1e-5 * expected.cwiseAbs().maxCoeff());
  EXPECT_FALSE(context->impl().device_lost());
}

TEST(VulkanFaults, OutOfDeviceMemoryInAMapIsThrown) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  FixedBoundaryOptions options;
  options.solver.backend = BackendChoice::vulkan;
  options.solver.vulkan_context = fresh_vulkan_context();
  options.solver.vulkan_context->impl().faults.fail_allocation(2);
  const Mesh mesh = hemisphere(8);
  const auto [status, message] = error_of([&] { (void)fixed_boundary_map(mesh, options); });
  EXPECT_EQ(status, Status::device_failure);
  EXPECT_TRUE(contains(message, "VK_ERROR_OUT_OF_DEVICE_MEMORY")) << message;
}

TEST(VulkanFaults, DeviceLossIsReportedAndStays) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  auto context = fresh_vulkan_context();
  const RowMajorSparse a = hemisphere_laplacian(10);
  const Eigen::MatrixXd x = random_block(static_cast<int>(a.rows()), 1, 5u);
  {
    VulkanBackend backend(context);
    context->impl().faults.lose_device_at_submission(1);
    auto [status, message] = error_of([&] { (void)product(backend, a, x); });
    EXPECT_EQ(status, Status::device_failure);
    EXPECT_TRUE(contains(message, "VK_ERROR_DEVICE_LOST")) << message;
    EXPECT_TRUE(context->impl().device_lost());
    // Later work fails at once, saying why.
    std::tie(status, message) = error_of([&] { (void)product(backend, a, x); });
    EXPECT_EQ(status, Status::device_failure);
    EXPECT_TRUE(contains(message, "was lost or stopped responding earlier")) << message;
  }
  // automatic on the lost context runs on the CPU and says why; vulkan refuses with the reason.
  SolverOptions options;
  options.vulkan_context = context;
  options.backend = BackendChoice::automatic;
  std::string notice;
  auto fallback = detail::make_backend(options, &notice);
  ASSERT_NE(fallback, nullptr);
  EXPECT_EQ(fallback->kind(), BackendKind::cpu);
  EXPECT_TRUE(contains(notice, "was lost")) << notice;
  EXPECT_TRUE(contains(notice, "using the CPU backend")) << notice;
  FixedBoundaryOptions map_options;
  map_options.solver = options;
  const MapResult on_cpu = fixed_boundary_map(hemisphere(8), map_options);
  EXPECT_TRUE(on_cpu.report.ok()) << on_cpu.report.message;
  EXPECT_EQ(on_cpu.report.backend, BackendKind::cpu);
  EXPECT_TRUE(contains(on_cpu.report.backend_notice, "was lost")) << on_cpu.report.backend_notice;
  options.backend = BackendChoice::vulkan;
  EXPECT_EQ(detail::make_backend(options, &notice), nullptr);
  EXPECT_TRUE(contains(notice, "was lost")) << notice;
  context.reset();  // Destroyable after the loss (validation would report leaks).
}

TEST(VulkanFaults, DeviceLossDuringAMapIsThrown) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  FixedBoundaryOptions options;
  options.solver.backend = BackendChoice::vulkan;
  options.solver.vulkan_context = fresh_vulkan_context();
  options.solver.vulkan_context->impl().faults.lose_device_at_submission(3);
  const auto [status, message] = error_of([&] { (void)fixed_boundary_map(hemisphere(8), options); });
  EXPECT_EQ(status, Status::device_failure);
  EXPECT_TRUE(contains(message, "VK_ERROR_DEVICE_LOST")) << message;
}

TEST(VulkanFaults, AHungSubmissionTimesOutInsteadOfHanging) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  auto context = fresh_vulkan_context();
  ASSERT_TRUE(context->device().timeline_semaphore);
  context->impl().wait_timeout_ns = 200'000'000;  // 0.2 s
  const RowMajorSparse a = hemisphere_laplacian(10);
  const Eigen::MatrixXd x = random_block(static_cast<int>(a.rows()), 1, 9u);
  const auto start = std::chrono::steady_clock::now();
  {
    VulkanBackend backend(context);
    context->impl().faults.hang_submission(1);
    const auto [status, message] = error_of([&] { (void)product(backend, a, x); });
    EXPECT_EQ(status, Status::device_failure);
    EXPECT_TRUE(contains(message, "did not finish within 0.2 s")) << message;
    EXPECT_TRUE(contains(message, "treated as hung")) << message;
    EXPECT_TRUE(context->impl().device_lost());
  }
  context.reset();  // The held-back work drains; nothing hangs, nothing leaks.
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 30.0);
}

TEST(VulkanFaults, TooLargeBufferNamesTheLimit) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  VulkanBackend backend(vulkan_test_context());
  const std::uint64_t limit = backend.context().device().max_storage_buffer_range;
  const int rows = static_cast<int>(std::min<std::uint64_t>(limit / 4 + 1024, 2'000'000'000));
  const auto [status, message] = error_of([&] { (void)backend.allocate(rows, 1); });
  EXPECT_EQ(status, Status::device_failure);
  EXPECT_TRUE(contains(message, vulkan::detail::mebibytes(limit))) << message;
  EXPECT_TRUE(contains(message, "maxStorageBufferRange")) << message;
}

}  // namespace
}  // namespace harmonia::testing
