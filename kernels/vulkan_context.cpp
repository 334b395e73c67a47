// harmonia::vulkan::Context: creating or borrowing the instance, device and compute queue.

#include "harmonia/vulkan_context.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "harmonia/types.h"
#include "kernels/context_impl.h"
#include "kernels/device_selection.h"
#include "kernels/pipelines.h"

namespace harmonia::vulkan {
namespace {

constexpr const char* validation_layer = "VK_LAYER_KHRONOS_validation";

MessageSeverity severity_of(VkDebugUtilsMessageSeverityFlagBitsEXT severity) {
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) return MessageSeverity::error;
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return MessageSeverity::warning;
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT) return MessageSeverity::info;
  return MessageSeverity::verbose;
}

// Forwards a validation or driver message to the context's callback (user_data is the Impl, whose
// address is stable: the Context holds it by unique_ptr).
VKAPI_ATTR VkBool32 VKAPI_CALL forward_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                               VkDebugUtilsMessageTypeFlagsEXT,
                                               const VkDebugUtilsMessengerCallbackDataEXT* data,
                                               void* user_data) {
  const auto* context = static_cast<const Context::Impl*>(user_data);
  const std::string_view message =
      data != nullptr && data->pMessage != nullptr ? data->pMessage : "";
  const MessageSeverity level = severity_of(severity);
  if (context != nullptr && context->debug_callback)
    context->debug_callback(level, message);
  else if (level == MessageSeverity::warning || level == MessageSeverity::error)
    std::cerr << "harmonia vulkan: " << message << '\n';
  return VK_FALSE;  // Never abort the call that triggered the message.
}

