#pragma once
// Internal: a loop over the faces of a frame split between the calling thread and one more.
//
// A frame's per-triangle stages (blending, the Poisson load, the orientation check) are a third of
// its time on a large mesh and independent from triangle to triangle; the back-substitution
// between them is sequential. Two threads halve those stages on a two-core machine. A thread is
// started per call (tens of microseconds, against milliseconds of work); below kMinimumItems
// items, or with one hardware thread, the calling thread does everything.

#include <thread>

#include <Eigen/Core>

namespace harmonia::detail {

inline constexpr Eigen::Index kMinimumItemsToSplit = 20000;

// Calls work(part, begin, end) for part 0 on [0, count / 2) on this thread and part 1 on
// [count / 2, count) on a second one, or work(0, 0, count) alone; returns the number of parts.
template <typename Work>
int split_two_ways(Eigen::Index count, const Work& work) {
  if (count < kMinimumItemsToSplit || std::thread::hardware_concurrency() < 2) {
    work(0, Eigen::Index{0}, count);
    return 1;
  }
  const Eigen::Index middle = count / 2;
  std::thread second([&work, middle, count] { work(1, middle, count); });
  work(0, Eigen::Index{0}, middle);
  second.join();
  return 2;
}

}  // namespace harmonia::detail
