// The library used from several threads at once, on the CPU backend: each thread maps its own mesh
// with its own solver object (a reusable mapper that it also updates and solves again), and every
// result equals the serial one bit for bit. The ThreadSanitizer run of docs/testing.md,
// "Sanitizers" runs this test (and its Vulkan twin, tests/kernels/test_vulkan_concurrent_use.cpp)
// to show it race-free.
#include <gtest/gtest.h>

#include <functional>
#include <vector>

#include "harmonia/procedural.h"
#include "support/concurrent_map_jobs.h"

namespace harmonia::testing {
namespace {

TEST(ConcurrentUse, CpuMapsOnSeveralThreadsGiveTheSerialResultsBitForBit) {
  SolverOptions cpu;
  cpu.backend = BackendChoice::cpu;
  const Mesh disk = planar_disk(12, 0.3);
  const Mesh cap = hemisphere(10);
  const Mesh small_disk = planar_disk(8, 0.2);
  const Mesh small_cap = hemisphere(7);
  const std::vector<std::function<Layouts()>> jobs = {
      [&] { return fixed_boundary_twice(disk, cpu); },
      [&] { return lscm_once(cap, cpu); },
      [&] { return quasi_harmonic_once(small_cap, cpu); },
      [&] { return linear_abf_once(small_disk, cpu); },
      [&] { return lscm_once(disk, cpu); },
      [&] { return fixed_boundary_twice(cap, cpu); }};
  expect_serial_results(run_serially_and_concurrently(jobs));
}

}  // namespace
}  // namespace harmonia::testing
