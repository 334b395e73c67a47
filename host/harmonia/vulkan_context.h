#pragma once
//! \file vulkan_context.h
//! \brief The Vulkan device harmonia computes on: created by harmonia, or borrowed from an engine.
//!
//! Available when harmonia is built with HARMONIA_WITH_VULKAN (the default). Pass a context to a
//! method through SolverOptions::vulkan_context; without one, BackendChoice::vulkan and
//! BackendChoice::automatic create their own (docs/vulkan.md).
//!
//! Ownership: a Context created by Context::create owns its instance and device and destroys them
//! last. A Context made by Context::wrap borrows every handle in ExternalVulkan and never destroys
//! them; the application keeps them alive until the Context and everything computed on it (maps
//! in progress, backends) are gone. harmonia's own objects (command pools, pipelines, buffers)
//! are always created and destroyed by harmonia.
//!
//! Thread safety: a Context may be shared by several threads, each running its own method (its
//! own backend): queue submissions are serialized by the context (and by the application's
//! lock_queue/unlock_queue callbacks for a borrowed queue), and the lazily built pipelines are
//! guarded. Moving or destroying a Context while another thread uses it is not allowed.
//!
//! Waiting: each submission is waited for through the context's timeline semaphore where timeline
//! semaphores are enabled (DeviceInfo::timeline_semaphore), else through a fence. A wait gives up
//! after 5 minutes (no harmonia submission legitimately runs that long) and reports
//! Status::device_failure, as does a lost device; after either, every later submission on the
//! context fails at once with a clear message, and the context can still be destroyed.
//!
//! The library never reads environment variables: the application (or the CLI, or a test
//! harness) chooses the device and whether validation layers run, through ContextOptions.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <vulkan/vulkan_core.h>

