#pragma once
// Internal: work(i) for every i in [0, count) on a few threads, each index once and in any order
// (the texture atlas prepares its charts so, linear_abf_batch its meshes). The calling thread is
// one of the workers; with one thread, or one index, nothing else is started. The first exception
// a work item throws stops the handing out of further indices and is rethrown here once every
// worker has finished. With several workers, each one runs the helper tasks its work starts
// (helper_tasks.h) itself: the workers already fill the cores.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "mesh/helper_tasks.h"

namespace harmonia::detail {

template <typename Work>
void for_each_index(std::size_t count, int threads, const Work& work) {
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)), count);
  if (workers <= 1) {
    for (std::size_t i = 0; i < count; ++i) work(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto worker = [&] {
    const HelperTasksOnThisThread helper_tasks_here;
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        work(i);
      } catch (...) {
        const std::lock_guard lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = count;
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace harmonia::detail
