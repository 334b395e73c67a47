// BlasThreadPolicy (harmonia/blas_threads.h): by default a library call never changes OpenBLAS's
// process-wide thread count, not even for a moment, and leaves the calling thread's OpenMP setting
// as it found it, also when it is cancelled or its progress callback throws; with the policy
// that allows it, large systems are factorized in two halves and the count is restored after.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "fallback/serial_openmp_regions.h"
#include "fallback/single_threaded_blas.h"
#include "harmonia/blas_threads.h"
#include "harmonia/linear_abf.h"
#include "harmonia/lscm.h"
#include "harmonia/procedural.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

using detail::SerialOpenMpRegions;
using detail::SingleThreadedBlas;

// Reads OpenBLAS's thread count over and over on its own thread while it lives, and keeps the
// smallest and largest values seen.
class ThreadCountWatch {
 public:
  ThreadCountWatch() {
    smallest_ = largest_ = SingleThreadedBlas::threads_now();
    watcher_ = std::thread([this] {
      while (!stop_.load()) {
        const int now = SingleThreadedBlas::threads_now();
        smallest_ = std::min(smallest_.load(), now);
        largest_ = std::max(largest_.load(), now);
        std::this_thread::sleep_for(std::chrono::microseconds(20));
      }
    });
  }
  ~ThreadCountWatch() { stop(); }
  ThreadCountWatch(const ThreadCountWatch&) = delete;
  ThreadCountWatch& operator=(const ThreadCountWatch&) = delete;
  void stop() {
    stop_ = true;
    if (watcher_.joinable()) watcher_.join();
  }
  [[nodiscard]] int smallest() const { return smallest_.load(); }
  [[nodiscard]] int largest() const { return largest_.load(); }

 private:
  std::atomic<bool> stop_{false};
  std::atomic<int> smallest_{0}, largest_{0};
  std::thread watcher_;
};

bool machine_can_split() {
  return std::thread::hardware_concurrency() >= 2 && SingleThreadedBlas::available();
}

// A disk of about 15K vertices: linear ABF's reduced system (two rows per interior vertex) and
// LSCM's UV system (two per vertex) are both above SubtreeParallelCholesky's 20000-row threshold.
const Mesh& large_disk() {
  static const Mesh mesh = planar_disk(70, 0.2);
  return mesh;
}

// Cancels (returns false) or throws at the first progress call of `stage`.
LinearAbfOptions stopping_at(const std::string& stage, bool throw_instead) {
  LinearAbfOptions options;
  options.solver_options.backend = BackendChoice::cpu;
  options.solver_options.progress = [stage, throw_instead](const Progress& progress) {
    if (progress.stage != stage) return true;
    if (throw_instead) throw std::runtime_error("the caller's progress callback failed");
    return false;
  };
  return options;
}

TEST(BlasThreadPolicy, TheLibraryLeavesTheCountAloneByDefault) {
  EXPECT_EQ(blas_thread_policy(), BlasThreadPolicy::leave_alone);
}

TEST(BlasThreadPolicy, SettingItReturnsThePreviousPolicy) {
  const BlasThreadPolicy before = blas_thread_policy();
  EXPECT_EQ(set_blas_thread_policy(BlasThreadPolicy::hold_during_split_factorizations), before);
  EXPECT_EQ(set_blas_thread_policy(before),
            BlasThreadPolicy::hold_during_split_factorizations);
  EXPECT_EQ(blas_thread_policy(), before);
}

TEST(BlasThreadPolicy, ADefaultCallNeverChangesTheThreadCountAndFactorizesWhole) {
  ASSERT_EQ(blas_thread_policy(), BlasThreadPolicy::leave_alone);
  const int count = SingleThreadedBlas::threads_now();
  const bool serial = SerialOpenMpRegions::serial_now();
  ThreadCountWatch watch;
  LinearAbfOptions abf_options;
  abf_options.solver_options.backend = BackendChoice::cpu;
  const AngleMapResult angles = linear_abf(large_disk(), abf_options);
  LscmOptions lscm_options;
  lscm_options.solver.backend = BackendChoice::cpu;
  const MapResult conformal = lscm(large_disk(), lscm_options);
  watch.stop();
  ASSERT_TRUE(angles.report.ok()) << angles.report.message;
  ASSERT_TRUE(conformal.report.ok()) << conformal.report.message;
  EXPECT_EQ(watch.smallest(), count);
  EXPECT_EQ(watch.largest(), count);
  EXPECT_EQ(angles.report.solver.find("two subtrees"), std::string::npos) << angles.report.solver;
  EXPECT_EQ(conformal.report.solver.find("two subtrees"), std::string::npos)
      << conformal.report.solver;
  EXPECT_EQ(SerialOpenMpRegions::serial_now(), serial);
}

