// Optional device features and submit-now-wait-later: shaderFloat64 only when asked for (created
// contexts) or declared (borrowed ones), timeline semaphores, the recorder's tickets, and
// harmonia::launch: a map running beside the caller, its result bit for bit the synchronous one,
// its timeline value reached after wait() (an engine's submission can wait on it), cancel().
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "harmonia/async.h"
#include "harmonia/fixed_boundary_map.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "kernels/context_impl.h"
#include "kernels/kernel_test_data.h"
#include "kernels/recorder.h"
#include "kernels/vulkan_backend.h"
#include "kernels/vulkan_fresh_context.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using vulkan::detail::Buffer;
using vulkan::detail::BufferRole;
using vulkan::detail::CommandRecorder;

vulkan::ExternalVulkan borrow(const vulkan::Context& owner) {
  const auto& impl = owner.impl();
  vulkan::ExternalVulkan external;
  external.instance = impl.instance;
  external.physical_device = impl.physical_device;
  external.device = impl.device;
  external.queue = impl.queue;
  external.queue_family_index = impl.queue_family;
  external.api_version = owner.device().api_version;
  external.get_instance_proc_addr = impl.vk.vkGetInstanceProcAddr;
  return external;
}

TEST(VulkanFeatures, Float64IsEnabledOnlyWhenAskedFor) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto plain = fresh_vulkan_context(false);
  EXPECT_TRUE(plain->device().shader_float64) << "lavapipe has shaderFloat64";
  EXPECT_FALSE(plain->device().float64_enabled);
  const auto with_float64 = fresh_vulkan_context(true);
  EXPECT_TRUE(with_float64->device().float64_enabled);
  // The shared test context asks for nothing.
  EXPECT_FALSE(vulkan_test_context()->device().float64_enabled);
}

TEST(VulkanFeatures, BorrowedFeaturesAreTheEnginesWord) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto owner = fresh_vulkan_context(true);
  vulkan::ExternalVulkan external = borrow(*owner);
  EXPECT_FALSE(vulkan::Context::wrap(external).device().float64_enabled);
  EXPECT_FALSE(vulkan::Context::wrap(external).device().timeline_semaphore);
  EXPECT_EQ(vulkan::Context::wrap(external).timeline_semaphore(), VK_NULL_HANDLE);
  external.float64_enabled = true;
  EXPECT_TRUE(vulkan::Context::wrap(external).device().float64_enabled);

  external.api_version = VK_API_VERSION_1_1;
  external.timeline_semaphore_enabled = true;
  try {
    (void)vulkan::Context::wrap(external);
    ADD_FAILURE() << "timeline semaphores on a Vulkan 1.1 device were accepted";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::unsupported);
    EXPECT_NE(std::string(error.what()).find("Vulkan 1.2"), std::string::npos) << error.what();
  }
}

TEST(VulkanFeatures, CreatedContextsSignalATimeline) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto context = vulkan_test_context();
  ASSERT_GE(context->device().api_version, VK_API_VERSION_1_2) << "lavapipe has Vulkan 1.2+";
  EXPECT_TRUE(context->device().timeline_semaphore);
  EXPECT_NE(context->timeline_semaphore(), VK_NULL_HANDLE);
}

// The recorder's tickets on the timeline path (the shared context) and the fence path (a
// borrowed context whose engine did not enable timelines).
TEST(VulkanRecorder, SubmitReturnsATicketThatWaitSettles) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto owner = vulkan_test_context();
  auto fence_only = std::make_shared<vulkan::Context>(vulkan::Context::wrap(borrow(*owner)));
  for (const auto& context : {owner, fence_only}) {
    auto& impl = context->impl();
    const int count = 1 << 16;
    Buffer source(impl, count * sizeof(float), BufferRole::device, "source");
    Buffer target(impl, count * sizeof(float), BufferRole::device, "target");
    ASSERT_NE(source.mapped(), nullptr);
    auto* values = static_cast<float*>(source.mapped());
    for (int k = 0; k < count; ++k) values[k] = static_cast<float>(k) * 0.5f;
    CommandRecorder recorder(impl);
    recorder.begin();
    recorder.copy(source, 0, target, 0, count * sizeof(float));
    recorder.end();
    const CommandRecorder::Ticket first = recorder.submit();
    while (!recorder.is_done(first)) std::this_thread::yield();
    recorder.wait(first);
    const CommandRecorder::Ticket second = recorder.submit();
    EXPECT_GT(second.value, first.value);
    EXPECT_TRUE(recorder.is_done(first));
    recorder.wait(second);
    EXPECT_TRUE(recorder.is_done(second));
    const auto* copied = static_cast<const float*>(target.mapped());
    for (int k = 0; k < count; k += 977) EXPECT_EQ(copied[k], static_cast<float>(k) * 0.5f);
    if (context == owner)
      EXPECT_EQ(second.value, context->last_submission_value());
    else
      EXPECT_EQ(context->last_submission_value(), 0u);
  }
}

FixedBoundaryOptions vulkan_map_options() {
  FixedBoundaryOptions options;
  options.weights = WeightScheme::cotangent;
  options.solver.backend = BackendChoice::vulkan;
  options.solver.vulkan_context = vulkan_test_context();
  return options;
}

