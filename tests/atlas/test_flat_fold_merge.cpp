// Joining charts across folds that unfold without stretch (atlas/flat_fold_merge.h), on hand-made
// surfaces whose answer is known: two squares hinged at a right angle unfold exactly and join;
// the third square at a cube's corner, which would bring the corner's 90 degrees of curvature
// inside, joins the other two only along one edge, with the other cut, and only where the union
// is compact (three sides of a long box around a corner, not three squares in an L) and both
// charts are developable (a side with a tent in it stays apart); two halves of a pyramid join
// along one edge from the apex, cut along the other, so that the apex stays on the boundary (a
// flat fan's halves join along all of their border); the two halves of a flat ring, which meet
// along two separate edges, do not join (their union is an annulus); a strip folded back on
// itself (normals more than the cone apart) does not; a single face hinged by one edge does,
// folded back or not.
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "atlas/chart_mesh.h"
#include "atlas/chart_segmentation.h"
#include "atlas/face_geometry.h"
#include "atlas/flat_fold_merge.h"
#include "harmonia/mesh.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

using testing::squares;
using testing::tented_squares;

constexpr double kCone = 89.0 * std::numbers::pi / 180.0;

// One chart per square (`faces_per_square` faces each, consecutive), seeded at its first face.
detail::Segmentation chart_per_square(const Mesh& mesh, int faces_per_square = 2) {
  detail::Segmentation segmentation;
  segmentation.chart_count = static_cast<int>(mesh.faces.rows() / faces_per_square);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    segmentation.chart_of_face.push_back(static_cast<int>(f / faces_per_square));
  for (int c = 0; c < segmentation.chart_count; ++c) segmentation.seed_of_chart.push_back(faces_per_square * c);
  return segmentation;
}

// The edges of `mesh` that the merge cut: shared by two faces but with no face across.
int cut_edges(const Mesh& mesh, const detail::FaceGeometry& before, const detail::FaceGeometry& after) {
  int half_edges = 0;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (std::size_t k = 0; k < 3; ++k)
      if (before.across[static_cast<std::size_t>(f)][k] >= 0 && after.across[static_cast<std::size_t>(f)][k] < 0) ++half_edges;
  return half_edges / 2;
}

const Eigen::Vector3d kO(0, 0, 0), kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1), kXy(1, 1, 0), kXz(1, 0, 1), kYz(0, 1, 1);

TEST(FlatFoldMerge, TwoSquaresHingedAtARightAngleJoin) {
  // The floor z = 0 and the wall y = 0 share the edge from the origin to x.
  const Mesh mesh = squares({{kO, kY, kXy, kX}, {kO, kX, kXz, kZ}});
  detail::Segmentation segmentation = chart_per_square(mesh);
  { detail::FaceGeometry geometry = detail::face_geometry(mesh); detail::merge_across_flat_folds(mesh, geometry, kCone, segmentation); }
  EXPECT_EQ(segmentation.chart_count, 1);
  EXPECT_EQ(segmentation.chart_of_face, std::vector<int>(4, 0));
  EXPECT_EQ(segmentation.seed_of_chart.size(), 1u);
}

TEST(FlatFoldMerge, TheThirdSquareAtACubeCornerStaysApart) {
  // The three squares of a cube around the origin: any two unfold (their common vertex at the
  // origin stays on the boundary), all three would hold the corner, a cone of 90 degrees. Joined
  // along one edge with the other cut, they would make an L of three squares, which packs worse
  // than a pair and a square.
  const Mesh mesh = squares({{kO, kY, kXy, kX}, {kO, kX, kXz, kZ}, {kO, kZ, kYz, kY}});
  detail::Segmentation segmentation = chart_per_square(mesh);
  { detail::FaceGeometry geometry = detail::face_geometry(mesh); detail::merge_across_flat_folds(mesh, geometry, kCone, segmentation); }
  EXPECT_EQ(segmentation.chart_count, 2);
}

