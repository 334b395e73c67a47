// Joining flattened charts whose union flattens within the stretch limit
// (atlas/stretch_bounded_join.h), on surfaces whose answer is known or checked here by hand:
//  - a flat square cut in four quarters joins into one chart, laid out without stretch;
//  - a cube's six squares join in three pairs (each pair a hinge that unfolds exactly) and never
//    three around a corner, whose 90 degrees of curvature no flat layout holds within the limit;
//  - a sphere's charts of the segmentation join into fewer, and every chart that comes back is a
//    disk, lays every face once, keeps every triangle's orientation and stays within the limit,
//    all measured here from the layouts (Sander's L2 stretch written out again below); the same
//    charts on one thread and on two;
//  - a progress callback that says stop stops it.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "atlas/chart_flattening.h"
#include "atlas/chart_mesh.h"
#include "atlas/chart_segmentation.h"
#include "atlas/face_geometry.h"
#include "atlas/stretch_bounded_join.h"
#include "harmonia/mesh.h"
#include "support/topology_meshes.h"
#include "harmonia/procedural.h"

namespace harmonia {
namespace {

using testing::squares;

constexpr double kLimit = 1.0025;                                // the atlas' default
constexpr double kCone = 89.0 * std::numbers::pi / 180.0;       // the widest joining cone
// Rounding of a layout's figures: a few hundred operations of double precision on lengths of 1.
constexpr double kRounding = 1e-9;

// Each face set of `sets` as a chart flattened by the atlas' methods (each must flatten).
std::vector<detail::FinishedChart> flattened(const Mesh& mesh, const detail::FaceGeometry& geometry,
                                             const std::vector<std::vector<int>>& sets) {
  std::vector<detail::FinishedChart> charts;
  for (const std::vector<int>& faces : sets) {
    detail::ChartMesh chart = detail::opened_chart(mesh, geometry, faces);
    std::optional<detail::FlattenedChart> layout = detail::flatten_chart(chart, kLimit, SolverOptions{}).chart;
    EXPECT_TRUE(layout.has_value());
    if (!layout) return {};
    charts.push_back(detail::FinishedChart{std::move(chart), std::move(*layout)});
  }
  return charts;
}

// The charts of a segmentation as the atlas makes them: each face set flattened, and one that does
// not flatten within the limit halved until its pieces do.
std::vector<detail::FinishedChart> flattened_or_halved(const Mesh& mesh, const detail::FaceGeometry& geometry,
                                                       std::vector<std::vector<int>> sets) {
  std::vector<detail::FinishedChart> charts;
  while (!sets.empty()) {
    std::vector<int> faces = std::move(sets.back());
    sets.pop_back();
    detail::ChartMesh chart = detail::opened_chart(mesh, geometry, faces);
    std::optional<detail::FlattenedChart> layout =
        detail::is_disk(chart) ? detail::flatten_chart(chart, kLimit, SolverOptions{}).chart : std::nullopt;
    if (layout) {
      charts.push_back(detail::FinishedChart{std::move(chart), std::move(*layout)});
    } else {
      for (std::vector<int>& half : detail::split_in_two(geometry, faces)) sets.push_back(std::move(half));
    }
  }
  std::sort(charts.begin(), charts.end(), [](const detail::FinishedChart& a, const detail::FinishedChart& b) {
    return a.mesh.surface_face.front() < b.mesh.surface_face.front();
  });
  return charts;
}

// Sander's L2 stretch of a chart's layout, written out from its definition: per triangle, the
// derivatives S_s and S_t of the map from the layout to the surface, the triangle's value
// sqrt((|S_s|^2 + |S_t|^2) / 2), their root mean square weighted by 3D area, with the layout
// first scaled to the chart's 3D area.
double sander_l2(const detail::FinishedChart& chart) {
  const Mesh& mesh = chart.mesh.mesh;
  const Eigen::MatrixX2d& uv = chart.layout.uv;
  double area_3d = 0.0, area_uv = 0.0;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d p0 = mesh.vertices.row(mesh.faces(f, 0)), p1 = mesh.vertices.row(mesh.faces(f, 1)),
                          p2 = mesh.vertices.row(mesh.faces(f, 2));
    area_3d += 0.5 * (p1 - p0).cross(p2 - p0).norm();
    const Eigen::Vector2d q0 = uv.row(mesh.faces(f, 0)), q1 = uv.row(mesh.faces(f, 1)), q2 = uv.row(mesh.faces(f, 2));
    area_uv += 0.5 * ((q1 - q0).x() * (q2 - q0).y() - (q1 - q0).y() * (q2 - q0).x());
  }
  const double to_3d_area = std::sqrt(area_3d / area_uv);
  double weighted = 0.0;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d p0 = mesh.vertices.row(mesh.faces(f, 0)), p1 = mesh.vertices.row(mesh.faces(f, 1)),
                          p2 = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::Vector2d q0 = to_3d_area * uv.row(mesh.faces(f, 0)).transpose();
    const Eigen::Vector2d q1 = to_3d_area * uv.row(mesh.faces(f, 1)).transpose();
    const Eigen::Vector2d q2 = to_3d_area * uv.row(mesh.faces(f, 2)).transpose();
    const double twice_area = (q1.x() - q0.x()) * (q2.y() - q0.y()) - (q2.x() - q0.x()) * (q1.y() - q0.y());
    const Eigen::Vector3d s = (p0 * (q1.y() - q2.y()) + p1 * (q2.y() - q0.y()) + p2 * (q0.y() - q1.y())) / twice_area;
    const Eigen::Vector3d t = (p0 * (q2.x() - q1.x()) + p1 * (q0.x() - q2.x()) + p2 * (q1.x() - q0.x())) / twice_area;
    weighted += 0.5 * (s.squaredNorm() + t.squaredNorm()) * 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  return std::sqrt(weighted / area_3d);
}

// Whether every triangle of the layout keeps its orientation (positive signed area).
bool keeps_orientation(const detail::FinishedChart& chart) {
  const Mesh& mesh = chart.mesh.mesh;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector2d q0 = chart.layout.uv.row(mesh.faces(f, 0)), q1 = chart.layout.uv.row(mesh.faces(f, 1)),
                          q2 = chart.layout.uv.row(mesh.faces(f, 2));
    if (!((q1 - q0).x() * (q2 - q0).y() - (q1 - q0).y() * (q2 - q0).x() > 0.0)) return false;
  }
  return true;
}

