#pragma once
// Internal: what a harmonia::vulkan::Context holds. Shared by every kernels/ file.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>

#include "harmonia/vulkan_context.h"
#include "kernels/fault_injection.h"
#include "kernels/vulkan_functions.h"

namespace harmonia::vulkan::detail {
class PipelineLibrary;

// Entry points that only feature discovery and the submission machinery use, beyond the shared
// table of kernels/vulkan_functions.h. Loaded here because the Vulkan 1.2 ones (timeline
// semaphores) may be absent: they stay null on a 1.1 device.
struct SubmissionFunctions {
  PFN_vkGetPhysicalDeviceFeatures2 vkGetPhysicalDeviceFeatures2 = nullptr;
  PFN_vkCreateSemaphore vkCreateSemaphore = nullptr;
  PFN_vkDestroySemaphore vkDestroySemaphore = nullptr;
  PFN_vkGetFenceStatus vkGetFenceStatus = nullptr;
  PFN_vkWaitSemaphores vkWaitSemaphores = nullptr;                      // Vulkan 1.2.
  PFN_vkGetSemaphoreCounterValue vkGetSemaphoreCounterValue = nullptr;  // Vulkan 1.2.
  PFN_vkSignalSemaphore vkSignalSemaphore = nullptr;                    // Vulkan 1.2.

  void load_instance(const VulkanFunctions& vk, VkInstance instance);
  void load_device(const VulkanFunctions& vk, VkDevice device);
};

// While installed on a thread (observe_submissions), every submission that thread makes on
// `context` stores the timeline value it signals in `value` (harmonia/async.h uses this to tell
// an engine which value a launched map's work signals). Null context: nothing is observed.
struct SubmissionObserver {
  const Context::Impl* context = nullptr;
  std::atomic<std::uint64_t>* value = nullptr;
};
// Installs `observer` for the calling thread (null removes it); returns the previous one.
SubmissionObserver* observe_submissions(SubmissionObserver* observer);

}  // namespace harmonia::vulkan::detail

namespace harmonia::vulkan {

struct Context::Impl {
  Impl();
  ~Impl();  // Destroys what is owned, in reverse order of creation; borrowed handles stay.
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  detail::VulkanFunctions vk;
  detail::SubmissionFunctions sync;
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;
  bool owns_instance = false;
  bool owns_device = false;
  const VkAllocationCallbacks* allocator = nullptr;  // Borrowed (ExternalVulkan) or null.

  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  DebugCallback debug_callback;  // Null: warnings and errors go to stderr.

  VkPipelineCache pipeline_cache = VK_NULL_HANDLE;
  bool owns_pipeline_cache = false;
  std::unique_ptr<detail::PipelineLibrary> pipelines;

  DeviceInfo info;
  VkPhysicalDeviceLimits limits{};
  VkPhysicalDeviceMemoryProperties memory{};
  float timestamp_period_ns = 1.0f;
  std::uint64_t timestamp_mask = ~std::uint64_t{0};  // The queue's valid timestamp bits.
  // One workgroup width for every kernel: a power of two, a multiple of the subgroup size where
  // the limits allow (tree reductions need a power of two). Chosen from the limits at creation.
  std::uint32_t workgroup_size = 64;
  // Most workgroups in the first pass of a reduction (kernels/reduction.h): 1024 on GPUs, enough
  // to fill a large one; 64 on CPU devices, where every extra group pays its barriers again.
  std::uint32_t reduction_groups = 1024;
  // Invocations that share one matrix row in the subgroup-per-row SpMV: the subgroup size, capped.
  std::uint32_t lanes_per_row = 8;

  std::function<void()> lock_queue, unlock_queue;

  // Signalled by every submission with the next value (1, 2, ...) when timeline semaphores are
  // enabled (info.timeline_semaphore); null otherwise, and submitters wait on fences.
  VkSemaphore timeline = VK_NULL_HANDLE;
  // Longest wait for one submission before harmonia gives up on the device (a hang without a
  // driver watchdog): no legitimate submission runs this long, since the solvers submit a few
  // iterations at a time. Tests shorten it.
  std::atomic<std::uint64_t> wait_timeout_ns{300'000'000'000ull};
  // Failures tests can provoke (kernels/fault_injection.h).
  detail::FaultInjection faults;

  // Submits one command buffer under the context's lock (and the application's, for a borrowed
  // queue), signalling `fence` (may be null) and, with timeline semaphores, the timeline. Returns
  // the timeline value it signals (0 without timelines). Throws harmonia::Error (device_failure)
  // when the submission fails or the device was lost before.
  std::uint64_t submit(VkCommandBuffer commands, VkFence fence);
  // The value the latest successful submission signals (0 before any, and without timelines).
  [[nodiscard]] std::uint64_t last_submitted_value() const { return last_submitted_.load(); }
  // Submissions this context has made so far (every one the queue accepted, with or without
  // timelines). Internal instrumentation: tests read it around a fused solve to show that several
  // iterations share one submission.
  [[nodiscard]] std::uint64_t submission_count() const { return submission_count_.load(); }
  // The timeline's current value (0 without timelines).
  [[nodiscard]] std::uint64_t completed_value() const;
  // Waits until the timeline reaches `value`, up to wait_timeout_ns. Throws harmonia::Error
  // (device_failure) on device loss or timeout; a timeout marks the device lost.
  void wait_for_value(std::uint64_t value);
  // Handles the result of a wait: nothing on success, else marks the device lost (device loss,
  // timeout) and throws harmonia::Error (device_failure) naming `what`.
  void check_wait(VkResult result, const char* what);
  // True once a submission or wait reported VK_ERROR_DEVICE_LOST or timed out: every later
  // submission fails at once (a lost device stays lost; a new Context is needed).
  [[nodiscard]] bool device_lost() const { return device_lost_.load(); }

  // Fills info, limits, memory and the workgroup shape from the physical device.
  void describe_device();
  // Creates the timeline semaphore when info.timeline_semaphore (set from enabled features).
  void prepare_timeline();
  // Creates the pipeline cache (unless one was lent) and the lazy pipeline library.
  void prepare_pipelines(VkPipelineCache lent_cache);

 private:
  // Makes an injected hang's submission wait on a gate semaphore (created on first use).
  VkSemaphore hang_gate();
  // Opens the gate, so that submissions held by an injected hang can drain (what a driver's
  // watchdog does to a real hang) and their objects can be destroyed. True when it opened now.
  bool open_hang_gate() noexcept;

  std::mutex queue_mutex_;
  std::uint64_t next_value_ = 1;  // Guarded by queue_mutex_.
  std::atomic<std::uint64_t> last_submitted_{0};
  std::atomic<std::uint64_t> submission_count_{0};
  mutable std::atomic<bool> device_lost_{false};
  VkSemaphore hang_gate_ = VK_NULL_HANDLE;  // Guarded by queue_mutex_.
};

}  // namespace harmonia::vulkan
