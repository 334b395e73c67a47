#include "kernels/recorder.h"

#include <algorithm>
#include <array>
#include <string>

#include "harmonia/types.h"

namespace harmonia::vulkan::detail {
namespace {

constexpr std::uint32_t sets_per_pool = 64;
constexpr std::uint32_t buffers_per_set = 8;  // The most bindings any shader has.

}  // namespace

CommandRecorder::CommandRecorder(Context::Impl& context) : context_(context) {
  const VulkanFunctions& vk = context.vk;
  auto pool_info = vk_info<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = context.queue_family;
  check(vk.vkCreateCommandPool(context.device, &pool_info, context.allocator, &pool_),
        "vkCreateCommandPool");
  try {
    auto buffer_info =
        vk_info<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    buffer_info.commandPool = pool_;
    buffer_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    buffer_info.commandBufferCount = 1;
    check(vk.vkAllocateCommandBuffers(context.device, &buffer_info, &commands_),
          "vkAllocateCommandBuffers");
    auto fence_info = vk_info<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    check(vk.vkCreateFence(context.device, &fence_info, context.allocator, &fence_),
          "vkCreateFence");
    if (context.info.timestamps) {
      auto query_info = vk_info<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
      query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
      query_info.queryCount = 2;
      check(vk.vkCreateQueryPool(context.device, &query_info, context.allocator, &timestamps_),
            "vkCreateQueryPool");
    }
  } catch (...) {
    destroy();
    throw;
  }
}

CommandRecorder::~CommandRecorder() {
  // The objects of a submission in flight must not be destroyed before it finishes. A failed wait
  // leaves it in flight: after a device loss the next wait returns at once, and a timed-out
  // (injected) hang has been released, so this wait ends either way.
  try {
    settle();
  } catch (const Error&) {
    // The device is lost: its objects may be destroyed.
  }
  destroy();
}

void CommandRecorder::destroy() noexcept {
  const VulkanFunctions& vk = context_.vk;
  const VkDevice device = context_.device;
  for (VkDescriptorPool pool : descriptor_pools_)
    vk.vkDestroyDescriptorPool(device, pool, context_.allocator);
  descriptor_pools_.clear();
  if (timestamps_ != VK_NULL_HANDLE) vk.vkDestroyQueryPool(device, timestamps_, context_.allocator);
  if (fence_ != VK_NULL_HANDLE) vk.vkDestroyFence(device, fence_, context_.allocator);
  if (pool_ != VK_NULL_HANDLE) vk.vkDestroyCommandPool(device, pool_, context_.allocator);
  timestamps_ = VK_NULL_HANDLE;
  fence_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
}

void CommandRecorder::settle() {
  if (in_flight_) wait(in_flight_ticket_);
}

void CommandRecorder::begin() {
  settle();  // The command buffer and its descriptor sets may still be in use.
  const VulkanFunctions& vk = context_.vk;
  check(vk.vkResetCommandBuffer(commands_, 0), "vkResetCommandBuffer");
  for (VkDescriptorPool pool : descriptor_pools_)
    check(vk.vkResetDescriptorPool(context_.device, pool, 0), "vkResetDescriptorPool");
  current_pool_ = 0;
  sets_in_current_pool_ = 0;
  auto info = vk_info<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  check(vk.vkBeginCommandBuffer(commands_, &info), "vkBeginCommandBuffer");
  if (timestamps_ != VK_NULL_HANDLE) {
    vk.vkCmdResetQueryPool(commands_, timestamps_, 0, 2);
    vk.vkCmdWriteTimestamp(commands_, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps_, 0);
  }
  recording_ = true;
  recorded_ = false;
}

VkDescriptorSet CommandRecorder::allocate_set(const Pipeline& pipeline) {
  const VulkanFunctions& vk = context_.vk;
  if (current_pool_ < descriptor_pools_.size() && sets_in_current_pool_ == sets_per_pool) {
    ++current_pool_;
    sets_in_current_pool_ = 0;
  }
  if (current_pool_ == descriptor_pools_.size()) {
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                    sets_per_pool * buffers_per_set};
    auto info = vk_info<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
    info.maxSets = sets_per_pool;
    info.poolSizeCount = 1;
    info.pPoolSizes = &size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    check(vk.vkCreateDescriptorPool(context_.device, &info, context_.allocator, &pool),
          "vkCreateDescriptorPool");
    descriptor_pools_.push_back(pool);
    sets_in_current_pool_ = 0;
  }
  auto info = vk_info<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  info.descriptorPool = descriptor_pools_[current_pool_];
  info.descriptorSetCount = 1;
  info.pSetLayouts = &pipeline.set_layout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  check(vk.vkAllocateDescriptorSets(context_.device, &info, &set), "vkAllocateDescriptorSets");
  ++sets_in_current_pool_;
  return set;
}

void CommandRecorder::throw_push_mismatch(const KernelProgram& program) {
  throw std::logic_error(std::string("push constants of shader ") + program.name +
                         " do not match its declared size");
}