VkDebugUtilsMessengerCreateInfoEXT messenger_info(Context::Impl* context) {
  auto info = detail::vk_info<VkDebugUtilsMessengerCreateInfoEXT>(
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
  info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  info.pfnUserCallback = forward_message;
  info.pUserData = context;
  return info;
}

bool layer_available(const detail::VulkanFunctions& vk, const char* name) {
  std::uint32_t count = 0;
  detail::check(vk.vkEnumerateInstanceLayerProperties(&count, nullptr),
                "vkEnumerateInstanceLayerProperties");
  std::vector<VkLayerProperties> layers(count);
  detail::check(vk.vkEnumerateInstanceLayerProperties(&count, layers.data()),
                "vkEnumerateInstanceLayerProperties");
  return std::any_of(layers.begin(), layers.end(), [name](const VkLayerProperties& layer) {
    return std::strcmp(layer.layerName, name) == 0;
  });
}

std::uint32_t instance_version(const detail::VulkanFunctions& vk) {
  std::uint32_t version = VK_API_VERSION_1_0;  // A 1.0 loader has no vkEnumerateInstanceVersion.
  if (vk.vkEnumerateInstanceVersion != nullptr)
    detail::check(vk.vkEnumerateInstanceVersion(&version), "vkEnumerateInstanceVersion");
  return version;
}

void create_instance(Context::Impl& context, const ContextOptions& options) {
  detail::VulkanFunctions& vk = context.vk;
  if (instance_version(vk) < VK_API_VERSION_1_1)
    throw Error(Status::unsupported,
                "the Vulkan loader supports only Vulkan 1.0 (1.1 is required)");
  std::vector<const char*> layers, extensions;
  if (options.enable_validation) {
    if (!layer_available(vk, validation_layer))
      throw Error(Status::unsupported,
                  "Vulkan validation was requested but VK_LAYER_KHRONOS_validation is not "
                  "installed (Debian: vulkan-validationlayers)");
    layers.push_back(validation_layer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  auto application = detail::vk_info<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  application.pApplicationName = "harmonia";
  application.pEngineName = "harmonia";
  // Vulkan 1.2 where the loader has it, so that timeline semaphores can be used on 1.2 devices;
  // the kernels themselves need only 1.1.
  application.apiVersion =
      instance_version(vk) >= VK_API_VERSION_1_2 ? VK_API_VERSION_1_2 : VK_API_VERSION_1_1;
  context.info.api_version = application.apiVersion;
  auto info = detail::vk_info<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  info.pApplicationInfo = &application;
  info.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  // Chained, the messenger also reports on vkCreateInstance and vkDestroyInstance themselves.
  VkDebugUtilsMessengerCreateInfoEXT debug_info = messenger_info(&context);
  if (options.enable_validation) info.pNext = &debug_info;
  const VkResult result = vk.vkCreateInstance(&info, nullptr, &context.instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw Error(Status::unsupported,
                "no Vulkan driver: the loader found no installable client driver (ICD) "
                "supporting Vulkan 1.1 (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER)");
  detail::check(result, "vkCreateInstance");
  context.owns_instance = true;
  vk.load_instance(context.instance);
  context.sync.load_instance(vk, context.instance);
  if (options.enable_validation) {
    if (vk.vkCreateDebugUtilsMessengerEXT == nullptr)
      throw Error(Status::unsupported, "validation: VK_EXT_debug_utils is not available");
    detail::check(vk.vkCreateDebugUtilsMessengerEXT(context.instance, &debug_info, nullptr,
                                                    &context.messenger),
                  "vkCreateDebugUtilsMessengerEXT");
  }
}

// The optional features harmonia may enable: what the device has of them.
struct OptionalFeatures {
  bool float64 = false;
  bool timeline_semaphore = false;
};

OptionalFeatures optional_features(const Context::Impl& context, VkPhysicalDevice device,
                                   std::uint32_t api_version) {
  auto timeline = detail::vk_info<VkPhysicalDeviceTimelineSemaphoreFeatures>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_TIMELINE_SEMAPHORE_FEATURES);
  auto features =
      detail::vk_info<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
  // The timeline structure is only known to Vulkan 1.2 (core) devices.
  if (api_version >= VK_API_VERSION_1_2) features.pNext = &timeline;
  context.sync.vkGetPhysicalDeviceFeatures2(device, &features);
  return OptionalFeatures{features.features.shaderFloat64 == VK_TRUE,
                          timeline.timelineSemaphore == VK_TRUE};
}

void create_device(Context::Impl& context, const detail::DeviceChoice& choice,
                   const ContextOptions& options) {
  VkPhysicalDeviceProperties properties{};
  context.vk.vkGetPhysicalDeviceProperties(choice.device, &properties);
  const std::uint32_t api_version = std::min(properties.apiVersion, context.info.api_version);
  const OptionalFeatures available = optional_features(context, choice.device, api_version);

  const float priority = 1.0f;
  auto queue_info =
      detail::vk_info<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queue_info.queueFamilyIndex = choice.queue_family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  // The fp32 kernels need only Vulkan 1.1 core. Optional: shaderFloat64 when asked for (fp64
  // kernels), timeline semaphores when present (submit now, wait later); nothing else.
  auto timeline = detail::vk_info<VkPhysicalDeviceTimelineSemaphoreFeatures>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_TIMELINE_SEMAPHORE_FEATURES);
  timeline.timelineSemaphore = available.timeline_semaphore ? VK_TRUE : VK_FALSE;
  auto features =
      detail::vk_info<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
  features.features.shaderFloat64 =
      options.enable_float64 && available.float64 ? VK_TRUE : VK_FALSE;
  if (available.timeline_semaphore) features.pNext = &timeline;
  auto info = detail::vk_info<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  info.pNext = &features;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue_info;
  detail::check(context.vk.vkCreateDevice(choice.device, &info, nullptr, &context.device),
                "vkCreateDevice");
  context.owns_device = true;
  context.physical_device = choice.device;
  context.queue_family = choice.queue_family;
  context.info.float64_enabled = features.features.shaderFloat64 == VK_TRUE;
  context.info.timeline_semaphore = available.timeline_semaphore;
  context.vk.load_device(context.device);
  context.sync.load_device(context.vk, context.device);
  context.vk.vkGetDeviceQueue(context.device, choice.queue_family, 0, &context.queue);
}

// The thread's submission observer (detail::observe_submissions).
thread_local detail::SubmissionObserver* thread_observer = nullptr;

}  // namespace

std::string_view to_string(DeviceType type) {
  switch (type) {
    case DeviceType::discrete_gpu:
      return "discrete_gpu";
    case DeviceType::integrated_gpu:
      return "integrated_gpu";
    case DeviceType::virtual_gpu:
      return "virtual_gpu";
    case DeviceType::cpu:
      return "cpu";
    case DeviceType::other:
      return "other";
  }
  return "other";
}

Context::Impl::Impl() = default;

Context::Impl::~Impl() {
  // Our own objects first, then what we own of the device and instance; borrowed ones stay. A
  // context whose creation failed half-way has null handles (or null entry points) beyond the
  // failure, which are skipped. Work held back by an injected hang is let go first, so that the
  // device can go idle.
  open_hang_gate();
  if (owns_device && device != VK_NULL_HANDLE && vk.vkDeviceWaitIdle != nullptr)
    vk.vkDeviceWaitIdle(device);
  pipelines.reset();
  if (timeline != VK_NULL_HANDLE) sync.vkDestroySemaphore(device, timeline, allocator);
  if (hang_gate_ != VK_NULL_HANDLE) sync.vkDestroySemaphore(device, hang_gate_, allocator);
  if (owns_pipeline_cache && pipeline_cache != VK_NULL_HANDLE)
    vk.vkDestroyPipelineCache(device, pipeline_cache, allocator);
  if (owns_device && device != VK_NULL_HANDLE && vk.vkDestroyDevice != nullptr)
    vk.vkDestroyDevice(device, nullptr);
  if (messenger != VK_NULL_HANDLE) vk.vkDestroyDebugUtilsMessengerEXT(instance, messenger, nullptr);
  if (owns_instance && instance != VK_NULL_HANDLE && vk.vkDestroyInstance != nullptr)
    vk.vkDestroyInstance(instance, nullptr);
  detail::close_loader(vk);
}

std::uint64_t Context::Impl::submit(VkCommandBuffer commands, VkFence fence) {
  const std::lock_guard lock(queue_mutex_);
  if (device_lost())
    throw Error(Status::device_failure,
                "the Vulkan device (" + info.name +
                    ") was lost or stopped responding earlier; its results are unavailable. "
                    "Create a new context, or use the CPU backend");
  const std::uint64_t value = timeline != VK_NULL_HANDLE ? next_value_ : 0;
  auto submit_info = detail::vk_info<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit_info.commandBufferCount = 1;
  submit_info.pCommandBuffers = &commands;
  auto timeline_info = detail::vk_info<VkTimelineSemaphoreSubmitInfo>(
      VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO);
  if (timeline != VK_NULL_HANDLE) {
    submit_info.signalSemaphoreCount = 1;
    submit_info.pSignalSemaphores = &timeline;
    timeline_info.signalSemaphoreValueCount = 1;
    timeline_info.pSignalSemaphoreValues = &value;
    submit_info.pNext = &timeline_info;
  }
  const detail::SubmissionFault fault = faults.next_submission();
  VkSemaphore gate = VK_NULL_HANDLE;
  const std::uint64_t gate_value = 1;
  const VkPipelineStageFlags gate_stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
  if (fault == detail::SubmissionFault::hang) {
    gate = hang_gate();
    submit_info.waitSemaphoreCount = 1;
    submit_info.pWaitSemaphores = &gate;
    submit_info.pWaitDstStageMask = &gate_stage;
    timeline_info.waitSemaphoreValueCount = 1;
    timeline_info.pWaitSemaphoreValues = &gate_value;
  }
  VkResult result = VK_ERROR_DEVICE_LOST;
  if (fault != detail::SubmissionFault::device_lost) {
    if (lock_queue) lock_queue();
    result = vk.vkQueueSubmit(queue, 1, &submit_info, fence);
    if (unlock_queue) unlock_queue();
  }
  if (result == VK_ERROR_DEVICE_LOST) device_lost_ = true;
  detail::check(result, "vkQueueSubmit");
  ++submission_count_;
  if (timeline != VK_NULL_HANDLE) {
    ++next_value_;
    last_submitted_ = value;
    detail::SubmissionObserver* observer = thread_observer;
    if (observer != nullptr && observer->context == this && observer->value != nullptr)
      observer->value->store(value);
  }
  return value;
}

std::uint64_t Context::Impl::completed_value() const {
  if (timeline == VK_NULL_HANDLE) return 0;
  std::uint64_t value = 0;
  const VkResult result = sync.vkGetSemaphoreCounterValue(device, timeline, &value);
  if (result == VK_ERROR_DEVICE_LOST) device_lost_ = true;
  detail::check(result, "reading the timeline (vkGetSemaphoreCounterValue)");
  return value;
}

void Context::Impl::wait_for_value(std::uint64_t value) {
  auto wait_info = detail::vk_info<VkSemaphoreWaitInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO);
  wait_info.semaphoreCount = 1;
  wait_info.pSemaphores = &timeline;
  wait_info.pValues = &value;
  check_wait(sync.vkWaitSemaphores(device, &wait_info, wait_timeout_ns.load()),
             "waiting for the device (vkWaitSemaphores)");
}

