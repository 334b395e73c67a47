#pragma once
// Internal: the Vulkan entry points harmonia calls, loaded at run time.
//
// The library does not link libvulkan: a machine without a Vulkan loader must still run the CPU
// backend, so the loader is opened with dlopen (or the engine's vkGetInstanceProcAddr is used)
// and every function is fetched into this table. Device functions come from vkGetDeviceProcAddr,
// which skips the loader's dispatch on every call.

#include <vulkan/vulkan_core.h>

#include <string>

namespace harmonia::vulkan::detail {

// X-macro lists: HARMONIA_VK(name) once per entry point, grouped by how it is loaded.
#define HARMONIA_VK_GLOBAL_FUNCTIONS(HARMONIA_VK) \
  HARMONIA_VK(vkCreateInstance)                   \
  HARMONIA_VK(vkEnumerateInstanceVersion)         \
  HARMONIA_VK(vkEnumerateInstanceLayerProperties) \
  HARMONIA_VK(vkEnumerateInstanceExtensionProperties)

#define HARMONIA_VK_INSTANCE_FUNCTIONS(HARMONIA_VK)     \
  HARMONIA_VK(vkDestroyInstance)                        \
  HARMONIA_VK(vkEnumeratePhysicalDevices)               \
  HARMONIA_VK(vkGetPhysicalDeviceProperties)            \
  HARMONIA_VK(vkGetPhysicalDeviceProperties2)           \
  HARMONIA_VK(vkGetPhysicalDeviceFeatures)              \
  HARMONIA_VK(vkGetPhysicalDeviceQueueFamilyProperties) \
  HARMONIA_VK(vkGetPhysicalDeviceMemoryProperties)      \
  HARMONIA_VK(vkCreateDevice)                           \
  HARMONIA_VK(vkGetDeviceProcAddr)

// Present only with VK_EXT_debug_utils enabled (validation); may stay null.
#define HARMONIA_VK_DEBUG_FUNCTIONS(HARMONIA_VK) \
  HARMONIA_VK(vkCreateDebugUtilsMessengerEXT)    \
  HARMONIA_VK(vkDestroyDebugUtilsMessengerEXT)

#define HARMONIA_VK_DEVICE_FUNCTIONS(HARMONIA_VK) \
  HARMONIA_VK(vkDestroyDevice)                    \
  HARMONIA_VK(vkGetDeviceQueue)                   \
  HARMONIA_VK(vkDeviceWaitIdle)                   \
  HARMONIA_VK(vkCreateBuffer)                     \
  HARMONIA_VK(vkDestroyBuffer)                    \
  HARMONIA_VK(vkGetBufferMemoryRequirements)      \
  HARMONIA_VK(vkAllocateMemory)                   \
  HARMONIA_VK(vkFreeMemory)                       \
  HARMONIA_VK(vkBindBufferMemory)                 \
  HARMONIA_VK(vkMapMemory)                        \
  HARMONIA_VK(vkUnmapMemory)                      \
  HARMONIA_VK(vkCreateShaderModule)               \
  HARMONIA_VK(vkDestroyShaderModule)              \
  HARMONIA_VK(vkCreateDescriptorSetLayout)        \
  HARMONIA_VK(vkDestroyDescriptorSetLayout)       \
  HARMONIA_VK(vkCreatePipelineLayout)             \
  HARMONIA_VK(vkDestroyPipelineLayout)            \
  HARMONIA_VK(vkCreateComputePipelines)           \
  HARMONIA_VK(vkDestroyPipeline)                  \
  HARMONIA_VK(vkCreatePipelineCache)              \
  HARMONIA_VK(vkDestroyPipelineCache)             \
  HARMONIA_VK(vkCreateDescriptorPool)             \
  HARMONIA_VK(vkDestroyDescriptorPool)            \
  HARMONIA_VK(vkResetDescriptorPool)              \
  HARMONIA_VK(vkAllocateDescriptorSets)           \
  HARMONIA_VK(vkUpdateDescriptorSets)             \
  HARMONIA_VK(vkCreateCommandPool)                \
  HARMONIA_VK(vkDestroyCommandPool)               \
  HARMONIA_VK(vkAllocateCommandBuffers)           \
  HARMONIA_VK(vkFreeCommandBuffers)               \
  HARMONIA_VK(vkBeginCommandBuffer)               \
  HARMONIA_VK(vkEndCommandBuffer)                 \
  HARMONIA_VK(vkResetCommandBuffer)               \
  HARMONIA_VK(vkCmdBindPipeline)                  \
  HARMONIA_VK(vkCmdBindDescriptorSets)            \
  HARMONIA_VK(vkCmdPushConstants)                 \
  HARMONIA_VK(vkCmdDispatch)                      \
  HARMONIA_VK(vkCmdPipelineBarrier)               \
  HARMONIA_VK(vkCmdCopyBuffer)                    \
  HARMONIA_VK(vkCmdWriteTimestamp)                \
  HARMONIA_VK(vkCmdResetQueryPool)                \
  HARMONIA_VK(vkCreateQueryPool)                  \
  HARMONIA_VK(vkDestroyQueryPool)                 \
  HARMONIA_VK(vkGetQueryPoolResults)              \
  HARMONIA_VK(vkCreateFence)                      \
  HARMONIA_VK(vkDestroyFence)                     \
  HARMONIA_VK(vkResetFences)                      \
  HARMONIA_VK(vkWaitForFences)                    \
  HARMONIA_VK(vkQueueSubmit)

#define HARMONIA_VK_MEMBER(name) PFN_##name name = nullptr;

// The loaded entry points. Filled in three steps: global (loader), instance, device.
struct VulkanFunctions {
  PFN_vkGetInstanceProcAddr vkGetInstanceProcAddr = nullptr;
  HARMONIA_VK_GLOBAL_FUNCTIONS(HARMONIA_VK_MEMBER)
  HARMONIA_VK_INSTANCE_FUNCTIONS(HARMONIA_VK_MEMBER)
  HARMONIA_VK_DEBUG_FUNCTIONS(HARMONIA_VK_MEMBER)
  HARMONIA_VK_DEVICE_FUNCTIONS(HARMONIA_VK_MEMBER)

  // Global functions from `entry` (the engine's), or from the system loader when null.
  // Throws Error(Status::unsupported) naming the library when no loader can be opened.
  void load_global(PFN_vkGetInstanceProcAddr entry);
  // Instance-level functions (throws Error naming a missing one); debug-utils ones may stay null.
  void load_instance(VkInstance instance);
  void load_device(VkDevice device);

  // The dlopen handle of the system loader, closed by the owner (Context) after the instance is
  // destroyed. Null when the engine's entry point is used.
  void* loader_library = nullptr;
};

#undef HARMONIA_VK_MEMBER

// Closes the loader opened by load_global (no-op when none was opened).
void close_loader(VulkanFunctions& functions);

// A zero-initialized Vulkan structure with its sType set.
template <typename Info>
[[nodiscard]] Info vk_info(VkStructureType type) {
  Info info{};
  info.sType = type;
  return info;
}

// Name of a VkResult, e.g. "VK_ERROR_OUT_OF_DEVICE_MEMORY".
[[nodiscard]] std::string result_name(VkResult result);

// Throws harmonia::Error for a failed call: Status::device_failure, with `what` and the result.
void check(VkResult result, const char* what);

}  // namespace harmonia::vulkan::detail
