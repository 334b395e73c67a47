// The segmentation of a surface into charts (atlas/chart_segmentation.h): every chart keeps a seed
// face of its own through the relaxation rounds and the absorbing of small charts. The seeds rank
// the charts in the tie-breaks that make the charts independent of the face order; a chart whose
// seed was lost in a relaxation round once ranked by whatever lay before the rank array.
#include <gtest/gtest.h>

#include "atlas/chart_segmentation.h"
#include "atlas/face_geometry.h"
#include "harmonia/procedural.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

TEST(ChartSegmentation, EveryChartKeepsASeedFaceOfItsOwnThroughTheRelaxation) {
  const std::pair<const char*, Mesh> meshes[] = {{"sphere", unit_sphere(3)},
                                                 {"torus", testing::torus(24, 12)},
                                                 {"octahedron", testing::octahedron()}};
  for (const auto& [name, mesh] : meshes) {
    const detail::FaceGeometry geometry = detail::face_geometry(mesh);
    for (const int rounds : {0, 1, 3}) {
      SCOPED_TRACE(std::string(name) + ", " + std::to_string(rounds) + " relaxation rounds");
      detail::SegmentationOptions options;
      options.relaxation_rounds = rounds;
      const detail::Segmentation segmentation = detail::segment_into_charts(geometry, options);
      ASSERT_GE(segmentation.chart_count, 1);
      ASSERT_EQ(segmentation.seed_of_chart.size(), static_cast<std::size_t>(segmentation.chart_count));
      std::vector<int> faces_of_chart(static_cast<std::size_t>(segmentation.chart_count), 0);
      for (const int chart : segmentation.chart_of_face)
        if (chart >= 0) ++faces_of_chart[static_cast<std::size_t>(chart)];
      for (int chart = 0; chart < segmentation.chart_count; ++chart) {
        const int seed = segmentation.seed_of_chart[static_cast<std::size_t>(chart)];
        ASSERT_GE(seed, 0) << "chart " << chart;
        ASSERT_LT(seed, mesh.face_count()) << "chart " << chart;
        EXPECT_EQ(segmentation.chart_of_face[static_cast<std::size_t>(seed)], chart) << "chart " << chart;
        EXPECT_GT(faces_of_chart[static_cast<std::size_t>(chart)], 0) << "chart " << chart;
      }
    }
  }
}

}  // namespace
}  // namespace harmonia