// Each chart's faces, sorted, in the charts' order.
std::vector<std::vector<int>> face_sets(const std::vector<detail::FinishedChart>& charts) {
  std::vector<std::vector<int>> sets;
  for (const detail::FinishedChart& chart : charts) sets.push_back(chart.mesh.surface_face);
  return sets;
}

TEST(StretchBoundedJoin, AFlatSquareCutInQuartersJoinsIntoOneChart) {
  // Four unit squares forming a 2 x 2 square in the plane z = 0.
  std::vector<std::array<Eigen::Vector3d, 4>> quarters;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      quarters.push_back({Eigen::Vector3d(i, j, 0), Eigen::Vector3d(i + 1, j, 0), Eigen::Vector3d(i + 1, j + 1, 0),
                          Eigen::Vector3d(i, j + 1, 0)});
  const Mesh mesh = squares(quarters);
  const detail::FaceGeometry geometry = detail::face_geometry(mesh);
  std::vector<detail::FinishedChart> charts = flattened(mesh, geometry, {{0, 1}, {2, 3}, {4, 5}, {6, 7}});
  ASSERT_TRUE(detail::join_within_stretch(mesh, geometry, kCone, kLimit, SolverOptions{}, 1, charts));
  ASSERT_EQ(charts.size(), 1u);
  EXPECT_EQ(charts[0].mesh.surface_face, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_NEAR(sander_l2(charts[0]), 1.0, kRounding);
  EXPECT_TRUE(keeps_orientation(charts[0]));
}

TEST(StretchBoundedJoin, ACubesSquaresJoinInPairsNeverThreeAroundACorner) {
  const Eigen::Vector3d o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1), xy(1, 1, 0), xz(1, 0, 1), yz(0, 1, 1),
      xyz(1, 1, 1);
  const Mesh mesh = squares({{o, y, xy, x}, {z, xz, xyz, yz}, {o, x, xz, z}, {y, yz, xyz, xy}, {o, z, yz, y},
                             {x, xy, xyz, xz}});
  const detail::FaceGeometry geometry = detail::face_geometry(mesh);
  std::vector<detail::FinishedChart> charts =
      flattened(mesh, geometry, {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {8, 9}, {10, 11}});
  ASSERT_TRUE(detail::join_within_stretch(mesh, geometry, kCone, kLimit, SolverOptions{}, 1, charts));
  // Three charts of two squares each: a third square would close a corner inside the chart, and
  // a band of three squares around the cube turns its normals by 180 degrees, past any cone.
  ASSERT_EQ(charts.size(), 3u);
  for (const detail::FinishedChart& chart : charts) {
    EXPECT_EQ(chart.mesh.surface_face.size(), 4u);
    EXPECT_NEAR(sander_l2(chart), 1.0, kRounding);
    EXPECT_TRUE(keeps_orientation(chart));
  }
}

