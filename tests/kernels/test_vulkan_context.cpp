// Vulkan context creation and borrowing, device choice, and every failure that can be provoked:
// no driver (hidden ICD), only a software device, unknown device, bad borrowed handles, a buffer
// beyond the device's limits, values beyond fp32; the validation layer really reports.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>

#include "harmonia/types.h"
#include "harmonia/vulkan_context.h"
#include "kernels/context_impl.h"
#include "kernels/kernel_test_data.h"
#include "kernels/vulkan_backend.h"
#include "solve/backend_selection.h"
#include "support/test_support.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using vulkan::detail::VulkanBackend;

// Sets the Vulkan loader's driver list for the scope (both the current and the older variable
// name) and restores it afterwards. The loader reads them at every instance creation.
class DriverListOverride {
 public:
  explicit DriverListOverride(const std::string& files) {
    for (const char* name : names_) {
      const char* old = std::getenv(name);
      previous_.emplace_back(old != nullptr ? std::optional<std::string>(old) : std::nullopt);
      setenv(name, files.c_str(), 1);
    }
  }
  ~DriverListOverride() {
    for (std::size_t k = 0; k < std::size(names_); ++k) {
      if (previous_[k])
        setenv(names_[k], previous_[k]->c_str(), 1);
      else
        unsetenv(names_[k]);
    }
  }

 private:
  static constexpr const char* names_[] = {"VK_DRIVER_FILES", "VK_ICD_FILENAMES"};
  std::vector<std::optional<std::string>> previous_;
};

const char* hidden_driver = "/nonexistent/harmonia-no-driver.json";

std::filesystem::path lavapipe_manifest() {
  for (const char* path : {"/usr/share/vulkan/icd.d/lvp_icd.x86_64.json",
                           "/usr/share/vulkan/icd.d/lvp_icd.aarch64.json"})
    if (std::filesystem::exists(path)) return path;
  return {};
}

Status status_of(const std::function<void()>& action, std::string* message) {
  try {
    action();
  } catch (const Error& error) {
    *message = error.what();
    return error.status();
  }
  return Status::ok;
}

TEST(VulkanContext, TheTestDeviceIsLavapipeWithValidation) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto context = vulkan_test_context();
  const vulkan::DeviceInfo& device = context->device();
  EXPECT_NE(device.name.find("llvmpipe"), std::string::npos) << device.name;
  EXPECT_EQ(device.type, vulkan::DeviceType::cpu);
  EXPECT_GE(device.api_version, VK_API_VERSION_1_1);
  EXPECT_GE(device.subgroup_size, 1u);
  EXPECT_GT(device.max_storage_buffer_range, 0u);
  EXPECT_TRUE(device.unified_memory) << "lavapipe's memory is host memory";
  EXPECT_FALSE(context->borrowed());
  EXPECT_NE(context->impl().messenger, VK_NULL_HANDLE);
}

TEST(VulkanContext, ValidationMessagesReachTheCallback) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  int messages = 0;
  vulkan::ContextOptions options;
  options.device_name = "llvmpipe";
  options.enable_validation = true;
  options.debug_callback = [&messages](vulkan::MessageSeverity severity, std::string_view) {
    if (severity == vulkan::MessageSeverity::error) ++messages;
  };
  const vulkan::Context context = vulkan::Context::create(options);
  // A deliberate misuse: a buffer of size 0 (VUID-VkBufferCreateInfo-size-00912).
  auto& impl = context.impl();
  auto info = vulkan::detail::vk_info<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = 0;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  if (impl.vk.vkCreateBuffer(impl.device, &info, nullptr, &buffer) == VK_SUCCESS)
    impl.vk.vkDestroyBuffer(impl.device, buffer, nullptr);
  EXPECT_GE(messages, 1) << "the validation layer did not report an invalid call";
}

TEST(VulkanContext, UnknownDeviceNameListsTheDevices) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  vulkan::ContextOptions options;
  options.device_name = "no-such-gpu";
  std::string message;
  EXPECT_EQ(status_of([&] { (void)vulkan::Context::create(options); }, &message),
            Status::unsupported);
  EXPECT_NE(message.find("no-such-gpu"), std::string::npos) << message;
  EXPECT_NE(message.find("llvmpipe"), std::string::npos) << message;

  options.device_name.clear();
  options.device_index = 99;
  EXPECT_EQ(status_of([&] { (void)vulkan::Context::create(options); }, &message),
            Status::unsupported);
  EXPECT_NE(message.find("index 99 is out of range"), std::string::npos) << message;
}

