#pragma once
// A test context with shaderFloat64 enabled, on the same validated lavapipe instance as
// vulkan_test_context(): a second VkDevice made with shaderFloat64 on, lent to harmonia through
// Context::wrap with ExternalVulkan::float64_enabled (the way an engine would lend it). The
// validation layer is an instance layer, so its messages reach the shared test callback and fail
// the test as for the shared context.
//
// Until the context side marks DeviceInfo::float64_enabled from ExternalVulkan::float64_enabled
// (helper vkasync's branch), the flag is set here after wrap, for the test only.

#include <memory>
#include <string>

#include "kernels/context_impl.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {

// Owns the lent VkDevice; destroys it after the harmonia context that borrows it.
struct Float64TestDevice {
  std::shared_ptr<vulkan::Context> shared;  // Keeps the instance alive.
  VkDevice device = VK_NULL_HANDLE;
  std::shared_ptr<vulkan::Context> context;
  ~Float64TestDevice() {
    context.reset();
    if (device != VK_NULL_HANDLE) shared->impl().vk.vkDestroyDevice(device, nullptr);
  }
};

// Null (and `reason`) when the test device is missing or has no shaderFloat64.
inline std::shared_ptr<vulkan::Context> float64_test_context(std::string* reason = nullptr) {
  // Statics are destroyed in the reverse order of their construction: the shared test context
  // (and its debug callback) must be made before `made`, so that it outlives the lent device even
  // in a process whose first test asks for fp64 (else a crash at exit).
  (void)vulkan_test_context();
  static std::unique_ptr<Float64TestDevice> made;
  static std::string why;
  if (!made && why.empty()) {
    std::shared_ptr<vulkan::Context> shared = vulkan_test_context(&why);
    if (!shared) return nullptr;
    vulkan::Context::Impl& impl = shared->impl();
    if (!impl.info.shader_float64) {
      why = "the test device has no shaderFloat64";
    } else {
      const float priority = 1.0f;
      auto queue_info = vulkan::detail::vk_info<VkDeviceQueueCreateInfo>(
          VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
      queue_info.queueFamilyIndex = impl.queue_family;
      queue_info.queueCount = 1;
      queue_info.pQueuePriorities = &priority;
      VkPhysicalDeviceFeatures features{};
      features.shaderFloat64 = VK_TRUE;
      auto device_info =
          vulkan::detail::vk_info<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
      device_info.queueCreateInfoCount = 1;
      device_info.pQueueCreateInfos = &queue_info;
      device_info.pEnabledFeatures = &features;
      auto device = std::make_unique<Float64TestDevice>();
      device->shared = shared;
      if (impl.vk.vkCreateDevice(impl.physical_device, &device_info, nullptr, &device->device) !=
          VK_SUCCESS) {
        why = "vkCreateDevice with shaderFloat64 failed";
        device->device = VK_NULL_HANDLE;
      } else {
        vulkan::ExternalVulkan external;
        external.instance = impl.instance;
        external.physical_device = impl.physical_device;
        external.device = device->device;
        impl.vk.vkGetDeviceQueue(device->device, impl.queue_family, 0, &external.queue);
        external.queue_family_index = impl.queue_family;
        external.get_instance_proc_addr = impl.vk.vkGetInstanceProcAddr;
        external.float64_enabled = true;
        device->context = std::make_shared<vulkan::Context>(vulkan::Context::wrap(external));
        device->context->impl().info.float64_enabled = true;  // Test-only shim, see above.
        made = std::move(device);
      }
    }
  }
  if (reason != nullptr) *reason = why;
  return made ? made->context : nullptr;
}

}  // namespace harmonia::testing

#define HARMONIA_REQUIRE_FLOAT64_TEST_DEVICE()                              \
  do {                                                                      \
    std::string float64_unavailable;                                        \
    if (!::harmonia::testing::float64_test_context(&float64_unavailable))   \
      GTEST_SKIP() << "no fp64 test device: " << float64_unavailable;       \
  } while (false)