void Context::Impl::check_wait(VkResult result, const char* what) {
  if (result == VK_SUCCESS) return;
  if (result == VK_TIMEOUT) {
    // Treated as a hang: the device is given up on (as a driver's watchdog would reset it).
    device_lost_ = true;
    bool released = false;
    {
      const std::lock_guard lock(queue_mutex_);
      released = open_hang_gate();
    }
    // Work held back by an injected hang now runs: let it finish before the caller unwinds and
    // destroys the buffers it uses. (A real hang has no gate; its objects are the driver's.)
    if (released) {
      const std::uint64_t last = last_submitted_.load();
      auto drain = detail::vk_info<VkSemaphoreWaitInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO);
      drain.semaphoreCount = 1;
      drain.pSemaphores = &timeline;
      drain.pValues = &last;
      (void)sync.vkWaitSemaphores(device, &drain, wait_timeout_ns.load());
    }
    char seconds[32];
    std::snprintf(seconds, sizeof(seconds), "%.3g", static_cast<double>(wait_timeout_ns) * 1e-9);
    throw Error(Status::device_failure,
                std::string(what) + ": the device (" + info.name + ") did not finish within " +
                    seconds +
                    " s and is treated as hung; its results are unavailable. Create a new "
                    "context, or use the CPU backend");
  }
  if (result == VK_ERROR_DEVICE_LOST) device_lost_ = true;
  detail::check(result, what);
}

