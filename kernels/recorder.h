#pragma once
// Internal: records dispatches and copies into one command buffer, submits it, waits for it.
//
// A recorder owns a command pool with one command buffer, a fence, descriptor pools for the sets
// its dispatches bind, and (where the queue has them) two timestamp queries that measure the GPU
// time of each submission. Every dispatch is followed by a compute-to-compute memory barrier, so
// a recorded sequence runs in order. A recording can be submitted any number of times (the fused
// PCG records a batch of iterations once and resubmits it). One thread at a time.
//
// Submit now, wait later: submit() returns a ticket at once; wait(ticket) or is_done(ticket)
// settle it. With timeline semaphores (DeviceInfo::timeline_semaphore) the ticket is the value
// the submission signals on the context's timeline; otherwise it counts this recorder's
// submissions and the fence tells when the latest is done. One command buffer means at most one
// submission in flight: begin() and submit() first wait for the previous one.

#include <cstdint>
#include <initializer_list>
#include <vector>

#include "kernels/buffer.h"
#include "kernels/pipelines.h"

namespace harmonia::vulkan::detail {

class CommandRecorder {
 public:
  explicit CommandRecorder(Context::Impl& context);
  ~CommandRecorder();
  CommandRecorder(const CommandRecorder&) = delete;
  CommandRecorder& operator=(const CommandRecorder&) = delete;

  // Starts a new recording (the previous one and its descriptor sets are discarded).
  void begin();
  // Records `program` over groups_x x groups_y workgroups with `buffers` at bindings 0, 1, ...
  template <typename Push>
  void dispatch(const KernelProgram& program, std::initializer_list<const Buffer*> buffers,
                const Push& push, std::uint32_t groups_x, std::uint32_t groups_y = 1) {
    static_assert(sizeof(Push) % 4 == 0, "push constants are made of 4-byte words");
    if (sizeof(Push) != program.push_constant_bytes) throw_push_mismatch(program);
    record_dispatch(program, buffers, &push, groups_x, groups_y);
  }
  // Records a copy of `bytes` from one buffer to another (offsets in bytes).
  void copy(const Buffer& source, std::uint64_t source_offset, const Buffer& target,
            std::uint64_t target_offset, std::uint64_t bytes);
  // Ends the recording.
  void end();
  // A submission in flight (or finished): see the class comment.
  struct Ticket {
    std::uint64_t value = 0;
  };
  // Submits the recording without waiting. Throws harmonia::Error (device_failure) when the
  // submission fails or the device was lost.
  [[nodiscard]] Ticket submit();
  // Whether the submission is finished (never blocks). Throws harmonia::Error (device_failure)
  // when the device was lost.
  [[nodiscard]] bool is_done(Ticket ticket) const;
  // Blocks until the submission is finished (at most the context's wait timeout). Throws
  // harmonia::Error (device_failure) on device loss or timeout.
  void wait(Ticket ticket);
  // submit() then wait().
  void submit_and_wait();

  // GPU time of the last submission in seconds (0 without timestamp support).
  [[nodiscard]] double last_gpu_seconds() const { return last_gpu_seconds_; }
  // Workgroups needed to cover `items` with one invocation each, capped at the device limit
  // (every kernel loops over its items with a grid stride, so a capped dispatch still covers all).
  [[nodiscard]] std::uint32_t groups_for(std::uint64_t items) const;
  [[nodiscard]] Context::Impl& context() const { return context_; }

 private:
  void record_dispatch(const KernelProgram& program, std::initializer_list<const Buffer*> buffers,
                       const void* push, std::uint32_t groups_x, std::uint32_t groups_y);
  [[noreturn]] static void throw_push_mismatch(const KernelProgram& program);
  VkDescriptorSet allocate_set(const Pipeline& pipeline);
  void barrier();
  void destroy() noexcept;
  // Waits for the submission in flight, if any.
  void settle();

  Context::Impl& context_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer commands_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkQueryPool timestamps_ = VK_NULL_HANDLE;
  std::vector<VkDescriptorPool> descriptor_pools_;
  std::size_t current_pool_ = 0;
  std::uint32_t sets_in_current_pool_ = 0;
  bool recording_ = false;
  bool recorded_ = false;
  double last_gpu_seconds_ = 0.0;
  std::uint64_t fence_submissions_ = 0;  // Tickets on the fence path.
  bool in_flight_ = false;               // A submission not yet waited for.
  Ticket in_flight_ticket_;
};

}  // namespace harmonia::vulkan::detail
