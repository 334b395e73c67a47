#pragma once
// Internal: compute pipelines built from the SPIR-V embedded at build time, created lazily (on
// first use) and kept for the lifetime of the context.
//
// Every shader declares `layout(local_size_x_id = 0) in;` and may declare
// `layout(constant_id = 1) const uint lanes_per_row`; both are specialization constants filled
// from the device's limits and subgroup size (Context::Impl::workgroup_size, lanes_per_row), so
// no shader hard-codes a width. Bindings are storage buffers 0..buffer_count-1 in set 0.

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>

#include "harmonia/solver_options.h"
#include "kernels/context_impl.h"

namespace harmonia::vulkan::detail {

// One shader as embedded in the library (defined in kernels/<shader name>.cpp). The fp32
// variant is the program the kernels name (<name>_program); it points to its fp64 twin, the same
// source compiled with HARMONIA_FP64 (shaders/common/real.glsl), which only runs on a device with
// shaderFloat64 enabled.
struct KernelProgram {
  const char* name;            // The shader's file name without .comp, for messages.
  const std::uint32_t* spirv;  // The <name>_spv (or <name>_fp64_spv) array.
  std::size_t spirv_bytes;
  std::uint32_t buffer_count;         // Storage buffers at bindings 0..buffer_count-1.
  std::uint32_t push_constant_bytes;  // sizeof the kernel's <Name>Push struct.
  const KernelProgram* float64_twin = nullptr;  // Set on the fp32 variant only.
};

// The variant of `program` (an fp32 <name>_program) for `precision`.
[[nodiscard]] const KernelProgram& in_precision(const KernelProgram& program,
                                                DevicePrecision precision);

struct Pipeline {
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
};

class PipelineLibrary {
 public:
  explicit PipelineLibrary(Context::Impl& context) : context_(context) {}
  ~PipelineLibrary();
  PipelineLibrary(const PipelineLibrary&) = delete;
  PipelineLibrary& operator=(const PipelineLibrary&) = delete;

  // The pipeline of `program`, created on the first call (thread-safe).
  const Pipeline& get(const KernelProgram& program);
  // Whether get(program) has been called: whether this context ever recorded the kernel (tests
  // tell by it which kernels a method ran on the device).
  [[nodiscard]] bool built(const KernelProgram& program);

 private:
  Context::Impl& context_;
  std::mutex mutex_;
  std::map<const KernelProgram*, std::unique_ptr<Pipeline>> pipelines_;
};

}  // namespace harmonia::vulkan::detail