PendingMap<MapResult> launch_map(const Mesh& mesh, const FixedBoundaryOptions& options) {
  return launch(options.solver, [&mesh, options](const SolverOptions& solver) {
    FixedBoundaryOptions task_options = options;
    task_options.solver = solver;
    return fixed_boundary_map(mesh, task_options);
  });
}

TEST(VulkanLaunch, RunsBesideTheCallerAndGivesTheSynchronousResult) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const Mesh mesh = hemisphere(30);
  FixedBoundaryOptions options = vulkan_map_options();
  const MapResult synchronous = fixed_boundary_map(mesh, options);
  ASSERT_TRUE(synchronous.report.ok()) << synchronous.report.message;

  // The map's first progress report waits for the caller: launch() must have returned by then.
  std::atomic<bool> released{false};
  options.solver.progress = [&released](const Progress&) {
    while (!released) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return true;
  };
  PendingMap<MapResult> pending = launch_map(mesh, options);
  EXPECT_FALSE(pending.ready());
  released = true;
  int polls = 0;
  double other_work = 0.0;
  while (!pending.ready()) {
    ++polls;
    for (int k = 1; k <= 1000; ++k) other_work += 1.0 / k;  // The caller's own frame.
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_GT(other_work, 0.0);
  const MapResult& result = pending.wait();
  ASSERT_TRUE(result.report.ok()) << result.report.message;
  EXPECT_EQ(result.report.backend, BackendKind::vulkan);
  ASSERT_EQ(result.uv.rows(), synchronous.uv.rows());
  EXPECT_TRUE((result.uv.array() == synchronous.uv.array()).all()) << "not bit for bit";
  EXPECT_EQ(result.report.iterations, synchronous.report.iterations);
  std::cout << "[ launch ] " << polls << " polls of ready() while the map ran\n";
}

TEST(VulkanLaunch, TheTimelineValueIsReachedAndAnEngineCanWaitOnIt) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto context = vulkan_test_context();
  const Mesh mesh = hemisphere(16);
  const std::uint64_t before = context->last_submission_value();
  PendingMap<MapResult> pending = launch_map(mesh, vulkan_map_options());
  ASSERT_TRUE(pending.wait().report.ok()) << pending.wait().report.message;
  const std::uint64_t value = pending.device_signal_value();
  EXPECT_GT(value, before);
  EXPECT_LE(value, context->last_submission_value());

  auto& impl = context->impl();
  const VkSemaphore timeline = context->timeline_semaphore();
  auto wait_info = vulkan::detail::vk_info<VkSemaphoreWaitInfo>(
      VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO);
  wait_info.semaphoreCount = 1;
  wait_info.pSemaphores = &timeline;
  wait_info.pValues = &value;
  EXPECT_EQ(impl.sync.vkWaitSemaphores(impl.device, &wait_info, 0), VK_SUCCESS);
  std::uint64_t counter = 0;
  ASSERT_EQ(impl.sync.vkGetSemaphoreCounterValue(impl.device, timeline, &counter), VK_SUCCESS);
  EXPECT_GE(counter, value);

  // The engine's own submission waits for the map's work on the timeline.
  auto fence_info = vulkan::detail::vk_info<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  VkFence fence = VK_NULL_HANDLE;
  ASSERT_EQ(impl.vk.vkCreateFence(impl.device, &fence_info, nullptr, &fence), VK_SUCCESS);
  auto timeline_info = vulkan::detail::vk_info<VkTimelineSemaphoreSubmitInfo>(
      VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO);
  timeline_info.waitSemaphoreValueCount = 1;
  timeline_info.pWaitSemaphoreValues = &value;
  const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
  auto submit = vulkan::detail::vk_info<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit.pNext = &timeline_info;
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &timeline;
  submit.pWaitDstStageMask = &stage;
  ASSERT_EQ(impl.vk.vkQueueSubmit(impl.queue, 1, &submit, fence), VK_SUCCESS);
  EXPECT_EQ(impl.vk.vkWaitForFences(impl.device, 1, &fence, VK_TRUE, 5'000'000'000ull), VK_SUCCESS);
  impl.vk.vkDestroyFence(impl.device, fence, nullptr);
}

TEST(VulkanLaunch, CancelStopsTheMap) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const Mesh mesh = hemisphere(16);
  FixedBoundaryOptions options = vulkan_map_options();
  std::atomic<bool> started{false}, released{false};
  options.solver.progress = [&](const Progress&) {
    started = true;
    while (!released) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return true;
  };
  PendingMap<MapResult> pending = launch_map(mesh, options);
  while (!started) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  pending.cancel();
  released = true;
  const MapResult& result = pending.wait();
  EXPECT_EQ(result.report.status, Status::cancelled) << result.report.message;
  EXPECT_TRUE(pending.ready());
}

TEST(VulkanLaunch, ErrorsReachTheCaller) {
  // A CPU map that throws: wait() rethrows, every time.
  PendingMap<int> pending = launch(SolverOptions{}, [](const SolverOptions&) -> int {
    throw Error(Status::device_failure, "thrown on the worker");
  });
  for (int attempt = 0; attempt < 2; ++attempt) {
    try {
      (void)pending.wait();
      ADD_FAILURE() << "no exception";
    } catch (const Error& error) {
      EXPECT_EQ(error.status(), Status::device_failure);
      EXPECT_STREQ(error.what(), "thrown on the worker");
    }
  }
  EXPECT_EQ(pending.device_signal_value(), 0u);
}

}  // namespace
}  // namespace harmonia::testing
