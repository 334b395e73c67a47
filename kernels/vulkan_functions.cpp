#include "kernels/vulkan_functions.h"

#include <dlfcn.h>

#include <string>

#include "harmonia/types.h"

namespace harmonia::vulkan::detail {
namespace {

template <typename Function>
void load(Function& target, PFN_vkVoidFunction address) {
  target = reinterpret_cast<Function>(address);
}

}  // namespace

void VulkanFunctions::load_global(PFN_vkGetInstanceProcAddr entry) {
  if (entry == nullptr) {
    // The loader's SONAME first (what a runtime package installs), then the development link.
    for (const char* name : {"libvulkan.so.1", "libvulkan.so"}) {
      loader_library = dlopen(name, RTLD_NOW | RTLD_LOCAL);
      if (loader_library != nullptr) break;
    }
    if (loader_library == nullptr)
      throw Error(Status::unsupported,
                  "no Vulkan loader: libvulkan.so.1 could not be opened (install the Vulkan "
                  "loader, e.g. Debian's libvulkan1, and a driver)");
    entry =
        reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(loader_library, "vkGetInstanceProcAddr"));
    if (entry == nullptr) {
      close_loader(*this);
      throw Error(Status::unsupported,
                  "the Vulkan loader libvulkan.so.1 has no vkGetInstanceProcAddr");
    }
  }
  vkGetInstanceProcAddr = entry;
#define HARMONIA_VK_LOAD(name) load(name, entry(VK_NULL_HANDLE, #name));
  HARMONIA_VK_GLOBAL_FUNCTIONS(HARMONIA_VK_LOAD)
#undef HARMONIA_VK_LOAD
  if (vkCreateInstance == nullptr || vkEnumerateInstanceLayerProperties == nullptr ||
      vkEnumerateInstanceExtensionProperties == nullptr)
    throw Error(Status::unsupported, "the Vulkan loader lacks the global entry points");
}

void VulkanFunctions::load_instance(VkInstance instance) {
#define HARMONIA_VK_LOAD(name)                                           \
  load(name, vkGetInstanceProcAddr(instance, #name));                    \
  if (name == nullptr)                                                   \
    throw Error(Status::unsupported, "the Vulkan instance has no " #name \
                                     " (Vulkan 1.1 "                     \
                                     "is required)");
  HARMONIA_VK_INSTANCE_FUNCTIONS(HARMONIA_VK_LOAD)
#undef HARMONIA_VK_LOAD
#define HARMONIA_VK_LOAD(name) load(name, vkGetInstanceProcAddr(instance, #name));
  HARMONIA_VK_DEBUG_FUNCTIONS(HARMONIA_VK_LOAD)
#undef HARMONIA_VK_LOAD
}

void VulkanFunctions::load_device(VkDevice device) {
#define HARMONIA_VK_LOAD(name)                    \
  load(name, vkGetDeviceProcAddr(device, #name)); \
  if (name == nullptr)                            \
    throw Error(Status::unsupported, "the Vulkan device has no " #name " (Vulkan 1.1 core)");
  HARMONIA_VK_DEVICE_FUNCTIONS(HARMONIA_VK_LOAD)
#undef HARMONIA_VK_LOAD
}

void close_loader(VulkanFunctions& functions) {
  if (functions.loader_library != nullptr) dlclose(functions.loader_library);
  functions.loader_library = nullptr;
}

std::string result_name(VkResult result) {
  switch (result) {
    case VK_SUCCESS:
      return "VK_SUCCESS";
    case VK_NOT_READY:
      return "VK_NOT_READY";
    case VK_TIMEOUT:
      return "VK_TIMEOUT";
    case VK_INCOMPLETE:
      return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
      return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
      return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
      return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED:
      return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT:
      return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
      return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
      return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
      return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS:
      return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED:
      return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_FRAGMENTED_POOL:
      return "VK_ERROR_FRAGMENTED_POOL";
    case VK_ERROR_OUT_OF_POOL_MEMORY:
      return "VK_ERROR_OUT_OF_POOL_MEMORY";
    default:
      return "VkResult " + std::to_string(static_cast<int>(result));
  }
}

void check(VkResult result, const char* what) {
  if (result == VK_SUCCESS) return;
  std::string message = std::string(what) + " failed: " + result_name(result);
  if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY)
    message += " (the device ran out of memory; try a smaller mesh or the CPU backend)";
  else if (result == VK_ERROR_DEVICE_LOST)
    message += " (the device was lost: driver reset or hang; results are unavailable)";
  throw Error(Status::device_failure, message);
}

}  // namespace harmonia::vulkan::detail