VkSemaphore Context::Impl::hang_gate() {
  if (timeline == VK_NULL_HANDLE)
    throw std::logic_error("fault injection: a hang needs timeline semaphores on the device");
  if (hang_gate_ == VK_NULL_HANDLE) {
    auto type = detail::vk_info<VkSemaphoreTypeCreateInfo>(
        VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO);
    type.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
    auto info_create =
        detail::vk_info<VkSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO);
    info_create.pNext = &type;
    detail::check(sync.vkCreateSemaphore(device, &info_create, allocator, &hang_gate_),
                  "vkCreateSemaphore (hang gate)");
  }
  return hang_gate_;
}

bool Context::Impl::open_hang_gate() noexcept {
  if (hang_gate_ == VK_NULL_HANDLE) return false;
  std::uint64_t opened = 0;
  if (sync.vkGetSemaphoreCounterValue(device, hang_gate_, &opened) != VK_SUCCESS || opened > 0)
    return false;
  auto signal = detail::vk_info<VkSemaphoreSignalInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_SIGNAL_INFO);
  signal.semaphore = hang_gate_;
  signal.value = 1;
  return sync.vkSignalSemaphore(device, &signal) == VK_SUCCESS;
}

void Context::Impl::prepare_timeline() {
  if (!info.timeline_semaphore) return;
  if (sync.vkWaitSemaphores == nullptr || sync.vkGetSemaphoreCounterValue == nullptr ||
      sync.vkSignalSemaphore == nullptr)
    throw Error(Status::unsupported,
                "timeline semaphores are enabled but the device has no vkWaitSemaphores "
                "(Vulkan 1.2 core)");
  auto type =
      detail::vk_info<VkSemaphoreTypeCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO);
  type.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
  type.initialValue = 0;
  auto info_create =
      detail::vk_info<VkSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO);
  info_create.pNext = &type;
  detail::check(sync.vkCreateSemaphore(device, &info_create, allocator, &timeline),
                "vkCreateSemaphore (timeline)");
}

