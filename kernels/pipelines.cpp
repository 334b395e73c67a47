#include "kernels/pipelines.h"

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace harmonia::vulkan::detail {

const KernelProgram& in_precision(const KernelProgram& program, DevicePrecision precision) {
  if (precision == DevicePrecision::float32) return program;
  if (program.float64_twin == nullptr)
    throw std::logic_error(std::string("vulkan backend: shader ") + program.name +
                           " has no fp64 variant");
  return *program.float64_twin;
}

PipelineLibrary::~PipelineLibrary() {
  const VulkanFunctions& vk = context_.vk;
  for (auto& [program, pipeline] : pipelines_) {
    vk.vkDestroyPipeline(context_.device, pipeline->pipeline, context_.allocator);
    vk.vkDestroyPipelineLayout(context_.device, pipeline->layout, context_.allocator);
    vk.vkDestroyDescriptorSetLayout(context_.device, pipeline->set_layout, context_.allocator);
  }
}

bool PipelineLibrary::built(const KernelProgram& program) {
  const std::lock_guard lock(mutex_);
  return pipelines_.count(&program) > 0;
}

const Pipeline& PipelineLibrary::get(const KernelProgram& program) {
  const std::lock_guard lock(mutex_);
  if (const auto found = pipelines_.find(&program); found != pipelines_.end())
    return *found->second;
  const VulkanFunctions& vk = context_.vk;
  const VkDevice device = context_.device;
  const std::string what = std::string("creating the pipeline of shader ") + program.name;

  // Build into a local object that destroys what it holds if a later step throws.
  struct Partial {
    const Context::Impl& context;
    Pipeline pipeline;
    VkShaderModule module = VK_NULL_HANDLE;
    ~Partial() {
      const VulkanFunctions& functions = context.vk;
      if (module) functions.vkDestroyShaderModule(context.device, module, context.allocator);
      if (pipeline.pipeline)
        functions.vkDestroyPipeline(context.device, pipeline.pipeline, context.allocator);
      if (pipeline.layout)
        functions.vkDestroyPipelineLayout(context.device, pipeline.layout, context.allocator);
      if (pipeline.set_layout)
        functions.vkDestroyDescriptorSetLayout(context.device, pipeline.set_layout,
                                               context.allocator);
    }
  } partial{context_, {}, VK_NULL_HANDLE};

  std::vector<VkDescriptorSetLayoutBinding> bindings(program.buffer_count);
  for (std::uint32_t binding = 0; binding < program.buffer_count; ++binding) {
    bindings[binding].binding = binding;
    bindings[binding].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[binding].descriptorCount = 1;
    bindings[binding].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  auto set_info =
      vk_info<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  set_info.bindingCount = program.buffer_count;
  set_info.pBindings = bindings.data();
  check(vk.vkCreateDescriptorSetLayout(device, &set_info, context_.allocator,
                                       &partial.pipeline.set_layout),
        what.c_str());

  VkPushConstantRange push_range{VK_SHADER_STAGE_COMPUTE_BIT, 0, program.push_constant_bytes};
  auto layout_info =
      vk_info<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &partial.pipeline.set_layout;
  layout_info.pushConstantRangeCount = program.push_constant_bytes > 0 ? 1 : 0;
  layout_info.pPushConstantRanges = &push_range;
  check(
      vk.vkCreatePipelineLayout(device, &layout_info, context_.allocator, &partial.pipeline.layout),
      what.c_str());

  auto module_info = vk_info<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  module_info.codeSize = program.spirv_bytes;
  module_info.pCode = program.spirv;
  check(vk.vkCreateShaderModule(device, &module_info, context_.allocator, &partial.module),
        what.c_str());

  // Specialization: constant 0 = workgroup width, constant 1 = lanes per matrix row.
  const std::array<std::uint32_t, 2> constants{context_.workgroup_size, context_.lanes_per_row};
  const std::array<VkSpecializationMapEntry, 2> entries{
      VkSpecializationMapEntry{0, 0, sizeof(std::uint32_t)},
      VkSpecializationMapEntry{1, sizeof(std::uint32_t), sizeof(std::uint32_t)}};
  VkSpecializationInfo specialization{static_cast<std::uint32_t>(entries.size()), entries.data(),
                                      sizeof(constants), constants.data()};
  auto pipeline_info =
      vk_info<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  pipeline_info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  pipeline_info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipeline_info.stage.module = partial.module;
  pipeline_info.stage.pName = "main";
  pipeline_info.stage.pSpecializationInfo = &specialization;
  pipeline_info.layout = partial.pipeline.layout;
  check(vk.vkCreateComputePipelines(device, context_.pipeline_cache, 1, &pipeline_info,
                                    context_.allocator, &partial.pipeline.pipeline),
        what.c_str());

  auto pipeline = std::make_unique<Pipeline>(partial.pipeline);
  partial.pipeline = {};  // Ownership moves to the library.
  const Pipeline& result = *pipeline;
  pipelines_.emplace(&program, std::move(pipeline));
  return result;
}

}  // namespace harmonia::vulkan::detail
