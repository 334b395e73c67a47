#pragma once
// Internal: what a harmonia::vulkan::Context holds. Shared by every kernels/ file.

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>

#include "harmonia/vulkan_context.h"
#include "kernels/vulkan_functions.h"

namespace harmonia::vulkan::detail {
class PipelineLibrary;
}  // namespace harmonia::vulkan::detail

namespace harmonia::vulkan {

struct Context::Impl {
  Impl();
  ~Impl();  // Destroys what is owned, in reverse order of creation; borrowed handles stay.
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  detail::VulkanFunctions vk;
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

  // vkQueueSubmit under the context's lock (and the application's, for a borrowed queue).
  void submit(const VkSubmitInfo& submit_info, VkFence fence);
  // Fills info, limits, memory and the workgroup shape from the physical device.
  void describe_device();
  // Creates the pipeline cache (unless one was lent) and the lazy pipeline library.
  void prepare_pipelines(VkPipelineCache lent_cache);

 private:
  std::mutex queue_mutex_;
};

}  // namespace harmonia::vulkan
