#include "kernels/device_selection.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "harmonia/types.h"

namespace harmonia::vulkan::detail {
namespace {

int preference_rank(DeviceType type) { return static_cast<int>(type); }

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string version_text(std::uint32_t version) {
  return std::to_string(VK_API_VERSION_MAJOR(version)) + "." +
         std::to_string(VK_API_VERSION_MINOR(version));
}

struct Candidate {
  int index = 0;
  VkPhysicalDevice device = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties{};
  std::optional<std::uint32_t> queue_family;
  std::string rejection;  // Empty when usable.
};

}  // namespace

DeviceType device_type(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return DeviceType::discrete_gpu;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return DeviceType::integrated_gpu;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return DeviceType::virtual_gpu;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return DeviceType::cpu;
    default:
      return DeviceType::other;
  }
}

std::optional<std::uint32_t> compute_queue_family(const VulkanFunctions& vk,
                                                  VkPhysicalDevice device) {
  std::uint32_t count = 0;
  vk.vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vk.vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  std::optional<std::uint32_t> any_compute;
  for (std::uint32_t family = 0; family < count; ++family) {
    const VkQueueFlags flags = families[family].queueFlags;
    if ((flags & VK_QUEUE_COMPUTE_BIT) == 0 || families[family].queueCount == 0) continue;
    if ((flags & VK_QUEUE_GRAPHICS_BIT) == 0) return family;
    if (!any_compute) any_compute = family;
  }
  return any_compute;
}

DeviceChoice choose_device(const VulkanFunctions& vk, VkInstance instance,
                           const ContextOptions& options) {
  std::uint32_t count = 0;
  check(vk.vkEnumeratePhysicalDevices(instance, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  if (count > 0)
    check(vk.vkEnumeratePhysicalDevices(instance, &count, devices.data()),
          "vkEnumeratePhysicalDevices");
  if (count == 0)
    throw Error(Status::unsupported, "no Vulkan device: the loader found no driver with a device");

  std::vector<Candidate> candidates(count);
  const std::string wanted_name = lowercase(options.device_name);
  for (std::uint32_t index = 0; index < count; ++index) {
    Candidate& candidate = candidates[index];
    candidate.index = static_cast<int>(index);
    candidate.device = devices[index];
    vk.vkGetPhysicalDeviceProperties(devices[index], &candidate.properties);
    candidate.queue_family = compute_queue_family(vk, devices[index]);
    const DeviceType type = device_type(candidate.properties.deviceType);
    if (candidate.properties.apiVersion < VK_API_VERSION_1_1)
      candidate.rejection =
          "Vulkan " + version_text(candidate.properties.apiVersion) + " (1.1 is required)";
    else if (!candidate.queue_family)
      candidate.rejection = "no compute queue";
    else if (options.device_index && *options.device_index != candidate.index)
      candidate.rejection = "not the requested index " + std::to_string(*options.device_index);
    else if (!options.device_index && !wanted_name.empty() &&
             lowercase(candidate.properties.deviceName).find(wanted_name) == std::string::npos)
      candidate.rejection = "name does not contain \"" + options.device_name + "\"";
    else if (options.hardware_only && type == DeviceType::cpu)
      candidate.rejection = "software device (slower than the CPU backend)";
  }

  const Candidate* best = nullptr;
  for (const Candidate& candidate : candidates) {
    if (!candidate.rejection.empty()) continue;
    const int rank = preference_rank(device_type(candidate.properties.deviceType));
    if (best == nullptr || rank < preference_rank(device_type(best->properties.deviceType)))
      best = &candidate;
  }
  if (best == nullptr) {
    std::string message = "no suitable Vulkan device;";
    if (options.device_index && *options.device_index >= static_cast<int>(count))
      message += " device index " + std::to_string(*options.device_index) + " is out of range;";
    for (const Candidate& candidate : candidates)
      message += " [" + std::to_string(candidate.index) + "] " + candidate.properties.deviceName +
                 " (" + std::string(to_string(device_type(candidate.properties.deviceType))) +
                 "): " + candidate.rejection + ";";
    message.pop_back();
    throw Error(Status::unsupported, message);
  }
  return DeviceChoice{best->device, *best->queue_family};
}

}  // namespace harmonia::vulkan::detail
