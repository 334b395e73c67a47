#pragma once
// Internal test seam: device failures a test can provoke on a context (Context::Impl::faults),
// so that the handling of out-of-memory, device loss and hangs is exercised on any machine.
//
// Not reachable from the public API: only code that includes kernels/context_impl.h (the library
// itself and its tests) can arm a fault. Each fault counts the events from the moment it is armed
// (1 = the next one); arming with 0 disarms it. Thread-safe.

#include <mutex>

namespace harmonia::vulkan::detail {

enum class SubmissionFault {
  none,
  device_lost,  // vkQueueSubmit is not called; the context reports VK_ERROR_DEVICE_LOST.
  hang,         // The submission waits on a gate that opens only when a wait gives up on it.
};

class FaultInjection {
 public:
  // The nth device memory allocation from now fails with VK_ERROR_OUT_OF_DEVICE_MEMORY.
  void fail_allocation(int nth);
  // The nth submission from now returns VK_ERROR_DEVICE_LOST (and the device stays lost).
  void lose_device_at_submission(int nth);
  // The nth submission from now never finishes on its own (needs timeline semaphores).
  void hang_submission(int nth);

  // Called by the allocation and submission code: whether this event is the one to fail.
  [[nodiscard]] bool next_allocation_fails();
  [[nodiscard]] SubmissionFault next_submission();

 private:
  // Counts an event down; true when it reaches the armed one (which disarms it).
  static bool count_down(int& countdown);

  std::mutex mutex_;
  int allocation_countdown_ = 0;
  int device_lost_countdown_ = 0;
  int hang_countdown_ = 0;
};

}  // namespace harmonia::vulkan::detail