TEST(VulkanContext, MovedFromContextSaysSo) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  vulkan::ContextOptions options;
  options.device_name = "llvmpipe";
  vulkan::Context first = vulkan::Context::create(options);
  const vulkan::Context second = std::move(first);
  EXPECT_NE(second.device().name.find("llvmpipe"), std::string::npos);
  EXPECT_THROW((void)first.device(), std::logic_error);  // NOLINT(bugprone-use-after-move)
}

TEST(VulkanContext, HiddenDriverIsAClearErrorAndAutomaticFallsBackToTheCpu) {
  const DriverListOverride no_driver(hidden_driver);
  std::string message;
  EXPECT_EQ(status_of([&] { (void)vulkan::Context::create(); }, &message), Status::unsupported);
  EXPECT_NE(message.find("no Vulkan driver"), std::string::npos) << message;

  auto vulkan_backend = detail::make_backend(BackendChoice::vulkan, &message);
  EXPECT_EQ(vulkan_backend, nullptr);
  EXPECT_NE(message.find("Vulkan backend is unavailable: no Vulkan driver"), std::string::npos)
      << message;
  EXPECT_NE(message.find("--backend cpu"), std::string::npos) << message;

  auto automatic = detail::make_backend(BackendChoice::automatic, &message);
  ASSERT_NE(automatic, nullptr);
  EXPECT_EQ(automatic->kind(), BackendKind::cpu);
  EXPECT_NE(message.find("no hardware Vulkan device (no Vulkan driver"), std::string::npos)
      << message;
  EXPECT_NE(message.find("using the CPU backend"), std::string::npos) << message;
}

TEST(VulkanContext, AutomaticNeverPicksASoftwareDevice) {
  const std::filesystem::path manifest = lavapipe_manifest();
  if (manifest.empty()) GTEST_SKIP() << "lavapipe is not installed";
  const DriverListOverride only_lavapipe(manifest.string());
  std::string message;
  auto automatic = detail::make_backend(BackendChoice::automatic, &message);
  ASSERT_NE(automatic, nullptr);
  EXPECT_EQ(automatic->kind(), BackendKind::cpu);
  EXPECT_NE(message.find("software device"), std::string::npos) << message;
  // Asked for explicitly, the software device is used.
  auto vulkan_backend = detail::make_backend(BackendChoice::vulkan, &message);
  ASSERT_NE(vulkan_backend, nullptr) << message;
  EXPECT_EQ(vulkan_backend->kind(), BackendKind::vulkan);
  EXPECT_TRUE(message.empty()) << message;
}

TEST(VulkanContext, TheCallersContextIsUsed) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  SolverOptions options;
  options.vulkan_context = vulkan_test_context();
  for (const BackendChoice choice : {BackendChoice::vulkan, BackendChoice::automatic}) {
    options.backend = choice;
    std::string message;
    auto backend = detail::make_backend(options, &message);
    ASSERT_NE(backend, nullptr) << message;
    ASSERT_EQ(backend->kind(), BackendKind::vulkan);
    EXPECT_EQ(&dynamic_cast<VulkanBackend&>(*backend).context(), options.vulkan_context.get());
  }
}

TEST(VulkanContext, CliReportsAMissingDriver) {
  const std::filesystem::path cli = cli_path();
  if (cli.empty()) GTEST_SKIP() << "the CLI is not built";
  const std::filesystem::path mesh = assets_dir() / "io" / "square_textured.obj";
  const std::filesystem::path output =
      std::filesystem::temp_directory_path() / "harmonia_vulkan_cli_test.obj";
  const std::string environment =
      std::string("VK_ICD_FILENAMES=") + hidden_driver + " VK_DRIVER_FILES=" + hidden_driver;
  std::string text;
  const int vulkan_status = run_with_environment(
      environment,
      cli.string() + " unwrap --backend vulkan " + mesh.string() + " " + output.string(), &text);
  EXPECT_EQ(vulkan_status, 5) << text;
  EXPECT_NE(text.find("no Vulkan driver"), std::string::npos) << text;
  const int automatic_status = run_with_environment(
      environment, cli.string() + " unwrap --backend auto " + mesh.string() + " " + output.string(),
      &text);
  EXPECT_EQ(automatic_status, 0) << text;
  std::filesystem::remove(output);
}