TEST(BlasThreadPolicy, ACancelledOrFailingDefaultCallLeavesBothSettingsAsFound) {
  ASSERT_EQ(blas_thread_policy(), BlasThreadPolicy::leave_alone);
  const int count = SingleThreadedBlas::threads_now();
  const bool serial = SerialOpenMpRegions::serial_now();
  ThreadCountWatch watch;
  // "solve" comes right after the reduced system's factorization, "reconstruction" after the
  // second factorization (angles to UVs) has been set up.
  for (const std::string stage : {"factorization", "solve", "reconstruction"}) {
    const AngleMapResult cancelled = linear_abf(large_disk(), stopping_at(stage, false));
    EXPECT_EQ(cancelled.report.status, Status::cancelled) << stage;
    EXPECT_THROW((void)linear_abf(large_disk(), stopping_at(stage, true)), std::runtime_error)
        << stage;
  }
  watch.stop();
  EXPECT_EQ(watch.smallest(), count);
  EXPECT_EQ(watch.largest(), count);
  EXPECT_EQ(SerialOpenMpRegions::serial_now(), serial);
}

TEST(BlasThreadPolicy, HoldingSplitsLargeSystemsAndRestoresTheCountAfterEveryEnding) {
  if (!machine_can_split()) GTEST_SKIP() << "one hardware thread or no OpenBLAS: no split is made";
  const testing::ScopedBlasThreadPolicy hold(BlasThreadPolicy::hold_during_split_factorizations);
  const int count = SingleThreadedBlas::threads_now();
  const bool serial = SerialOpenMpRegions::serial_now();
  {
    ThreadCountWatch watch;
    LinearAbfOptions options;
    options.solver_options.backend = BackendChoice::cpu;
    const AngleMapResult angles = linear_abf(large_disk(), options);
    watch.stop();
    ASSERT_TRUE(angles.report.ok()) << angles.report.message;
    EXPECT_NE(angles.report.solver.find("two subtrees"), std::string::npos)
        << angles.report.solver;
    EXPECT_EQ(watch.smallest(), 1);  // Held while the halves ran ...
    EXPECT_EQ(SingleThreadedBlas::threads_now(), count);  // ... and restored.
  }
  for (const std::string stage : {"solve", "reconstruction"}) {
    EXPECT_EQ(linear_abf(large_disk(), stopping_at(stage, false)).report.status,
              Status::cancelled);
    EXPECT_EQ(SingleThreadedBlas::threads_now(), count) << "cancelled at " << stage;
    EXPECT_THROW((void)linear_abf(large_disk(), stopping_at(stage, true)), std::runtime_error);
    EXPECT_EQ(SingleThreadedBlas::threads_now(), count) << "thrown at " << stage;
  }
  EXPECT_EQ(SerialOpenMpRegions::serial_now(), serial);
}

TEST(BlasThreadPolicy, BothPoliciesGiveTheSameMap) {
  if (!machine_can_split()) GTEST_SKIP() << "one hardware thread or no OpenBLAS: no split is made";
  LinearAbfOptions options;
  options.solver_options.backend = BackendChoice::cpu;
  const AngleMapResult whole = linear_abf(large_disk(), options);
  const testing::ScopedBlasThreadPolicy hold(BlasThreadPolicy::hold_during_split_factorizations);
  const AngleMapResult halves = linear_abf(large_disk(), options);
  ASSERT_TRUE(whole.report.ok() && halves.report.ok());
  // Two factorizations of the same system in other orders: the angles agree to the solve's
  // rounding, amplified by the reduced system's conditioning. Each angle is O(1); the bound is
  // 1e6 machine epsilons, for condition numbers up to 1e6 (a mesh of sound, jittered triangles).
  EXPECT_LT((whole.angles - halves.angles).cwiseAbs().maxCoeff(), 1e6 * 2.2e-16);
}

}  // namespace
}  // namespace harmonia
