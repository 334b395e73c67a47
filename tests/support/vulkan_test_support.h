#pragma once
// The Vulkan device the tests run on: Mesa's lavapipe (a CPU implementation every CI machine can
// install) with the Khronos validation layer on. The harness, not the library, makes this choice
// (ContextOptions). Every validation warning or error fails the test that caused it.

#include <memory>
#include <string>

#ifdef HARMONIA_HAVE_VULKAN
#include "harmonia/map_result.h"
#include "harmonia/vulkan_context.h"
#endif

namespace harmonia::testing {

#ifdef HARMONIA_HAVE_VULKAN
//! The shared test context (created on first use): the device named "llvmpipe", validation on,
//! and a debug callback that turns each validation warning or error into a test failure
//! (ADD_FAILURE in the test running at the time). Null when lavapipe or the validation layer is
//! missing; `reason` then says why.
std::shared_ptr<vulkan::Context> vulkan_test_context(std::string* reason = nullptr);

//! Validation warnings and errors seen so far in this process.
int vulkan_validation_messages();

//! A run whose backend was left to harmonia and whose device solves were capped far too low:
//! it succeeded on the test device's report, each of its notices (at least one) saying that a
//! solve moved to the CPU, with the device's figures, and its solver named after the device's.
void expect_moved_to_the_cpu(const SolveReport& report);

//! The same run with the device asked for: it failed with the solve's figures, and no fallback.
void expect_refused_with_figures(const SolveReport& report);
#endif

//! Runs `command` through the shell with `environment` (e.g. "VK_ICD_FILENAMES=/none") prefixed;
//! returns the exit status and fills `output` with stdout and stderr together.
int run_with_environment(const std::string& environment, const std::string& command,
                         std::string* output);

}  // namespace harmonia::testing

#ifdef HARMONIA_HAVE_VULKAN
//! Skips the current test when the test device is unavailable (with the reason).
#define HARMONIA_REQUIRE_VULKAN_TEST_DEVICE()                            \
  do {                                                                   \
    std::string vulkan_unavailable;                                      \
    if (!::harmonia::testing::vulkan_test_context(&vulkan_unavailable))  \
      GTEST_SKIP() << "no lavapipe test device: " << vulkan_unavailable; \
  } while (false)
#endif