namespace harmonia::vulkan {

//! Kinds of physical device, in the order harmonia prefers them.
enum class DeviceType { discrete_gpu, integrated_gpu, virtual_gpu, cpu, other };
//! Short name, e.g. "discrete_gpu", "cpu".
[[nodiscard]] std::string_view to_string(DeviceType type);

//! What harmonia knows about the device it computes on.
struct DeviceInfo {
  std::string name;                       //!< e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  DeviceType type = DeviceType::other;    //!< cpu for software rasterizers such as lavapipe.
  std::uint32_t api_version = 0;          //!< The version harmonia uses (<= the device's).
  std::uint32_t subgroup_size = 1;        //!< Default subgroup size (8 on lavapipe, 32 or 64 GPUs).
  std::uint64_t max_storage_buffer_range = 0;  //!< Largest storage buffer binding, in bytes.
  std::uint64_t device_local_bytes = 0;   //!< Size of the largest device-local memory heap.
  bool unified_memory = false;            //!< Device-local memory is host-visible (no staging).
  bool shader_float64 = false;            //!< The device supports shaderFloat64.
  //! shaderFloat64 is enabled on the VkDevice (ContextOptions::enable_float64 on a device that
  //! has it, or ExternalVulkan::float64_enabled): fp64 kernels may run.
  bool float64_enabled = false;
  //! Timeline semaphores (Vulkan 1.2) are enabled: every submission signals
  //! Context::timeline_semaphore(). Without them harmonia waits on fences.
  bool timeline_semaphore = false;
  bool timestamps = false;                //!< Compute-queue timestamps are available.
};

//! Severity of a message from the validation layer or the driver.
enum class MessageSeverity { verbose, info, warning, error };

//! Receives validation and driver messages (called on the thread that made the Vulkan call).
using DebugCallback = std::function<void(MessageSeverity severity, std::string_view message)>;

//! How Context::create chooses and sets up a device.
struct ContextOptions {
  //! Index into the list of devices as the Vulkan loader enumerates them; overrides the rest.
  std::optional<int> device_index;
  //! Choose the first device whose name contains this text (case-insensitive), e.g. "llvmpipe".
  std::string device_name;
  //! Skip software devices (DeviceType::cpu, e.g. lavapipe). BackendChoice::automatic sets this:
  //! a software device is slower than harmonia's native CPU backend.
  bool hardware_only = false;
  //! Enable shaderFloat64 on the device when it has it (DevicePrecision::float64 asks for this);
  //! off by default, so that harmonia's device needs nothing beyond Vulkan 1.1 core. On a device
  //! without it the context is still created, with DeviceInfo::float64_enabled false.
  bool enable_float64 = false;
  //! Enable VK_LAYER_KHRONOS_validation and route its messages to debug_callback (create fails
  //! with a clear message when the layer is not installed).
  bool enable_validation = false;
  //! Receives validation and driver messages of severity info and above. Without a callback,
  //! warnings and errors are written to stderr when validation is enabled.
  DebugCallback debug_callback;
};

//! An engine's Vulkan objects, lent to harmonia (Context::wrap). All handles are borrowed.
struct ExternalVulkan {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;               //!< Must support compute.
  std::uint32_t queue_family_index = 0;         //!< The family `queue` belongs to.
  std::uint32_t api_version = VK_API_VERSION_1_1;  //!< The version the device was created with.
  //! The loader entry point the engine uses (e.g. from its own loader); when null, harmonia
  //! opens the system loader (libvulkan.so.1).
  PFN_vkGetInstanceProcAddr get_instance_proc_addr = nullptr;
  //! True when the engine enabled shaderFloat64 on `device` (harmonia then may run fp64 kernels
  //! when asked for DevicePrecision::float64; it never assumes a feature the engine did not enable).
  bool float64_enabled = false;
  //! True when the engine created `device` with Vulkan 1.2 (api_version) and enabled the
  //! timelineSemaphore feature: harmonia then signals its own timeline semaphore with every
  //! submission (Context::timeline_semaphore) instead of only a fence, so that the engine's
  //! submissions can wait on harmonia's work.
  bool timeline_semaphore_enabled = false;
  //! Optional: pipelines are created through this cache (harmonia never destroys it).
  VkPipelineCache pipeline_cache = VK_NULL_HANDLE;
  //! Optional: used for every object harmonia creates on the device; must outlive the Context.
  const VkAllocationCallbacks* allocation_callbacks = nullptr;
  //! Optional: called around every vkQueueSubmit when the engine submits to the same queue
  //! from other threads (the queue is externally synchronized in Vulkan).
  std::function<void()> lock_queue;
  std::function<void()> unlock_queue;
};

//! A Vulkan instance, physical device, logical device and compute queue. Move-only RAII.
class Context {
 public:
  //! Creates an instance and a device: the device chosen by index or name, otherwise the most
  //! capable one (discrete, then integrated, virtual, cpu). Needs Vulkan 1.1. Enables
  //! shaderFloat64 when asked for (ContextOptions::enable_float64) and present, and timeline
  //! semaphores when the device has Vulkan 1.2 with them; no other optional feature.
  //! \throw harmonia::Error with Status::unsupported when there is no Vulkan loader, no suitable
  //! device (the message lists the devices seen and why each was passed over) or no validation
  //! layer although one was asked for; Status::device_failure when the driver fails.
  [[nodiscard]] static Context create(const ContextOptions& options = {});
  //! Borrows an engine's objects; harmonia then requires no device feature beyond Vulkan 1.1 core
  //! and uses fp64 and timeline semaphores only when ExternalVulkan says the engine enabled them.
  //! \throw harmonia::Error (Status::unsupported) for a null handle, a queue family without
  //! compute, an API version below 1.1, or timeline_semaphore_enabled below Vulkan 1.2.
  [[nodiscard]] static Context wrap(const ExternalVulkan& external);

  Context(Context&& other) noexcept;
  Context& operator=(Context&& other) noexcept;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  ~Context();

  //! The device in use. \pre the context was not moved from.
  [[nodiscard]] const DeviceInfo& device() const;
  //! True when the handles are borrowed (Context::wrap).
  [[nodiscard]] bool borrowed() const;

  //! The timeline semaphore (owned by the context) that every harmonia submission on this context
  //! signals with the next value, 1, 2, 3, ...; VK_NULL_HANDLE when DeviceInfo::timeline_semaphore
  //! is false. An engine makes its own vkQueueSubmit wait for harmonia's work through it (a
  //! VkTimelineSemaphoreSubmitInfo wait value), or polls it with vkGetSemaphoreCounterValue; the
  //! value of one launched map's work comes from PendingMap::device_signal_value (harmonia/async.h).
  //! Never signal or destroy it. Valid until the Context is destroyed.
  [[nodiscard]] VkSemaphore timeline_semaphore() const;
  //! The timeline value that the latest submission on this context signals (0 before any, and
  //! without timeline semaphores). Any thread.
  [[nodiscard]] std::uint64_t last_submission_value() const;

  //! Internal state (kernels/context_impl.h); not part of the stable API.
  struct Impl;
  [[nodiscard]] Impl& impl() const;

 private:
  explicit Context(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace harmonia::vulkan
