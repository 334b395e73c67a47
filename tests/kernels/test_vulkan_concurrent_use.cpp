// The library used from several threads at once on one shared Vulkan context (lavapipe, with the
// validation layer): each thread maps its own mesh with its own solver object on the device, and
// every result equals the serial one on the same context bit for bit, without a validation
// message. The ThreadSanitizer run of docs/testing.md, "Sanitizers" runs it to show it race-free.
#include <gtest/gtest.h>

#include <functional>
#include <vector>

#include "harmonia/procedural.h"
#include "support/concurrent_map_jobs.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

TEST(VulkanConcurrentUse, MapsSharingOneContextGiveTheSerialResultsBitForBit) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  SolverOptions shared_device;
  shared_device.backend = BackendChoice::vulkan;
  shared_device.vulkan_context = vulkan_test_context();
  const Mesh disk = planar_disk(10, 0.3);
  const Mesh cap = hemisphere(8);
  const Mesh small_cap = hemisphere(6);
  const std::vector<std::function<Layouts()>> jobs = {
      [&] { return fixed_boundary_twice(disk, shared_device); },
      [&] { return lscm_once(cap, shared_device); },
      [&] { return quasi_harmonic_once(small_cap, shared_device); },
      [&] { return fixed_boundary_twice(cap, shared_device); }};
  expect_serial_results(run_serially_and_concurrently(jobs));
}

}  // namespace
}  // namespace harmonia::testing