TEST(FlatFoldMerge, HalvesOfAPyramidJoinWithTheApexOnTheBoundary) {
  // Four triangles around an apex (its angles sum to less than 2 pi): two charts of two faces,
  // whose common border runs through the apex, which joining along all of it would make interior.
  // They join along one of its two edges and the other is cut: a fan with a slit, apex on the
  // boundary, a disk.
  Mesh mesh;
  mesh.vertices.resize(5, 3);
  mesh.vertices << 0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0;
  mesh.faces.resize(4, 3);
  mesh.faces << 0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1;
  detail::Segmentation segmentation = chart_per_square(mesh);
  const detail::FaceGeometry before = detail::face_geometry(mesh);
  detail::FaceGeometry geometry = before;
  detail::merge_across_flat_folds(mesh, geometry, kCone, segmentation);
  EXPECT_EQ(segmentation.chart_count, 1);
  EXPECT_EQ(cut_edges(mesh, before, geometry), 1);
  const detail::ChartMesh chart = detail::chart_mesh(mesh, geometry, {0, 1, 2, 3});
  EXPECT_TRUE(detail::is_disk(chart));
  EXPECT_EQ(chart.mesh.vertices.rows(), 6);  // the apex's and the cut's far end's copies
  // The same with the apex lowered into the plane (a flat fan): the union is a flat disk, joined
  // along all of the border, nothing cut.
  mesh.vertices(0, 2) = 0.0;
  segmentation = chart_per_square(mesh);
  const detail::FaceGeometry flat_before = detail::face_geometry(mesh);
  geometry = flat_before;
  detail::merge_across_flat_folds(mesh, geometry, kCone, segmentation);
  EXPECT_EQ(segmentation.chart_count, 1);
  EXPECT_EQ(cut_edges(mesh, flat_before, geometry), 0);
}

TEST(FlatFoldMerge, ThreeSidesOfALongBoxAroundACornerJoinWithOneCut) {
  // The bottom (1 x 3.5), a long side (3.5 x 0.3) and an end (1 x 0.3) of a box around the
  // origin. The bottom and the long side join along their long edge; the end borders both, and
  // joins along its edge with the bottom, the edge it shares with the long side cut: the corner
  // stays on the boundary, the union is a disk that unfolds exactly, about as compact as its
  // parts. The same sides with a tent in the bottom (curvature inside it) do not join the end.
  const double length = 3.5, height = 0.3;
  const Eigen::Vector3d y = length * kY, z = height * kZ;
  const std::vector<std::array<Eigen::Vector3d, 4>> sides = {
      {kO, y, y + kX, kX}, {kO, z, y + z, y}, {kO, kX, kX + z, z}};
  for (const double tent : {0.0, 0.1}) {
    const Mesh mesh = tented_squares(sides, {tent, 0.0, 0.0});
    detail::Segmentation segmentation = chart_per_square(mesh, 4);
    const detail::FaceGeometry before = detail::face_geometry(mesh);
    detail::FaceGeometry geometry = before;
    detail::merge_across_flat_folds(mesh, geometry, kCone, segmentation);
    if (tent == 0.0) {
      EXPECT_EQ(segmentation.chart_count, 1);
      EXPECT_EQ(cut_edges(mesh, before, geometry), 1);
      // The cut is the end's edge with the long side, from the origin up: both its faces are
      // left with nothing across it.
      const detail::ChartMesh chart = detail::chart_mesh(mesh, geometry, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
      EXPECT_TRUE(detail::is_disk(chart));
      for (int f = 0; f < 12; ++f)
        for (std::size_t k = 0; k < 3; ++k) {
          if (before.across[static_cast<std::size_t>(f)][k] < 0 || geometry.across[static_cast<std::size_t>(f)][k] >= 0) continue;
          const Eigen::Vector3d from = mesh.vertices.row(mesh.faces(f, static_cast<Eigen::Index>(k)));
          const Eigen::Vector3d to = mesh.vertices.row(mesh.faces(f, static_cast<Eigen::Index>((k + 1) % 3)));
          EXPECT_NEAR(std::min((from - kO).norm() + (to - z).norm(), (from - z).norm() + (to - kO).norm()), 0.0, 1e-12);
        }
    } else {
      EXPECT_EQ(segmentation.chart_count, 2);
      EXPECT_EQ(cut_edges(mesh, before, geometry), 0);
    }
  }
}

TEST(FlatFoldMerge, HalvesOfAnAnnulusMeetingAlongTwoEdgesStayApart) {
  // A flat ring: the 3 x 3 unit squares of the plane z = 0 but the centre one, halved into the
  // left column with the top middle square and the bottom middle with the right column. The
  // halves are flat and meet along two separate edges: joined, they would make an annulus.
  std::vector<std::array<Eigen::Vector3d, 4>> ring;
  std::vector<int> half;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (i == 1 && j == 1) continue;
      const Eigen::Vector3d corner(i, j, 0);
      ring.push_back({corner, corner + kX, corner + kXy, corner + kY});
      half.push_back(i == 0 || (i == 1 && j == 2) ? 0 : 1);
    }
  const Mesh mesh = squares(ring);
  detail::Segmentation segmentation;
  segmentation.chart_count = 2;
  for (const int h : half) segmentation.chart_of_face.insert(segmentation.chart_of_face.end(), {h, h});
  segmentation.seed_of_chart = {0, 6};
  ASSERT_EQ(segmentation.chart_of_face[6], 1);
  { detail::FaceGeometry geometry = detail::face_geometry(mesh); detail::merge_across_flat_folds(mesh, geometry, kCone, segmentation); }
  EXPECT_EQ(segmentation.chart_count, 2);
}

