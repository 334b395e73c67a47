#pragma once
// A new lavapipe context with validation for tests that break it on purpose (fault injection) or
// need other features than the shared test context; validation messages fail the test.

#include <gtest/gtest.h>

#include <memory>

#include "harmonia/vulkan_context.h"

namespace harmonia::testing {

inline std::shared_ptr<vulkan::Context> fresh_vulkan_context(bool enable_float64 = false) {
  vulkan::ContextOptions options;
  options.device_name = "llvmpipe";
  options.enable_validation = true;
  options.enable_float64 = enable_float64;
  options.debug_callback = [](vulkan::MessageSeverity severity, std::string_view message) {
    if (severity == vulkan::MessageSeverity::warning || severity == vulkan::MessageSeverity::error)
      ADD_FAILURE() << "Vulkan validation: " << message;
  };
  return std::make_shared<vulkan::Context>(vulkan::Context::create(options));
}

}  // namespace harmonia::testing
