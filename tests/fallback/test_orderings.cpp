// Fill-reducing orderings of the CPU direct solvers: nested dissection stays deterministic when
// several threads of one application ask for it at the same time.
#include <algorithm>
#include <numeric>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "fallback/direct_solvers.h"
#include "harmonia/io.h"
#include "planar/map_pipeline.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

TEST(NestedDissection, ConcurrentOrderingsEqualTheSequentialOne) {
#ifndef HARMONIA_HAVE_CHOLMOD
  GTEST_SKIP() << "built without CHOLMOD: no nested dissection ordering";
#endif
  const Mesh mesh = read_mesh(testing::shared_data_dir() / "disk" / "face.obj");
  const Eigen::SparseMatrix<double> pattern = detail::operator_pattern(mesh).pattern;
  const Eigen::SparseMatrix<double> lower = pattern.triangularView<Eigen::Lower>();
  const std::vector<int> sequential = detail::nested_dissection_ordering(lower);
  ASSERT_EQ(sequential.size(), static_cast<std::size_t>(mesh.vertex_count()));
  std::vector<int> sorted = sequential;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> identity(sorted.size());
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(sorted, identity);  // A permutation.
  // METIS draws random numbers from process-wide state: unserialized, concurrent calls interleave
  // the draws and differ from the sequential result (seen on this mesh every time).
  for (int attempt = 0; attempt < 3; ++attempt) {
    std::vector<std::vector<int>> results(3);
    std::vector<std::thread> threads;
    for (auto& result : results)
      threads.emplace_back([&result, &lower] { result = detail::nested_dissection_ordering(lower); });
    for (auto& thread : threads) thread.join();
    for (const auto& result : results) EXPECT_EQ(result, sequential) << "attempt " << attempt;
  }
}

}  // namespace
}  // namespace harmonia