// A segmentation cone of 30 degrees, half the default, leaves a sphere's charts well within the
// stretch limit (at the default the segmentation's own elimination already leaves about the
// charts a sphere needs): their unions flatten within it.
TEST(StretchBoundedJoin, ASpheresChartsJoinIntoFewerDisksWithinTheLimit) {
  const Mesh sphere = unit_sphere(3);  // 1,280 faces
  const detail::FaceGeometry geometry = detail::face_geometry(sphere);
  detail::SegmentationOptions options;
  options.max_normal_deviation = M_PI / 6.0;
  const detail::Segmentation segmentation = detail::segment_into_charts(geometry, options);
  std::vector<std::vector<int>> sets(static_cast<std::size_t>(segmentation.chart_count));
  for (int f = 0; f < geometry.face_count(); ++f) sets[static_cast<std::size_t>(segmentation.chart_of_face[static_cast<std::size_t>(f)])].push_back(f);
  const std::vector<detail::FinishedChart> segmented = flattened_or_halved(sphere, geometry, sets);

  std::vector<detail::FinishedChart> one_thread = segmented, two_threads = segmented;
  ASSERT_TRUE(detail::join_within_stretch(sphere, geometry, detail::joining_cone(options), kLimit, SolverOptions{}, 1,
                                          one_thread));
  ASSERT_TRUE(detail::join_within_stretch(sphere, geometry, detail::joining_cone(options), kLimit, SolverOptions{}, 2,
                                          two_threads));
  EXPECT_LT(one_thread.size(), segmented.size());
  EXPECT_EQ(face_sets(one_thread), face_sets(two_threads));

  std::vector<int> times_laid(static_cast<std::size_t>(sphere.faces.rows()), 0);
  for (const detail::FinishedChart& chart : one_thread) {
    EXPECT_TRUE(detail::is_disk(chart.mesh));
    EXPECT_TRUE(keeps_orientation(chart));
    EXPECT_LE(sander_l2(chart), kLimit + kRounding);
    for (const int f : chart.mesh.surface_face) ++times_laid[static_cast<std::size_t>(f)];
  }
  EXPECT_EQ(std::count(times_laid.begin(), times_laid.end(), 1), sphere.faces.rows());
}

TEST(StretchBoundedJoin, AProgressCallbackStopsIt) {
  const Mesh sphere = unit_sphere(2);
  const detail::FaceGeometry geometry = detail::face_geometry(sphere);
  const detail::Segmentation segmentation = detail::segment_into_charts(geometry, detail::SegmentationOptions{});
  std::vector<std::vector<int>> sets(static_cast<std::size_t>(segmentation.chart_count));
  for (int f = 0; f < geometry.face_count(); ++f) sets[static_cast<std::size_t>(segmentation.chart_of_face[static_cast<std::size_t>(f)])].push_back(f);
  std::vector<detail::FinishedChart> charts = flattened_or_halved(sphere, geometry, sets);
  const std::size_t before = charts.size();
  SolverOptions stopping;
  int asked = 0;
  stopping.progress = [&asked](const Progress& progress) {
    ++asked;
    return progress.stage != "joining";
  };
  EXPECT_FALSE(detail::join_within_stretch(sphere, geometry, kCone, kLimit, stopping, 1, charts));
  EXPECT_EQ(asked, 1);
  EXPECT_EQ(charts.size(), before);
}

}  // namespace
}  // namespace harmonia