TEST(FlatFoldMerge, ASingleFaceHingedByOneEdgeJoinsAtAnyAngle) {
  // A square (two faces) and a triangle on its edge from the origin to x, folded back over the
  // square (174 degrees: its normal nearly opposite the square's, beyond any cone): unfolded
  // about the edge it lies beside the square, with its own lengths.
  Mesh mesh = squares({{kO, kY, kXy, kX}});
  mesh.vertices.conservativeResize(5, 3);
  mesh.vertices.row(4) << 0.5, 0.5, -0.05;
  const int origin = 0, x_corner = 3;
  ASSERT_EQ(Eigen::Vector3d(mesh.vertices.row(x_corner)), kX);
  mesh.faces.conservativeResize(3, 3);
  mesh.faces.row(2) << origin, x_corner, 4;
  detail::Segmentation segmentation;
  segmentation.chart_count = 2;
  segmentation.chart_of_face = {0, 0, 1};
  segmentation.seed_of_chart = {0, 2};
  detail::FaceGeometry geometry = detail::face_geometry(mesh);
  ASSERT_LT(geometry.normal[2].dot(geometry.normal[0]), -0.9);
  detail::merge_across_flat_folds(mesh, geometry, kCone, segmentation);
  EXPECT_EQ(segmentation.chart_count, 1);
}

TEST(FlatFoldMerge, AStripFoldedBackOnItselfStaysApart) {
  // Three squares in a U (floor, and two walls facing each other): the walls are 180 degrees
  // apart, beyond any cone around one normal. The floor joins one wall; the other stays.
  const Mesh mesh = squares({{kO, kY, kXy, kX}, {kO, kX, kXz, kZ}, {kY, kYz, Eigen::Vector3d(1, 1, 1), kXy}});
  detail::Segmentation segmentation = chart_per_square(mesh);
  { detail::FaceGeometry geometry = detail::face_geometry(mesh); detail::merge_across_flat_folds(mesh, geometry, kCone, segmentation); }
  EXPECT_EQ(segmentation.chart_count, 2);
}

}  // namespace
}  // namespace harmonia
