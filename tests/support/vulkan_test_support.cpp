#include "support/vulkan_test_support.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <atomic>
#include <cstdio>

#include "harmonia/types.h"

namespace harmonia::testing {

#ifdef HARMONIA_HAVE_VULKAN
namespace {

std::atomic<int> validation_messages{0};

struct TestContext {
  bool attempted = false;
  std::shared_ptr<vulkan::Context> context;
  std::string reason;
};

TestContext& test_context() {
  static TestContext shared;
  return shared;
}

void create_test_context(TestContext& test) {
  vulkan::ContextOptions options;
  options.device_name = "llvmpipe";
  options.enable_validation = true;
  options.debug_callback = [](vulkan::MessageSeverity severity, std::string_view message) {
    if (severity != vulkan::MessageSeverity::warning && severity != vulkan::MessageSeverity::error)
      return;
    ++validation_messages;
    ADD_FAILURE() << "Vulkan validation "
                  << (severity == vulkan::MessageSeverity::error ? "error" : "warning") << ": "
                  << message;
  };
  try {
    test.context = std::make_shared<vulkan::Context>(vulkan::Context::create(options));
  } catch (const Error& error) {
    test.reason = error.what();
  }
}

// Destroys the shared context before the test program ends, so that what the validation layer
// reports when the device is destroyed (objects harmonia leaked) still fails the run.
class VulkanEnvironment : public ::testing::Environment {
 public:
  void TearDown() override { test_context().context.reset(); }
};

[[maybe_unused]] ::testing::Environment* const vulkan_environment =
    ::testing::AddGlobalTestEnvironment(new VulkanEnvironment);

}  // namespace

std::shared_ptr<vulkan::Context> vulkan_test_context(std::string* reason) {
  TestContext& test = test_context();
  if (!test.attempted) {
    test.attempted = true;
    create_test_context(test);
  }
  if (reason != nullptr) *reason = test.reason;
  return test.context;
}

int vulkan_validation_messages() { return validation_messages.load(); }
#endif

int run_with_environment(const std::string& environment, const std::string& command,
                         std::string* output) {
  const std::string line = "env " + environment + " " + command + " 2>&1";
  FILE* pipe = popen(line.c_str(), "r");
  if (pipe == nullptr) return -1;
  std::array<char, 4096> chunk{};
  std::string text;
  while (fgets(chunk.data(), static_cast<int>(chunk.size()), pipe) != nullptr) text += chunk.data();
  const int status = pclose(pipe);
  if (output != nullptr) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

#ifdef HARMONIA_HAVE_VULKAN
void expect_moved_to_the_cpu(const SolveReport& report) {
  ASSERT_TRUE(report.ok()) << report.message;
  EXPECT_EQ(report.backend, BackendKind::vulkan);
  ASSERT_FALSE(report.fallbacks.empty());
  for (const std::string& notice : report.fallbacks) {
    EXPECT_NE(notice.find("solved on the CPU"), std::string::npos) << notice;
    EXPECT_NE(notice.find("stopped after"), std::string::npos) << notice;
  }
  EXPECT_NE(report.solver.find("(after the device's"), std::string::npos) << report.solver;
}

void expect_refused_with_figures(const SolveReport& report) {
  EXPECT_EQ(report.status, Status::not_converged);
  EXPECT_NE(report.message.find("stopped after"), std::string::npos) << report.message;
  EXPECT_NE(report.message.find("e-"), std::string::npos) << report.message;  // scientific notation
  EXPECT_TRUE(report.fallbacks.empty());
}
#endif

}  // namespace harmonia::testing