void Context::Impl::describe_device() {
  auto subgroup = detail::vk_info<VkPhysicalDeviceSubgroupProperties>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES);
  auto properties =
      detail::vk_info<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
  properties.pNext = &subgroup;
  vk.vkGetPhysicalDeviceProperties2(physical_device, &properties);
  VkPhysicalDeviceFeatures features{};
  vk.vkGetPhysicalDeviceFeatures(physical_device, &features);
  vk.vkGetPhysicalDeviceMemoryProperties(physical_device, &memory);
  limits = properties.properties.limits;
  timestamp_period_ns = limits.timestampPeriod;

  info.name = properties.properties.deviceName;
  info.type = detail::device_type(properties.properties.deviceType);
  info.api_version = std::min(properties.properties.apiVersion, info.api_version);
  info.subgroup_size = std::max(1u, subgroup.subgroupSize);
  info.max_storage_buffer_range = limits.maxStorageBufferRange;
  info.shader_float64 = features.shaderFloat64 == VK_TRUE;
  for (std::uint32_t heap = 0; heap < memory.memoryHeapCount; ++heap) {
    if (memory.memoryHeaps[heap].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      info.device_local_bytes =
          std::max<std::uint64_t>(info.device_local_bytes, memory.memoryHeaps[heap].size);
  }
  // Unified memory: an integrated or software device whose device-local memory is host-visible
  // and coherent, so buffers are written in place instead of through a staging copy. (A discrete
  // GPU's small host-visible BAR window does not count.)
  const VkMemoryPropertyFlags unified_flags = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT |
                                              VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                              VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  bool has_unified_type = false;
  for (std::uint32_t type = 0; type < memory.memoryTypeCount; ++type)
    has_unified_type = has_unified_type ||
                       (memory.memoryTypes[type].propertyFlags & unified_flags) == unified_flags;
  info.unified_memory =
      has_unified_type && (info.type == DeviceType::integrated_gpu || info.type == DeviceType::cpu);

  std::uint32_t family_count = 0;
  vk.vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vk.vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &family_count, families.data());
  info.timestamps = queue_family < family_count && families[queue_family].timestampValidBits > 0 &&
                    limits.timestampPeriod > 0.0f;
  if (info.timestamps && families[queue_family].timestampValidBits < 64)
    timestamp_mask = (std::uint64_t{1} << families[queue_family].timestampValidBits) - 1;

  // Workgroup width: a power of two (the tree reductions need one), never above the limits. 256 on
  // GPUs (enough work per group to hide latency); 64 on CPU devices such as lavapipe, which run a
  // group's invocations in a loop around every barrier, so that wide trees cost more than they
  // bring (measured: the dot product got 10x faster on lavapipe going from 256 to 64). The tree
  // reductions keep one real per invocation in shared memory (shaders/common/tree_sum.glsl): 8
  // bytes in the fp64 kernels, so the width must fit maxComputeSharedMemorySize / 8.
  std::uint32_t width = info.type == DeviceType::cpu ? 64 : 256;
  constexpr std::uint32_t largest_shared_real_bytes = sizeof(double);
  const std::uint32_t cap =
      std::min({limits.maxComputeWorkGroupSize[0], limits.maxComputeWorkGroupInvocations,
                limits.maxComputeSharedMemorySize / largest_shared_real_bytes});
  while (width > cap && width > 1) width /= 2;
  workgroup_size = width;
  reduction_groups = info.type == DeviceType::cpu ? 64 : 1024;
  std::uint32_t lanes = std::min(info.subgroup_size, 32u);
  while (lanes > width) lanes /= 2;
  lanes_per_row = std::max(1u, lanes);
}

void Context::Impl::prepare_pipelines(VkPipelineCache lent_cache) {
  if (lent_cache != VK_NULL_HANDLE) {
    pipeline_cache = lent_cache;
  } else {
    auto info =
        detail::vk_info<VkPipelineCacheCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO);
    detail::check(vk.vkCreatePipelineCache(device, &info, allocator, &pipeline_cache),
                  "vkCreatePipelineCache");
    owns_pipeline_cache = true;
  }
  pipelines = std::make_unique<detail::PipelineLibrary>(*this);
}

Context Context::create(const ContextOptions& options) {
  auto impl = std::make_unique<Impl>();
  impl->debug_callback = options.debug_callback;
  impl->vk.load_global(nullptr);
  create_instance(*impl, options);
  const detail::DeviceChoice choice = detail::choose_device(impl->vk, impl->instance, options);
  create_device(*impl, choice, options);
  impl->describe_device();
  impl->prepare_timeline();
  impl->prepare_pipelines(VK_NULL_HANDLE);
  return Context(std::move(impl));
}

