#pragma once
// Running the same jobs one after another and then all at once, each on its own thread, so that a
// test can check that the library used from several threads gives the serial results bit for bit
// (and, under ThreadSanitizer, that it does so without a data race: docs/testing.md, "Sanitizers").

#include <exception>
#include <functional>
#include <latch>
#include <thread>
#include <vector>

namespace harmonia::testing {

template <typename Result>
struct SerialAndConcurrent {
  std::vector<Result> serial;      //!< Job k's result, the jobs run one after another.
  std::vector<Result> concurrent;  //!< Job k's result, every job on its own thread at once.
};

//! Runs `jobs` serially, then concurrently (the threads start together, at a latch, so that they
//! overlap). An exception of a job is rethrown here, after every thread has finished.
template <typename Result>
SerialAndConcurrent<Result> run_serially_and_concurrently(
    const std::vector<std::function<Result()>>& jobs) {
  SerialAndConcurrent<Result> results;
  for (const auto& job : jobs) results.serial.push_back(job());

  results.concurrent.resize(jobs.size());
  std::vector<std::exception_ptr> errors(jobs.size());
  std::latch start(static_cast<std::ptrdiff_t>(jobs.size()));
  std::vector<std::thread> threads;
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    threads.emplace_back([&, k] {
      start.arrive_and_wait();
      try {
        results.concurrent[k] = jobs[k]();
      } catch (...) {
        errors[k] = std::current_exception();
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
  return results;
}

}  // namespace harmonia::testing
