#include "kernels/fault_injection.h"

namespace harmonia::vulkan::detail {

void FaultInjection::fail_allocation(int nth) {
  const std::lock_guard lock(mutex_);
  allocation_countdown_ = nth;
}

void FaultInjection::lose_device_at_submission(int nth) {
  const std::lock_guard lock(mutex_);
  device_lost_countdown_ = nth;
}

void FaultInjection::hang_submission(int nth) {
  const std::lock_guard lock(mutex_);
  hang_countdown_ = nth;
}

bool FaultInjection::count_down(int& countdown) {
  if (countdown <= 0) return false;
  return --countdown == 0;
}

bool FaultInjection::next_allocation_fails() {
  const std::lock_guard lock(mutex_);
  return count_down(allocation_countdown_);
}

SubmissionFault FaultInjection::next_submission() {
  const std::lock_guard lock(mutex_);
  // Both counters advance on every submission, so each keeps counting from when it was armed.
  const bool lost = count_down(device_lost_countdown_);
  const bool hang = count_down(hang_countdown_);
  if (lost) return SubmissionFault::device_lost;
  if (hang) return SubmissionFault::hang;
  return SubmissionFault::none;
}

}  // namespace harmonia::vulkan::detail