TEST(VulkanContext, WrapBorrowsTheApplicationsObjects) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto owner = vulkan_test_context();
  const auto& impl = owner->impl();
  int locks = 0, unlocks = 0;
  vulkan::ExternalVulkan external;
  external.instance = impl.instance;
  external.physical_device = impl.physical_device;
  external.device = impl.device;
  external.queue = impl.queue;
  external.queue_family_index = impl.queue_family;
  external.api_version = VK_API_VERSION_1_1;
  external.get_instance_proc_addr = impl.vk.vkGetInstanceProcAddr;
  external.pipeline_cache = impl.pipeline_cache;
  external.lock_queue = [&locks] { ++locks; };
  external.unlock_queue = [&unlocks] { ++unlocks; };

  const RowMajorSparse a = hemisphere_laplacian(12);
  const Eigen::MatrixXd x = random_block(static_cast<int>(a.rows()), 2, 7u);
  const auto product_on = [&](std::shared_ptr<vulkan::Context> context) {
    VulkanBackend backend(std::move(context));
    const auto matrix = backend.upload(a);
    const auto x_device = backend.upload(x);
    const auto y_device = backend.allocate(static_cast<int>(a.rows()), 2);
    backend.spmv(*matrix, *x_device, *y_device);
    return y_device->download();
  };
  {
    auto borrowed = std::make_shared<vulkan::Context>(vulkan::Context::wrap(external));
    EXPECT_TRUE(borrowed->borrowed());
    EXPECT_EQ(borrowed->device().name, owner->device().name);
    const Eigen::MatrixXd on_borrowed = product_on(borrowed);
    EXPECT_EQ(on_borrowed, product_on(owner));  // Same device, same kernels: same bits.
    EXPECT_GT(locks, 0);
    EXPECT_EQ(locks, unlocks);
  }
  // The borrowed context is gone; the owner's device still works.
  EXPECT_EQ(product_on(owner).rows(), a.rows());
}

TEST(VulkanContext, WrapRefusesIncompleteHandles) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const auto& impl = vulkan_test_context()->impl();
  vulkan::ExternalVulkan external;
  std::string message;
  EXPECT_EQ(status_of([&] { (void)vulkan::Context::wrap(external); }, &message),
            Status::unsupported);
  EXPECT_NE(message.find("must all be given"), std::string::npos) << message;
  external.instance = impl.instance;
  external.physical_device = impl.physical_device;
  external.device = impl.device;
  external.queue = impl.queue;
  external.queue_family_index = impl.queue_family;
  external.api_version = VK_API_VERSION_1_0;
  EXPECT_EQ(status_of([&] { (void)vulkan::Context::wrap(external); }, &message),
            Status::unsupported);
  EXPECT_NE(message.find("1.1"), std::string::npos) << message;
  external.api_version = VK_API_VERSION_1_1;
  external.lock_queue = [] {};
  EXPECT_EQ(status_of([&] { (void)vulkan::Context::wrap(external); }, &message),
            Status::unsupported);
  EXPECT_NE(message.find("lock_queue and unlock_queue"), std::string::npos) << message;
}

TEST(VulkanContext, TooLargeBufferIsAClearErrorBeforeAllocating) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  VulkanBackend backend(vulkan_test_context());
  const std::uint64_t limit = backend.context().device().max_storage_buffer_range;
  const int rows = static_cast<int>(std::min<std::uint64_t>(limit / 4 + 1024, 2'000'000'000));
  std::string message;
  EXPECT_EQ(status_of([&] { (void)backend.allocate(rows, 1); }, &message), Status::device_failure);
  EXPECT_NE(message.find("maxStorageBufferRange"), std::string::npos) << message;
  EXPECT_NE(message.find("vector block"), std::string::npos) << message;
  EXPECT_NE(message.find("CPU backend"), std::string::npos) << message;
  // The backend is still usable afterwards.
  const auto small = backend.upload(Eigen::MatrixXd::Ones(4, 1));
  EXPECT_EQ(backend.dot(*small, *small)[0], 4.0);
}

TEST(VulkanContext, ValuesBeyondFloatRangeAreRefused) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  VulkanBackend backend(vulkan_test_context());
  Eigen::MatrixXd values = Eigen::MatrixXd::Ones(5, 1);
  values(3, 0) = 1e300;
  std::string message;
  EXPECT_EQ(status_of([&] { (void)backend.upload(values); }, &message), Status::unsupported);
  EXPECT_NE(message.find("entry 3"), std::string::npos) << message;
  EXPECT_NE(message.find("float32 range"), std::string::npos) << message;
}

}  // namespace
}  // namespace harmonia::testing
