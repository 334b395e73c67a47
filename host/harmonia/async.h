#pragma once
//! \file async.h
//! \brief Running a map without blocking the caller: launch() returns a PendingMap at once.
//!
//! An application (an engine's frame loop) launches any harmonia map on a worker thread, goes on
//! with its own work, polls ready() and collects the result with wait():
//! \code
//!   harmonia::PendingMap<harmonia::MapResult> pending = harmonia::launch(
//!       options.solver, [&mesh, options](const harmonia::SolverOptions& solver) {
//!         harmonia::FixedBoundaryOptions map_options = options;
//!         map_options.solver = solver;  // carries the cancellation hook
//!         return harmonia::fixed_boundary_map(mesh, map_options);
//!       });
//!   while (!pending.ready()) render_a_frame();
//!   const harmonia::MapResult& result = pending.wait();
//! \endcode
//! The result is the one the synchronous call gives, bit for bit (the same code runs).
//!
//! On a Vulkan context the application passes in (SolverOptions::vulkan_context) that has
//! timeline semaphores (vulkan::DeviceInfo::timeline_semaphore), device_signal_value() is the
//! value the task's latest GPU submission signals on vulkan::Context::timeline_semaphore(): the
//! engine can make its own queue submission wait for it or poll it (vkGetSemaphoreCounterValue).
//!
//! Thread safety: ready(), cancel() and device_signal_value() may be called from any thread at
//! any time; wait() from one thread at a time. The launched map must not touch data the caller
//! changes meanwhile (capture the mesh by reference only if it stays unchanged and alive until
//! wait() returns). Several launched maps may share one Context (vulkan_context.h).

#include <atomic>
#include <cstdint>
#include <exception>
#include <future>
#include <memory>
#include <optional>
#include <type_traits>
#include <utility>

#include "harmonia/solver_options.h"

namespace harmonia {

namespace detail {

//! Shared by a PendingMap and the thread that runs its map (host/solve/async.cpp).
class TaskControl {
 public:
  void request_cancel() noexcept { cancel_requested_ = true; }
  [[nodiscard]] bool cancel_requested() const noexcept { return cancel_requested_; }
  void mark_finished() noexcept { finished_ = true; }
  [[nodiscard]] bool finished() const noexcept { return finished_; }
  [[nodiscard]] std::uint64_t device_signal_value() const noexcept { return signal_value_; }
  std::atomic<std::uint64_t>& signal_value_slot() noexcept { return signal_value_; }

 private:
  std::atomic<bool> cancel_requested_{false};
  std::atomic<bool> finished_{false};
  std::atomic<std::uint64_t> signal_value_{0};
};

//! The options the task runs with: `solver` with a progress callback that first asks `control`
//! whether the task was cancelled, then the application's own callback (if any).
[[nodiscard]] SolverOptions cancellable_options(const SolverOptions& solver,
                                                std::shared_ptr<TaskControl> control);

//! Lives on the worker thread while the map runs: records the timeline value of every submission
//! the thread makes on options.vulkan_context, and marks the task finished when it ends.
class TaskScope {
 public:
  TaskScope(TaskControl& control, const SolverOptions& options);
  ~TaskScope();
  TaskScope(const TaskScope&) = delete;
  TaskScope& operator=(const TaskScope&) = delete;

 private:
  TaskControl& control_;
  std::shared_ptr<void> observation_;  // The installed submission observer (Vulkan builds).
};

}  // namespace detail

//! A map running on a worker thread. Move-only. Destroying one that is still running cancels it
//! and waits for it to stop (as std::future from std::async does).
template <typename Result>
class PendingMap {
 public:
  PendingMap(std::shared_ptr<detail::TaskControl> control, std::future<Result> future)
      : control_(std::move(control)), future_(std::move(future)) {}
  PendingMap(PendingMap&&) noexcept = default;
  PendingMap& operator=(PendingMap&& other) noexcept {
    if (this != &other) {
      cancel();
      if (future_.valid()) future_.wait();
      control_ = std::move(other.control_);
      future_ = std::move(other.future_);
      result_ = std::move(other.result_);
      error_ = std::move(other.error_);
    }
    return *this;
  }
  PendingMap(const PendingMap&) = delete;
  PendingMap& operator=(const PendingMap&) = delete;
  ~PendingMap() { cancel(); }  // future_'s destructor then waits for the thread.

  //! True once the map has finished (with a result or an exception); never blocks.
  [[nodiscard]] bool ready() const noexcept {
    return control_ == nullptr || control_->finished();
  }
  //! Blocks until the map has finished and returns its result (its report says
  //! Status::cancelled after cancel()). Rethrows what the map threw (harmonia::Error, e.g.
  //! Status::device_failure), on this and every later call.
  Result& wait() {
    if (!result_ && !error_) {
      try {
        result_.emplace(future_.get());
      } catch (...) {
        error_ = std::current_exception();
      }
    }
    if (error_) std::rethrow_exception(error_);
    return *result_;
  }
  //! Asks the map to stop: its next progress check returns false, and it returns with
  //! Status::cancelled (work already on the GPU still finishes). No effect once finished.
  void cancel() noexcept {
    if (control_) control_->request_cancel();
  }
  //! The value the task's latest GPU submission signals on the context's timeline semaphore
  //! (vulkan::Context::timeline_semaphore of SolverOptions::vulkan_context); 0 while it has made
  //! none, and always 0 without such a context (CPU, or a context created for the call). Final
  //! once ready(): once the semaphore reaches it, all of the task's GPU work is done.
  [[nodiscard]] std::uint64_t device_signal_value() const noexcept {
    return control_ ? control_->device_signal_value() : 0;
  }

 private:
  std::shared_ptr<detail::TaskControl> control_;
  std::future<Result> future_;
  std::optional<Result> result_;
  std::exception_ptr error_;
};

//! Runs `map(options)` on a new thread and returns at once. `map` is any callable taking
//! `const SolverOptions&` and returning the result (typically a lambda that calls one of the
//! maps with these solver options, so that cancel() reaches it through the progress callback).
template <typename Map>
[[nodiscard]] auto launch(const SolverOptions& solver, Map map)
    -> PendingMap<std::invoke_result_t<Map&, const SolverOptions&>> {
  using Result = std::invoke_result_t<Map&, const SolverOptions&>;
  auto control = std::make_shared<detail::TaskControl>();
  SolverOptions options = detail::cancellable_options(solver, control);
  std::future<Result> future = std::async(
      std::launch::async,
      [control, options = std::move(options), map = std::move(map)]() mutable -> Result {
        const detail::TaskScope scope(*control, options);
        return map(static_cast<const SolverOptions&>(options));
      });
  return PendingMap<Result>(std::move(control), std::move(future));
}

}  // namespace harmonia
