// The segmentation of a surface into charts (atlas/chart_segmentation.h): every chart keeps a seed
// face of its own through the relaxation rounds and the absorbing of small charts. The seeds rank
// the charts in the tie-breaks that make the charts independent of the face order; a chart whose
// seed was lost in a relaxation round once ranked by whatever lay before the rank array. And the
// elimination of charts leaves a sphere about the charts its normal cone needs.
#include <cmath>

#include <Eigen/Geometry>
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

// The six faces of a cube projected onto the sphere are charts whose every normal lies within
// acos(1/sqrt(3)) = 54.7 degrees of their centre: six charts fit the default 60-degree cone. The
// greedy pass and the Lloyd rounds alone keep the charts they start with (eight on the sphere as
// made, six or eight turned); with the elimination a sphere at any of these resolutions and turns
// gets at most seven, never more than without, each still a connected set of faces whose normals
// lie within the joining cone of the chart's mean normal (the cone small charts are absorbed
// within), and every face has a chart.
TEST(ChartSegmentation, EliminationLeavesASphereAboutTheChartsItsConeNeeds) {
  for (const int subdivisions : {3, 4, 5})
  for (const double angle : {0.0, 0.3, 0.7, 1.1}) {
    SCOPED_TRACE("unit_sphere(" + std::to_string(subdivisions) + ") turned by " + std::to_string(angle));
    Mesh mesh = unit_sphere(subdivisions);
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(angle, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
    mesh.vertices = mesh.vertices * turn.transpose();
    const detail::FaceGeometry geometry = detail::face_geometry(mesh);
    detail::SegmentationOptions options;
    options.eliminate_charts = false;
    const int without = detail::segment_into_charts(geometry, options).chart_count;
    options.eliminate_charts = true;
    const detail::Segmentation segmentation = detail::segment_into_charts(geometry, options);
    EXPECT_LE(segmentation.chart_count, 7);
    EXPECT_LE(segmentation.chart_count, without);

    const double cone_cosine = std::cos(detail::joining_cone(options));
    std::vector<Eigen::Vector3d> normal_sum(static_cast<std::size_t>(segmentation.chart_count), Eigen::Vector3d::Zero());
    for (int f = 0; f < mesh.face_count(); ++f) {
      const int chart = segmentation.chart_of_face[static_cast<std::size_t>(f)];
      ASSERT_GE(chart, 0) << "face " << f;
      normal_sum[static_cast<std::size_t>(chart)] += geometry.area[static_cast<std::size_t>(f)] * geometry.normal[static_cast<std::size_t>(f)];
    }
    for (int f = 0; f < mesh.face_count(); ++f) {
      const int chart = segmentation.chart_of_face[static_cast<std::size_t>(f)];
      const Eigen::Vector3d mean = normal_sum[static_cast<std::size_t>(chart)].normalized();
      EXPECT_GE(geometry.normal[static_cast<std::size_t>(f)].dot(mean), cone_cosine) << "face " << f << ", chart " << chart;
    }
    // Connected: a walk across the faces' edges from each chart's seed reaches all its faces.
    std::vector<char> reached(static_cast<std::size_t>(mesh.face_count()), 0);
    for (int chart = 0; chart < segmentation.chart_count; ++chart) {
      std::vector<int> stack{segmentation.seed_of_chart[static_cast<std::size_t>(chart)]};
      reached[static_cast<std::size_t>(stack.back())] = 1;
      while (!stack.empty()) {
        const int f = stack.back();
        stack.pop_back();
        for (const int g : geometry.across[static_cast<std::size_t>(f)])
          if (g >= 0 && !reached[static_cast<std::size_t>(g)] && segmentation.chart_of_face[static_cast<std::size_t>(g)] == chart) {
            reached[static_cast<std::size_t>(g)] = 1;
            stack.push_back(g);
          }
      }
    }
    for (int f = 0; f < mesh.face_count(); ++f) EXPECT_TRUE(reached[static_cast<std::size_t>(f)]) << "face " << f << " apart from its chart's seed";
  }
}

}  // namespace
}  // namespace harmonia
