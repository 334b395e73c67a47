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

#include "kernels/context_impl.h"

namespace harmonia::vulkan::detail {

// One shader as embedded in the library (defined in kernels/<shader name>.cpp).
struct KernelProgram {
  const char* name;            // The shader's file name without .comp, for messages.
  const std::uint32_t* spirv;  // The <name>_spv array.
  std::size_t spirv_bytes;
  std::uint32_t buffer_count;         // Storage buffers at bindings 0..buffer_count-1.
  std::uint32_t push_constant_bytes;  // sizeof the kernel's <Name>Push struct.
};

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

 private:
  Context::Impl& context_;
  std::mutex mutex_;
  std::map<const KernelProgram*, std::unique_ptr<Pipeline>> pipelines_;
};

}  // namespace harmonia::vulkan::detail
