// Helper tasks (mesh/helper_tasks.h): started beside the caller on a thread of their own, or, in a
// HelperTasksOnThisThread scope, run at once on the calling thread; values and exceptions come
// out of the future either way, and scopes nest and end.
#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "mesh/for_each_index.h"
#include "mesh/helper_tasks.h"

namespace harmonia::detail {
namespace {

TEST(HelperTasks, RunBesideOnAThreadOfTheirOwn) {
  ASSERT_FALSE(helper_tasks_on_this_thread());
  std::future<std::thread::id> task = start_beside([] { return std::this_thread::get_id(); });
  EXPECT_NE(task.get(), std::this_thread::get_id());
}

TEST(HelperTasks, RunAtOnceOnTheCallingThreadInsideAScope) {
  int runs = 0;
  {
    const HelperTasksOnThisThread scope;
    std::future<std::thread::id> task = start_beside([&runs] {
      ++runs;
      return std::this_thread::get_id();
    });
    EXPECT_EQ(runs, 1);  // already ran, before get()
    EXPECT_EQ(task.get(), std::this_thread::get_id());
    {
      const HelperTasksOnThisThread nested;
      EXPECT_TRUE(helper_tasks_on_this_thread());
    }
    EXPECT_TRUE(helper_tasks_on_this_thread());  // the outer scope still holds
  }
  EXPECT_FALSE(helper_tasks_on_this_thread());
}

TEST(HelperTasks, ExceptionsComeOutOfTheFutureEitherWay) {
  std::future<int> beside = start_beside([]() -> int { throw std::runtime_error("beside"); });
  EXPECT_THROW(beside.get(), std::runtime_error);
  const HelperTasksOnThisThread scope;
  std::future<void> here = start_beside([] { throw std::runtime_error("here"); });
  EXPECT_THROW(here.get(), std::runtime_error);
}

TEST(HelperTasks, WorkersOfSeveralThreadsRunTheirHelpersThemselves) {
  // Each of two workers' helper tasks runs on that worker; a single worker leaves them beside.
  std::vector<int> on_worker(8, 0);
  for_each_index(on_worker.size(), 2, [&](std::size_t i) {
    const std::thread::id worker = std::this_thread::get_id();
    on_worker[i] = start_beside([] { return std::this_thread::get_id(); }).get() == worker;
  });
  for (const int same : on_worker) EXPECT_EQ(same, 1);
  for_each_index(2, 1, [&](std::size_t) {
    EXPECT_NE(start_beside([] { return std::this_thread::get_id(); }).get(), std::this_thread::get_id());
  });
}

}  // namespace
}  // namespace harmonia::detail
