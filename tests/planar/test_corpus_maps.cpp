// Tutte's theorem on the corpus: with positive weights and a convex (circle) boundary, every disk
// mesh of /work/shared/data/disk maps without a single flipped or degenerate triangle.
#include <iostream>

#include <gtest/gtest.h>

#include "harmonia/fixed_boundary_map.h"
#include "harmonia/io.h"
#include "harmonia/metrics.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

TEST(CorpusMaps, PositiveWeightsWithACircleBoundaryNeverFlip) {
  const auto meshes = testing::corpus_meshes("disk");
  if (meshes.empty())
    HARMONIA_SKIP_WITHOUT_CORPUS("no disk corpus at " << (testing::shared_data_dir() / "disk")
                 << " (set HARMONIA_SHARED_DATA to the shared data folder)");
  for (const auto& path : meshes) {
    const Mesh mesh = read_mesh(path);
    for (const WeightScheme scheme :
         {WeightScheme::uniform, WeightScheme::mean_value, WeightScheme::shape_preserving}) {
      FixedBoundaryOptions options;
      options.weights = scheme;
      options.boundary.shape = BoundaryShape::circle;
      options.solver.backend = BackendChoice::cpu;
      const MapResult result = fixed_boundary_map(mesh, options);
      ASSERT_EQ(result.report.status, Status::ok)
          << path.filename() << ", " << to_string(scheme) << ": " << result.report.message;
      // Counted independently of the report as well.
      const FlipCount flips = count_flips(result.uv, mesh.faces);
      EXPECT_EQ(flips.flipped, 0) << path.filename() << ", " << to_string(scheme);
      EXPECT_EQ(flips.zero_area, 0) << path.filename() << ", " << to_string(scheme);
      EXPECT_EQ(result.report.boundary_self_intersections, 0) << path.filename();
      EXPECT_LT(result.report.residual, 1e-8) << path.filename() << ", " << to_string(scheme);
      std::cout << path.filename().string() << " (" << mesh.vertex_count() << " vertices) "
                << to_string(scheme) << ": " << result.report.total_seconds() << " s, "
                << result.report.solver << '\n';
    }
  }
}

}  // namespace
}  // namespace harmonia
