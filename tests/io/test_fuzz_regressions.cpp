// The fuzz targets of the readers (tests/fuzz) in the ordinary suite: every seed of their corpus and
// every input a past fuzzing run found (tests/fuzz/regressions/TARGET/, minimized) goes through its
// target again, with the same checks of the parse and of the topology report and both cleanups,
// so that a finding once fixed stays fixed in every build, sanitized or not.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz/fuzz_checks.h"
#include "fuzz/fuzz_targets.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;

struct BrokenPromise : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void throw_broken_promise(std::string_view what) {
  throw BrokenPromise(std::string(what));
}

std::vector<std::uint8_t> contents_of(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

//! Runs every file of `folder` (if it exists) through `target`; returns how many ran.
int replay(const fuzz::FuzzTarget& target, const fs::path& folder) {
  if (!fs::is_directory(folder)) return 0;
  int count = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::vector<std::uint8_t> input = contents_of(entry.path());
    try {
      target.run(input);
    } catch (const BrokenPromise& broken) {
      ADD_FAILURE() << entry.path() << ": " << broken.what();
    } catch (const std::exception& error) {
      ADD_FAILURE() << entry.path() << ": unexpected exception: " << error.what();
    }
    ++count;
  }
  return count;
}

class FuzzReplay : public ::testing::TestWithParam<fuzz::FuzzTarget> {
 protected:
  void SetUp() override { previous_ = fuzz::set_finding_handler(throw_broken_promise); }
  void TearDown() override { fuzz::set_finding_handler(previous_); }

 private:
  fuzz::FindingHandler previous_ = nullptr;
};

TEST_P(FuzzReplay, SeedsAndPastFindingsKeepEveryPromise) {
  const fuzz::FuzzTarget& target = GetParam();
  const fs::path fuzz_dir = HARMONIA_FUZZ_DIR;
  const int seeds = replay(target, fuzz_dir / "corpus" / target.name);
  EXPECT_GT(seeds, 0) << "no seed corpus for " << target.name;
  replay(target, fuzz_dir / "regressions" / target.name);
}

INSTANTIATE_TEST_SUITE_P(Readers, FuzzReplay, ::testing::ValuesIn(fuzz::fuzz_targets().begin(),
                                                                  fuzz::fuzz_targets().end()),
                         [](const auto& info) { return std::string(info.param.name); });

// A finding of the checks themselves reaches the handler (the replay above would miss nothing).
TEST(FuzzChecks, ABrokenPromiseReachesTheHandler) {
  const fuzz::FindingHandler previous = fuzz::set_finding_handler(throw_broken_promise);
  Mesh bad;
  bad.vertices.resize(3, 3);
  bad.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  bad.faces.resize(1, 3);
  bad.faces << 0, 1, 7;  // A parser must never accept an index out of range.
  EXPECT_THROW(fuzz::check_accepted_mesh(bad), BrokenPromise);
  fuzz::set_finding_handler(previous);
}

}  // namespace
}  // namespace harmonia
