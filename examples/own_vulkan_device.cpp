// An application that owns its Vulkan device lends it to harmonia, as an engine would: it creates
// the VkInstance, picks the physical device, creates the VkDevice and its compute queue, and hands
// them to harmonia::vulkan::Context::wrap. harmonia creates its own objects on that device
// (pipelines, buffers) and destroys them with its context; the application destroys its device and
// instance after that. The same map runs on the device and on the CPU backend, and the two
// layouts are compared.
//   own_vulkan_device [--validation]
// --validation: the Khronos validation layer checks every Vulkan call, the application's and
// harmonia's; each warning or error is printed and makes the exit status 1.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include <vulkan/vulkan.h>

#include <harmonia/fixed_boundary_map.h>
#include <harmonia/procedural.h>
#include <harmonia/vulkan_context.h>

namespace {

constexpr int kNoVulkanDevice = 77;  // "skipped" for CTest: nothing to run on here

int validation_messages = 0;  // counted by the messenger: any of them fails the run

VKAPI_ATTR VkBool32 VKAPI_CALL print_validation_message(
    VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
    const VkDebugUtilsMessengerCallbackDataEXT* message, void*) {
  ++validation_messages;
  std::fprintf(stderr, "validation: %s\n", message->pMessage);
  return VK_FALSE;  // the call goes on
}

struct ComputeDevice {
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;  // a family with compute
  VkPhysicalDeviceProperties properties{};
};

// A device with Vulkan 1.1 (what harmonia needs) and a compute queue; a discrete GPU if any.
std::optional<ComputeDevice> pick_compute_device(VkInstance instance) {
  std::uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance, &count, devices.data());
  const auto discrete = [](const ComputeDevice& option) {
    return option.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
  };
  std::optional<ComputeDevice> chosen;
  for (VkPhysicalDevice device : devices) {
    ComputeDevice candidate{device, 0, {}};
    vkGetPhysicalDeviceProperties(device, &candidate.properties);
    std::uint32_t family_count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> families(family_count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &family_count, families.data());
    while (candidate.queue_family < family_count &&
           !(families[candidate.queue_family].queueFlags & VK_QUEUE_COMPUTE_BIT))
      ++candidate.queue_family;
    const bool usable = candidate.properties.apiVersion >= VK_API_VERSION_1_1 &&
                        candidate.queue_family < family_count;
    if (usable && (!chosen || (discrete(candidate) && !discrete(*chosen)))) chosen = candidate;
  }
  return chosen;
}

void print_run(const char* where, const harmonia::SolveReport& report) {
  if (!report.ok()) {
    std::fprintf(stderr, "%-7s %s\n", where, report.message.c_str());
    return;
  }
  std::printf("%-7s %s: %s, %s, %d iterations, residual %.1e, %.1f ms\n", where,
              report.device.c_str(), report.solver.c_str(), report.precision.c_str(),
              report.iterations, report.residual, 1e3 * report.total_seconds());
}

// harmonia's part: every harmonia object lives in this function and is gone when it returns.
int map_on_device_and_cpu(const harmonia::vulkan::ExternalVulkan& lent) {
  const harmonia::Mesh mesh = harmonia::demo_surface(24);
  harmonia::FixedBoundaryOptions options;
  options.solver.backend = harmonia::BackendChoice::vulkan;
  options.solver.vulkan_context =
      std::make_shared<harmonia::vulkan::Context>(harmonia::vulkan::Context::wrap(lent));
  const harmonia::MapResult on_device = harmonia::fixed_boundary_map(mesh, options);
  options.solver = {};  // the same map on the CPU backend
  options.solver.backend = harmonia::BackendChoice::cpu;
  const harmonia::MapResult on_cpu = harmonia::fixed_boundary_map(mesh, options);
  print_run("device", on_device.report);
  print_run("cpu", on_cpu.report);
  if (!on_device.report.ok() || !on_cpu.report.ok()) return 1;
  const double size = on_cpu.uv.cwiseAbs().maxCoeff();
  std::printf("largest difference %.1e of the layout's size, over %d vertices\n",
              (on_device.uv - on_cpu.uv).cwiseAbs().maxCoeff() / size, mesh.vertex_count());
  return 0;
}

// The application's device, with one compute queue and no optional feature: lent to harmonia for
// the maps, destroyed by the application once harmonia is done with it.
int run_on_own_device(VkInstance instance, const ComputeDevice& chosen) {
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{};
  queue_info.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue_info.queueFamilyIndex = chosen.queue_family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{};
  device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  VkDevice device = VK_NULL_HANDLE;
  if (vkCreateDevice(chosen.physical_device, &device_info, nullptr, &device) != VK_SUCCESS) {
    std::fprintf(stderr, "vkCreateDevice failed on %s\n", chosen.properties.deviceName);
    return 1;
  }
  harmonia::vulkan::ExternalVulkan lent;  // harmonia borrows every handle and destroys none
  lent.instance = instance;
  lent.physical_device = chosen.physical_device;
  lent.device = device;
  vkGetDeviceQueue(device, chosen.queue_family, 0, &lent.queue);
  lent.queue_family_index = chosen.queue_family;
  lent.api_version = VK_API_VERSION_1_1;
  lent.get_instance_proc_addr = vkGetInstanceProcAddr;  // the loader this program links
  int status = 1;
  try {
    status = map_on_device_and_cpu(lent);
  } catch (const harmonia::Error& error) {  // the device failed or was lost
    std::fprintf(stderr, "%s\n", error.what());
  }
  // harmonia's context and everything made on it are gone: the device can go.
  vkDeviceWaitIdle(device);
  vkDestroyDevice(device, nullptr);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  const bool validation = argc > 1 && std::strcmp(argv[1], "--validation") == 0;

  // The instance; with --validation, the layer and a messenger for its warnings and errors (also
  // chained to the instance's own creation and destruction, so that they are checked too).
  VkDebugUtilsMessengerCreateInfoEXT messenger_info{};
  messenger_info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  messenger_info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger_info.pfnUserCallback = print_validation_message;
  const char* layer = "VK_LAYER_KHRONOS_validation";
  const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  VkApplicationInfo application{};
  application.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  application.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo instance_info{};
  instance_info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  instance_info.pApplicationInfo = &application;
  if (validation) {
    instance_info.pNext = &messenger_info;
    instance_info.enabledLayerCount = 1;
    instance_info.ppEnabledLayerNames = &layer;
    instance_info.enabledExtensionCount = 1;
    instance_info.ppEnabledExtensionNames = &extension;
  }
  VkInstance instance = VK_NULL_HANDLE;
  if (vkCreateInstance(&instance_info, nullptr, &instance) != VK_SUCCESS) {
    std::printf("no Vulkan device: no driver%s\n", validation ? ", or no validation layer" : "");
    return kNoVulkanDevice;
  }
  const auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
  const auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  if (validation) create_messenger(instance, &messenger_info, nullptr, &messenger);

  int status = kNoVulkanDevice;
  if (const std::optional<ComputeDevice> chosen = pick_compute_device(instance))
    status = run_on_own_device(instance, *chosen);
  else
    std::printf("no Vulkan device: none with Vulkan 1.1 and a compute queue\n");

  if (validation) destroy_messenger(instance, messenger, nullptr);
  vkDestroyInstance(instance, nullptr);
  if (validation_messages > 0) {
    std::fprintf(stderr, "%d validation messages\n", validation_messages);
    return 1;
  }
  return status;
}