void CommandRecorder::record_dispatch(const KernelProgram& program,
                                      std::initializer_list<const Buffer*> buffers,
                                      const void* push, std::uint32_t groups_x,
                                      std::uint32_t groups_y) {
  if (!recording_) throw std::logic_error("CommandRecorder: dispatch outside begin()/end()");
  if (buffers.size() != program.buffer_count || buffers.size() > buffers_per_set)
    throw std::logic_error(std::string("shader ") + program.name + " binds " +
                           std::to_string(program.buffer_count) + " buffers, not " +
                           std::to_string(buffers.size()));
  if (groups_x == 0 || groups_y == 0) return;  // Nothing to do (empty block).
  if (groups_y > context_.limits.maxComputeWorkGroupCount[1])
    throw Error(Status::unsupported,
                std::string("shader ") + program.name + ": " + std::to_string(groups_y) +
                    " vector columns exceed the device's maxComputeWorkGroupCount[1] (" +
                    std::to_string(context_.limits.maxComputeWorkGroupCount[1]) + ")");
  const VulkanFunctions& vk = context_.vk;
  const Pipeline& pipeline = context_.pipelines->get(program);
  const VkDescriptorSet set = allocate_set(pipeline);

  std::array<VkDescriptorBufferInfo, buffers_per_set> infos{};
  std::array<VkWriteDescriptorSet, buffers_per_set> writes{};
  std::uint32_t binding = 0;
  for (const Buffer* buffer : buffers) {
    infos[binding] = VkDescriptorBufferInfo{buffer->handle(), 0, VK_WHOLE_SIZE};
    writes[binding] = vk_info<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    writes[binding].dstSet = set;
    writes[binding].dstBinding = binding;
    writes[binding].descriptorCount = 1;
    writes[binding].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[binding].pBufferInfo = &infos[binding];
    ++binding;
  }
  vk.vkUpdateDescriptorSets(context_.device, binding, writes.data(), 0, nullptr);
  vk.vkCmdBindPipeline(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.pipeline);
  vk.vkCmdBindDescriptorSets(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout, 0, 1, &set,
                             0, nullptr);
  if (program.push_constant_bytes > 0)
    vk.vkCmdPushConstants(commands_, pipeline.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                          program.push_constant_bytes, push);
  vk.vkCmdDispatch(commands_, groups_x, groups_y, 1);
  barrier();
}

void CommandRecorder::copy(const Buffer& source, std::uint64_t source_offset, const Buffer& target,
                           std::uint64_t target_offset, std::uint64_t bytes) {
  if (!recording_) throw std::logic_error("CommandRecorder: copy outside begin()/end()");
  if (bytes == 0) return;
  const VkBufferCopy region{source_offset, target_offset, bytes};
  context_.vk.vkCmdCopyBuffer(commands_, source.handle(), target.handle(), 1, &region);
  barrier();
}

// Every write so far (shaders, copies) is visible to every later read or write (shaders, copies,
// and the host after the fence).
void CommandRecorder::barrier() {
  auto memory = vk_info<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  memory.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  memory.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                         VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                         VK_ACCESS_HOST_READ_BIT;
  const VkPipelineStageFlags stages =
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  context_.vk.vkCmdPipelineBarrier(commands_, stages, stages | VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                                   &memory, 0, nullptr, 0, nullptr);
}

void CommandRecorder::end() {
  if (!recording_) throw std::logic_error("CommandRecorder: end() without begin()");
  if (timestamps_ != VK_NULL_HANDLE)
    context_.vk.vkCmdWriteTimestamp(commands_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps_,
                                    1);
  check(context_.vk.vkEndCommandBuffer(commands_), "vkEndCommandBuffer");
  recording_ = false;
  recorded_ = true;
}

CommandRecorder::Ticket CommandRecorder::submit() {
  if (!recorded_) throw std::logic_error("CommandRecorder: submit without a finished recording");
  settle();  // One command buffer: the previous submission must be finished before it is reused.
  const bool timeline = context_.timeline != VK_NULL_HANDLE;
  if (!timeline) check(context_.vk.vkResetFences(context_.device, 1, &fence_), "vkResetFences");
  const std::uint64_t value = context_.submit(commands_, timeline ? VK_NULL_HANDLE : fence_);
  in_flight_ticket_ = Ticket{timeline ? value : ++fence_submissions_};
  in_flight_ = true;
  return in_flight_ticket_;
}

bool CommandRecorder::is_done(Ticket ticket) const {
  // Tickets older than the one in flight were settled before it was submitted.
  if (!in_flight_ || ticket.value < in_flight_ticket_.value) return true;
  if (context_.timeline != VK_NULL_HANDLE) return context_.completed_value() >= ticket.value;
  const VkResult status = context_.sync.vkGetFenceStatus(context_.device, fence_);
  if (status == VK_NOT_READY) return false;
  context_.check_wait(status, "polling the device (vkGetFenceStatus)");
  return true;
}

void CommandRecorder::wait(Ticket ticket) {
  if (!in_flight_ || ticket.value < in_flight_ticket_.value) return;
  if (context_.timeline != VK_NULL_HANDLE)
    context_.wait_for_value(ticket.value);
  else
    context_.check_wait(context_.vk.vkWaitForFences(context_.device, 1, &fence_, VK_TRUE,
                                                    context_.wait_timeout_ns.load()),
                        "waiting for the device (vkWaitForFences)");
  in_flight_ = false;
  last_gpu_seconds_ = 0.0;
  if (timestamps_ != VK_NULL_HANDLE) {
    const VulkanFunctions& vk = context_.vk;
    std::array<std::uint64_t, 2> ticks{};
    if (vk.vkGetQueryPoolResults(context_.device, timestamps_, 0, 2, sizeof(ticks), ticks.data(),
                                 sizeof(std::uint64_t),
                                 VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS)
      last_gpu_seconds_ = static_cast<double>((ticks[1] - ticks[0]) & context_.timestamp_mask) *
                          static_cast<double>(context_.timestamp_period_ns) * 1e-9;
  }
}

void CommandRecorder::submit_and_wait() { wait(submit()); }

std::uint32_t CommandRecorder::groups_for(std::uint64_t items) const {
  const std::uint64_t width = context_.workgroup_size;
  const std::uint64_t groups = (items + width - 1) / width;
  return static_cast<std::uint32_t>(
      std::min<std::uint64_t>(groups, context_.limits.maxComputeWorkGroupCount[0]));
}

}  // namespace harmonia::vulkan::detail