Context Context::wrap(const ExternalVulkan& external) {
  if (external.instance == VK_NULL_HANDLE || external.physical_device == VK_NULL_HANDLE ||
      external.device == VK_NULL_HANDLE || external.queue == VK_NULL_HANDLE)
    throw Error(Status::unsupported,
                "Context::wrap: instance, physical device, device and queue must all be given");
  if (external.api_version < VK_API_VERSION_1_1)
    throw Error(Status::unsupported,
                "Context::wrap: the device must be created with Vulkan 1.1 "
                "or later (api_version)");
  if (external.timeline_semaphore_enabled && external.api_version < VK_API_VERSION_1_2)
    throw Error(Status::unsupported,
                "Context::wrap: timeline_semaphore_enabled needs a device created with Vulkan 1.2 "
                "or later (api_version)");
  if (static_cast<bool>(external.lock_queue) != static_cast<bool>(external.unlock_queue))
    throw Error(Status::unsupported,
                "Context::wrap: give both lock_queue and unlock_queue, or neither");
  auto impl = std::make_unique<Impl>();
  impl->vk.load_global(external.get_instance_proc_addr);
  impl->instance = external.instance;
  impl->vk.load_instance(external.instance);
  impl->sync.load_instance(impl->vk, external.instance);
  impl->physical_device = external.physical_device;
  impl->device = external.device;
  impl->queue = external.queue;
  impl->queue_family = external.queue_family_index;
  impl->allocator = external.allocation_callbacks;
  impl->lock_queue = external.lock_queue;
  impl->unlock_queue = external.unlock_queue;
  std::uint32_t family_count = 0;
  impl->vk.vkGetPhysicalDeviceQueueFamilyProperties(external.physical_device, &family_count,
                                                    nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  impl->vk.vkGetPhysicalDeviceQueueFamilyProperties(external.physical_device, &family_count,
                                                    families.data());
  if (external.queue_family_index >= family_count ||
      (families[external.queue_family_index].queueFlags & VK_QUEUE_COMPUTE_BIT) == 0)
    throw Error(Status::unsupported, "Context::wrap: queue family " +
                                         std::to_string(external.queue_family_index) +
                                         " does not support compute");
  impl->vk.load_device(external.device);
  impl->sync.load_device(impl->vk, external.device);
  impl->info.api_version = external.api_version;
  impl->describe_device();
  // Features are the engine's to enable: harmonia takes its word for them.
  if (external.float64_enabled && !impl->info.shader_float64)
    throw Error(Status::unsupported, "Context::wrap: float64_enabled, but the device (" +
                                         impl->info.name + ") has no shaderFloat64");
  impl->info.float64_enabled = external.float64_enabled;
  impl->info.timeline_semaphore = external.timeline_semaphore_enabled;
  impl->prepare_timeline();
  impl->prepare_pipelines(external.pipeline_cache);
  return Context(std::move(impl));
}

Context::Context(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Context::Context(Context&& other) noexcept = default;
Context& Context::operator=(Context&& other) noexcept = default;
Context::~Context() = default;

const DeviceInfo& Context::device() const { return impl().info; }
bool Context::borrowed() const { return !impl().owns_device; }
VkSemaphore Context::timeline_semaphore() const { return impl().timeline; }
std::uint64_t Context::last_submission_value() const { return impl().last_submitted_value(); }

Context::Impl& Context::impl() const {
  if (!impl_) throw std::logic_error("harmonia::vulkan::Context: used after being moved from");
  return *impl_;
}

namespace detail {

void SubmissionFunctions::load_instance(const VulkanFunctions& vk, VkInstance instance) {
  vkGetPhysicalDeviceFeatures2 = reinterpret_cast<PFN_vkGetPhysicalDeviceFeatures2>(
      vk.vkGetInstanceProcAddr(instance, "vkGetPhysicalDeviceFeatures2"));
  if (vkGetPhysicalDeviceFeatures2 == nullptr)
    throw Error(Status::unsupported,
                "the Vulkan instance has no vkGetPhysicalDeviceFeatures2 (Vulkan 1.1 core)");
}

void SubmissionFunctions::load_device(const VulkanFunctions& vk, VkDevice device) {
  const auto load = [&vk, device](auto& entry, const char* name) {
    entry = reinterpret_cast<std::remove_reference_t<decltype(entry)>>(
        vk.vkGetDeviceProcAddr(device, name));
  };
  load(vkCreateSemaphore, "vkCreateSemaphore");
  load(vkDestroySemaphore, "vkDestroySemaphore");
  load(vkGetFenceStatus, "vkGetFenceStatus");
  if (vkCreateSemaphore == nullptr || vkDestroySemaphore == nullptr || vkGetFenceStatus == nullptr)
    throw Error(Status::unsupported, "the Vulkan device lacks semaphore or fence entry points");
  load(vkWaitSemaphores, "vkWaitSemaphores");
  load(vkGetSemaphoreCounterValue, "vkGetSemaphoreCounterValue");
  load(vkSignalSemaphore, "vkSignalSemaphore");
}

SubmissionObserver* observe_submissions(SubmissionObserver* observer) {
  return std::exchange(thread_observer, observer);
}

}  // namespace detail
}  // namespace harmonia::vulkan
