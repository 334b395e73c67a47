#pragma once
// Internal: helper tasks, started beside the calling thread's own work (a fill-reducing ordering
// computed while the caller validates and assembles, the second half of a loop over the faces),
// each on a thread of its own or, inside a pool of workers, at once on the calling thread.
//
// Why: a thread costs tens of microseconds to start (several times that on a virtual machine),
// nothing against a large mesh's milliseconds of work. But the texture atlas flattens hundreds of
// small charts on one worker per core, and there each chart's three or four helper threads cost
// about a fifth of the flattening and compete with the other workers for cores they already fill.
// Every helper task is independent of the timing (its result does not depend on when it runs), so
// running it on the calling thread, at the point where it is started, gives the same result: it
// only gives up the overlap.

#include <exception>
#include <future>
#include <type_traits>
#include <utility>

namespace harmonia::detail {

//! Whether helper tasks started on this thread run on it (inside a HelperTasksOnThisThread scope).
[[nodiscard]] inline bool& helper_tasks_on_this_thread() {
  thread_local bool on_this_thread = false;
  return on_this_thread;
}

//! While it lives, start_beside() runs its tasks at once on the thread that made it: for the
//! workers of a pool that already keeps every core busy. Scopes nest.
class HelperTasksOnThisThread {
 public:
  HelperTasksOnThisThread() : before_(std::exchange(helper_tasks_on_this_thread(), true)) {}
  ~HelperTasksOnThisThread() { helper_tasks_on_this_thread() = before_; }
  HelperTasksOnThisThread(const HelperTasksOnThisThread&) = delete;
  HelperTasksOnThisThread& operator=(const HelperTasksOnThisThread&) = delete;

 private:
  bool before_;
};

//! task() on a thread of its own, or (inside a HelperTasksOnThisThread scope) run now on this
//! thread; either way its value or exception comes out of the future's get(). The task must not
//! wait for anything the caller does after starting it.
template <typename Task>
[[nodiscard]] std::future<std::invoke_result_t<std::decay_t<Task>>> start_beside(Task&& task) {
  using Result = std::invoke_result_t<std::decay_t<Task>>;
  if (!helper_tasks_on_this_thread()) return std::async(std::launch::async, std::forward<Task>(task));
  std::packaged_task<Result()> now(std::forward<Task>(task));
  std::future<Result> result = now.get_future();
  now();
  return result;
}

}  // namespace harmonia::detail
