#pragma once
// Internal: choosing the physical device and queue family Context::create uses.

#include <cstdint>
#include <optional>

#include "harmonia/vulkan_context.h"
#include "kernels/vulkan_functions.h"

namespace harmonia::vulkan::detail {

struct DeviceChoice {
  VkPhysicalDevice device = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;
};

[[nodiscard]] DeviceType device_type(VkPhysicalDeviceType type);

// A queue family with compute: one without graphics first (a dedicated compute queue runs beside
// an engine's rendering), else any with compute.
[[nodiscard]] std::optional<std::uint32_t> compute_queue_family(const VulkanFunctions& vk,
                                                                VkPhysicalDevice device);

// The device the options ask for: by index, by name, else the first of the most preferred type
// (discrete, integrated, virtual, cpu, other). Devices without Vulkan 1.1 or without a compute
// queue are passed over, and so are software devices when options.hardware_only. Throws
// Error(Status::unsupported) listing every device and why it was passed over when none fits.
[[nodiscard]] DeviceChoice choose_device(const VulkanFunctions& vk, VkInstance instance,
                                         const ContextOptions& options);

}  // namespace harmonia::vulkan::detail
