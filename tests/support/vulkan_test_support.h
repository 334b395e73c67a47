#pragma once
// The Vulkan device the tests run on: Mesa's lavapipe (a CPU implementation every CI machine can
// install) with the Khronos validation layer on. The harness, not the library, makes this choice
// (ContextOptions). Every validation warning or error fails the test that caused it.

#include <memory>
#include <string>

#ifdef HARMONIA_HAVE_VULKAN
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
