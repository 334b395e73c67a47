#include "support/test_support.h"

#include <algorithm>
#include <cstdlib>

namespace harmonia::testing {

std::filesystem::path shared_data_dir() {
  if (const char* env = std::getenv("HARMONIA_SHARED_DATA"); env != nullptr && *env != '\0') return env;
  return HARMONIA_SHARED_DATA_DIR;
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

std::filesystem::path cli_path() { return HARMONIA_CLI_PATH; }

}  // namespace harmonia::testing
