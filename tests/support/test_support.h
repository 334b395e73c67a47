#pragma once
// Helpers shared by the tests: where the corpus and assets are, and corpus mesh listing.

#include <filesystem>
#include <string>
#include <vector>

#include "harmonia/blas_threads.h"

namespace harmonia::testing {

//! ../shared/data beside the checkout (compile-time default), or $HARMONIA_SHARED_DATA if set.
std::filesystem::path shared_data_dir();
//! Whether this run is the continuous integration's (CI=true in the environment): CI always has
//! ../shared beside the checkout, so a test that needs the corpus (or its tools) fails there when
//! they are missing instead of passing by skipping.
bool corpus_required();
//! Skips the test where the corpus (or a tool of ../shared/tools) it needs is missing, with
//! `message`; under CI=true fails instead. Use in a test body: `if (meshes.empty())
//! HARMONIA_SKIP_WITHOUT_CORPUS("no corpus at " << folder);`.
#define HARMONIA_SKIP_WITHOUT_CORPUS(message)                                      \
  do {                                                                             \
    if (::harmonia::testing::corpus_required()) {                                  \
      FAIL() << "CI=true, and the corpus this test needs is missing: " << message; \
    } else {                                                                       \
      GTEST_SKIP() << message;                                                     \
    }                                                                              \
  } while (false)

//! tests/assets in the source tree.
std::filesystem::path assets_dir();
//! Sorted list of *.obj files in shared_data_dir()/subfolder; empty if the folder is absent.
std::vector<std::filesystem::path> corpus_meshes(const std::string& subfolder);
//! The whole file as bytes (empty when it cannot be read).
std::string file_bytes(const std::filesystem::path& path);
//! How many times `pattern` starts in `text` (overlapping occurrences count).
int count_occurrences(const std::string& text, const std::string& pattern);
//! The number printed right after the first `label` in `message` (NaN when the label is missing).
double figure_after(const std::string& message, const std::string& label);
//! A fresh, empty folder under the system temp directory for the running test
//! ("harmonia-PREFIX-PID-TESTNAME"), removed with everything in it when destroyed.
class ScratchFolder {
 public:
  explicit ScratchFolder(const std::string& prefix);
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::filesystem::path file(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

//! The BlasThreadPolicy for a scope (a test that needs two-thread factorizations sets
//! hold_during_split_factorizations), restored at its end.
class ScopedBlasThreadPolicy {
 public:
  explicit ScopedBlasThreadPolicy(BlasThreadPolicy policy)
      : previous_(set_blas_thread_policy(policy)) {}
  ~ScopedBlasThreadPolicy() { set_blas_thread_policy(previous_); }
  ScopedBlasThreadPolicy(const ScopedBlasThreadPolicy&) = delete;
  ScopedBlasThreadPolicy& operator=(const ScopedBlasThreadPolicy&) = delete;

 private:
  BlasThreadPolicy previous_;
};

//! Path of the harmonia CLI binary built with the tests (empty if the CLI is not built).
std::filesystem::path cli_path();

}  // namespace harmonia::testing
