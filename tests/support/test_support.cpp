#include "support/test_support.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <string_view>

namespace harmonia::testing {

std::filesystem::path shared_data_dir() {
  if (const char* env = std::getenv("HARMONIA_SHARED_DATA"); env != nullptr && *env != '\0')
    return env;
  return HARMONIA_SHARED_DATA_DIR;
}

bool corpus_required() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string_view(ci) == "true";
}

std::filesystem::path assets_dir() { return HARMONIA_TEST_ASSETS_DIR; }

std::vector<std::filesystem::path> corpus_meshes(const std::string& subfolder) {
  std::vector<std::filesystem::path> meshes;
  const std::filesystem::path folder = shared_data_dir() / subfolder;
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) return meshes;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (entry.path().extension() == ".obj") meshes.push_back(entry.path());
  }
  std::sort(meshes.begin(), meshes.end());
  return meshes;
}

ScratchFolder::ScratchFolder(const std::string& prefix) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string test_name = info != nullptr ? info->name() : "outside-a-test";
  path_ = std::filesystem::temp_directory_path() /
          ("harmonia-" + prefix + "-" + std::to_string(::getpid()) + "-" + test_name);
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;  // A test may have made the folder read-only to provoke write errors.
  std::filesystem::permissions(path_, std::filesystem::perms::owner_all,
                               std::filesystem::perm_options::add, ignored);
  std::filesystem::remove_all(path_, ignored);
}

std::filesystem::path cli_path() { return HARMONIA_CLI_PATH; }

std::string file_bytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream bytes;
  bytes << file.rdbuf();
  return bytes.str();
}

double figure_after(const std::string& message, const std::string& label) {
  const std::size_t at = message.find(label);
  if (at == std::string::npos) return std::numeric_limits<double>::quiet_NaN();
  return std::strtod(message.c_str() + at + label.size(), nullptr);
}

int count_occurrences(const std::string& text, const std::string& pattern) {
  int count = 0;
  for (std::size_t at = text.find(pattern); at != std::string::npos;
       at = text.find(pattern, at + 1)) {
    ++count;
  }
  return count;
}

}  // namespace harmonia::testing
