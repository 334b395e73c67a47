// Repacking a mesh's own UV charts (harmonia/texture_atlas.h, repack_texture_atlas), on a hand-made
// mesh whose charts and layouts are known: four flat squares and rectangles, one laid out in a
// tiled corner of UV space far outside [0, 1], one mirrored, one cut by a UV seam along its
// diagonal. The charts must be the input's (a seam splits, a shared UV joins), each layout kept
// up to a quarter turn, every chart at one texel density (the layouts here are isometric, so
// every edge's texels per 3D unit equal the atlas' density), the mirrored chart still mirrored
// and the charts apart; bad UV arrays are refused.
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "harmonia/texture_atlas.h"

namespace harmonia {
namespace {

// Rounding of a placement: a turn, a scale and a shift of coordinates of order 1 and 1e3 texels.
constexpr double kRounding = 1e-9;

struct TexturedMesh {
  Mesh mesh;
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv;
};

// Squares and rectangles in the plane z = 0, each two triangles (0 1 2, 0 2 3); `uv` gives each
// corner of each quad, in the quads' corner order.
TexturedMesh textured_quads(const std::vector<std::array<Eigen::Vector2d, 4>>& corners,
                            const std::vector<std::array<Eigen::Vector2d, 4>>& uv) {
  TexturedMesh textured;
  textured.mesh.vertices.resize(static_cast<Eigen::Index>(4 * corners.size()), 3);
  textured.mesh.faces.resize(static_cast<Eigen::Index>(2 * corners.size()), 3);
  textured.corner_uv.resize(static_cast<Eigen::Index>(2 * corners.size()), 6);
  for (std::size_t q = 0; q < corners.size(); ++q) {
    const int first = static_cast<int>(4 * q);
    for (int k = 0; k < 4; ++k)
      textured.mesh.vertices.row(first + k) << corners[q][static_cast<std::size_t>(k)].x(), corners[q][static_cast<std::size_t>(k)].y(), 0.0;
    const std::array<std::array<int, 3>, 2> triangles{{{0, 1, 2}, {0, 2, 3}}};
    for (int t = 0; t < 2; ++t) {
      const Eigen::Index face = static_cast<Eigen::Index>(2 * q) + t;
      for (int k = 0; k < 3; ++k) {
        const int corner = triangles[static_cast<std::size_t>(t)][static_cast<std::size_t>(k)];
        textured.mesh.faces(face, k) = first + corner;
        textured.corner_uv(face, 2 * k) = uv[q][static_cast<std::size_t>(corner)].x();
        textured.corner_uv(face, 2 * k + 1) = uv[q][static_cast<std::size_t>(corner)].y();
      }
    }
  }
  return textured;
}

TEST(Repack, KeepsEveryChartAsItIsAtOneDensity) {
  using V = Eigen::Vector2d;
  const auto turned = [](const V& p) { return V(Eigen::Rotation2Dd(std::numbers::pi / 6) * p); };
  // A: a unit square, its UVs a square of side 0.5 turned by 30 degrees (a packer free to turn
  // charts would lay it along the axes; a repack keeps it). B: a 1 x 2 rectangle laid out in a tile far
  // from [0, 1]. C: a unit square laid out mirrored (clockwise). D: a unit square whose two
  // triangles are two charts (the diagonal is a seam: its ends have other UVs in the second).
  TexturedMesh textured = textured_quads(
      {{V(0, 0), V(1, 0), V(1, 1), V(0, 1)},
       {V(2, 0), V(3, 0), V(3, 2), V(2, 2)},
       {V(4, 0), V(5, 0), V(5, 1), V(4, 1)},
       {V(6, 0), V(7, 0), V(7, 1), V(6, 1)}},
      {{V(0, 0), turned(V(0.5, 0)), turned(V(0.5, 0.5)), turned(V(0, 0.5))},
       {V(3, 3), V(3.25, 3), V(3.25, 3.5), V(3, 3.5)},
       {V(0.9, 0.6), V(0.6, 0.6), V(0.6, 0.9), V(0.9, 0.9)},
       {V(0, 0), V(0.2, 0), V(0.2, 0.2), V(0, 0.2)}});
  // D's second triangle (0 2 3) takes its own copy of the diagonal's UVs, shifted.
  textured.corner_uv.row(7) << 0.5, 0.5, 0.7, 0.7, 0.5, 0.7;

  TextureAtlasOptions options;
  options.resolution = 256;
  const TextureAtlas atlas = repack_texture_atlas(textured.mesh, textured.corner_uv, options);
  ASSERT_TRUE(atlas.report.ok()) << atlas.report.message;
  ASSERT_EQ(atlas.charts.size(), 5u);
  EXPECT_EQ(atlas.chart_of_face[0], atlas.chart_of_face[1]);
  EXPECT_EQ(atlas.chart_of_face[2], atlas.chart_of_face[3]);
  EXPECT_EQ(atlas.chart_of_face[4], atlas.chart_of_face[5]);
  EXPECT_NE(atlas.chart_of_face[6], atlas.chart_of_face[7]);
  for (const AtlasChart& chart : atlas.charts) EXPECT_EQ(chart.method, ChartMethod::input_layout);

  const double density = atlas.metrics.texels_per_unit;
  ASSERT_GT(density, 0.0);
  for (Eigen::Index f = 0; f < textured.mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int next = (k + 1) % 3;
      const Eigen::Vector3d edge = textured.mesh.vertices.row(textured.mesh.faces(f, next)) -
                                   textured.mesh.vertices.row(textured.mesh.faces(f, k));
      const Eigen::Vector2d placed(atlas.corner_uv(f, 2 * next) - atlas.corner_uv(f, 2 * k),
                                   atlas.corner_uv(f, 2 * next + 1) - atlas.corner_uv(f, 2 * k + 1));
      const Eigen::Vector2d given(textured.corner_uv(f, 2 * next) - textured.corner_uv(f, 2 * k),
                                  textured.corner_uv(f, 2 * next + 1) - textured.corner_uv(f, 2 * k + 1));
      // One density: every edge as many texels long as its 3D length asks.
      EXPECT_NEAR(placed.norm() * options.resolution, density * edge.norm(), kRounding * density)
          << "face " << f << " edge " << k;
      // A quarter turn at most: the placed edge along the given one or across it.
      const double along = std::abs(placed.normalized().dot(given.normalized()));
      EXPECT_TRUE(std::abs(along - 1.0) < kRounding || along < kRounding) << "face " << f << " edge " << k;
    }
  }
  // Corners that share a UV in the input share one in the atlas.
  EXPECT_EQ(atlas.corner_uv(0, 0), atlas.corner_uv(1, 0));
  EXPECT_EQ(atlas.corner_uv(0, 5), atlas.corner_uv(1, 3));
  EXPECT_EQ(atlas.metrics.mirrored_charts, 1);  // C, as it came
  EXPECT_EQ(atlas.metrics.overlapping_texels, 0);
  EXPECT_EQ(atlas.metrics.dropped_faces, 0);
  EXPECT_GE(atlas.corner_uv.minCoeff(), 0.0);
  EXPECT_LE(atlas.corner_uv.maxCoeff(), 1.0);
}

TEST(Repack, RefusesUvsOfTheWrongSizeOrNotFinite) {
  using V = Eigen::Vector2d;
  TexturedMesh textured = textured_quads({{V(0, 0), V(1, 0), V(1, 1), V(0, 1)}},
                                         {{V(0, 0), V(1, 0), V(1, 1), V(0, 1)}});
  const Eigen::Matrix<double, Eigen::Dynamic, 6> one_row = textured.corner_uv.topRows(1);
  const TextureAtlas short_uv = repack_texture_atlas(textured.mesh, one_row);
  EXPECT_EQ(short_uv.report.status, Status::invalid_input);
  EXPECT_NE(short_uv.report.message.find("1 rows for 2 faces"), std::string::npos) << short_uv.report.message;
  textured.corner_uv(1, 3) = std::nan("");
  const TextureAtlas not_finite = repack_texture_atlas(textured.mesh, textured.corner_uv);
  EXPECT_EQ(not_finite.report.status, Status::invalid_input);
  EXPECT_NE(not_finite.report.message.find("face 1"), std::string::npos) << not_finite.report.message;
}

}  // namespace
}  // namespace harmonia
