// The atlas metrics (host/atlas/atlas_metrics.h) on hand-made atlases whose answers are known:
// texel counts from the geometry of rectangles on the texel grid, orientation counts from the
// triangles drawn, boundary crossings counted by hand, distortions in closed form.

#include "atlas/atlas_metrics.h"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "harmonia/types.h"

namespace harmonia {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// Each figure is a handful of roundings per triangle, then a weighted mean: far below this.
constexpr double kTolerance = 64 * std::numeric_limits<double>::epsilon();

struct MeshWithAtlas {
  Mesh mesh;
  TextureAtlas atlas;
};

// Builds a mesh and its atlas face by face; UV corners are given in texels.
class AtlasBuilder {
 public:
  explicit AtlasBuilder(int resolution) : resolution_(resolution) {}

  int vertex(const Vector3d& position) {
    positions_.push_back(position);
    return static_cast<int>(positions_.size()) - 1;
  }

  // A face of `chart` (-1: no chart) over existing vertices, with its corners at `texels`.
  void face(int chart, const std::array<int, 3>& corners, const std::array<Vector2d, 3>& texels) {
    faces_.push_back(corners);
    texels_.push_back(texels);
    charts_.push_back(chart);
  }

  // A quad of `chart`: 3D corners counter-clockwise, split along corner 0 to corner 2.
  void quad(int chart, const std::array<Vector3d, 4>& corners,
            const std::array<Vector2d, 4>& texels) {
    std::array<int, 4> v{};
    for (int k = 0; k < 4; ++k) v[k] = vertex(corners[k]);
    face(chart, {v[0], v[1], v[2]}, {texels[0], texels[1], texels[2]});
    face(chart, {v[0], v[2], v[3]}, {texels[0], texels[2], texels[3]});
  }

  // A quad over an axis-aligned rectangle: 3D corners (x0, y0) .. (x1, y1) in the plane z = 0,
  // drawn on the texel rectangle (tx0, ty0) .. (tx1, ty1).
  void rectangle(int chart, double x0, double y0, double x1, double y1, double tx0, double ty0,
                 double tx1, double ty1) {
    quad(chart,
         {Vector3d(x0, y0, 0), Vector3d(x1, y0, 0), Vector3d(x1, y1, 0), Vector3d(x0, y1, 0)},
         {Vector2d(tx0, ty0), Vector2d(tx1, ty0), Vector2d(tx1, ty1), Vector2d(tx0, ty1)});
  }

  [[nodiscard]] MeshWithAtlas build() const {
    MeshWithAtlas built;
    built.mesh.vertices.resize(static_cast<Eigen::Index>(positions_.size()), 3);
    for (std::size_t v = 0; v < positions_.size(); ++v) {
      built.mesh.vertices.row(static_cast<Eigen::Index>(v)) = positions_[v].transpose();
    }
    const auto face_count = static_cast<Eigen::Index>(faces_.size());
    built.mesh.faces.resize(face_count, 3);
    built.atlas.corner_uv.resize(face_count, 6);
    built.atlas.resolution = resolution_;
    built.atlas.chart_of_face = charts_;
    for (Eigen::Index f = 0; f < face_count; ++f) {
      const auto face = static_cast<std::size_t>(f);
      for (int k = 0; k < 3; ++k) {
        built.mesh.faces(f, k) = faces_[face][k];
        built.atlas.corner_uv(f, 2 * k) = texels_[face][k].x() / resolution_;
        built.atlas.corner_uv(f, 2 * k + 1) = texels_[face][k].y() / resolution_;
      }
      const int chart = charts_[face];
      if (chart < 0) continue;
      if (static_cast<int>(built.atlas.charts.size()) <= chart) {
        built.atlas.charts.resize(static_cast<std::size_t>(chart) + 1);
      }
      built.atlas.charts[static_cast<std::size_t>(chart)].faces.push_back(static_cast<int>(f));
    }
    return built;
  }

 private:
  int resolution_;
  std::vector<Vector3d> positions_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<std::array<Vector2d, 3>> texels_;
  std::vector<int> charts_;
};

AtlasMetrics measure(MeshWithAtlas& built) {
  return detail::measure_atlas(built.mesh, built.atlas);
}

// ------------------------------------------------------------------------------ texels

TEST(AtlasMetrics, TwoChartsOverlapByTheTexelCentresTheyShare) {
  // Two 4 x 3 texel rectangles, the second moved by (2, 1): they share the 2 x 2 texels of
  // [2, 4] x [1, 3]. A 4 x 3 rectangle's diagonal passes through no texel centre (3x - 4y = 0.5
  // has no integer solution), so each covers all 12 of its texel centres.
  AtlasBuilder builder(8);
  builder.rectangle(0, 0, 0, 4, 3, 0, 0, 4, 3);
  builder.rectangle(1, 0, 0, 4, 3, 2, 1, 6, 4);
  MeshWithAtlas built = builder.build();
  const AtlasMetrics metrics = measure(built);
  EXPECT_EQ(metrics.overlapping_texels, 4);
  EXPECT_DOUBLE_EQ(metrics.coverage, (12.0 + 12.0 - 4.0) / 64.0);
  // The rectangles' outlines cross twice: at (2, 3) and at (4, 1).
  EXPECT_EQ(metrics.boundary_crossings, 2);
  EXPECT_EQ(metrics.flipped_triangles, 0);
  EXPECT_EQ(metrics.mirrored_charts, 0);
  EXPECT_EQ(metrics.charts, 2);
  EXPECT_EQ(metrics.faces, 4);
  EXPECT_EQ(metrics.dropped_faces, 0);
}

// The same two rectangles with the second on a page of its own: on two pages nothing overlaps or
// crosses, the coverage is over both pages' texels, and each page has its own.
TEST(AtlasMetrics, ChartsOnTwoPagesShareNoTexel) {
  AtlasBuilder builder(8);
  builder.rectangle(0, 0, 0, 4, 3, 0, 0, 4, 3);
  builder.rectangle(1, 0, 0, 4, 3, 2, 1, 6, 4);
  MeshWithAtlas built = builder.build();
  built.atlas.pages = 2;
  built.atlas.charts[1].page = 1;
  const AtlasMetrics metrics = measure(built);
  EXPECT_EQ(metrics.overlapping_texels, 0);
  EXPECT_EQ(metrics.boundary_crossings, 0);
  EXPECT_DOUBLE_EQ(metrics.coverage, 24.0 / 128.0);
  ASSERT_EQ(metrics.page_coverage.size(), 2u);
  EXPECT_DOUBLE_EQ(metrics.page_coverage[0], 12.0 / 64.0);
  EXPECT_DOUBLE_EQ(metrics.page_coverage[1], 12.0 / 64.0);
  // A chart on a page the atlas does not have is a mismatch.
  built.atlas.charts[1].page = 2;
  EXPECT_NE(detail::atlas_mismatch(built.mesh, built.atlas).find("page 2"), std::string::npos);
}

TEST(AtlasMetrics, ChartsSideBySideTouchButNeitherOverlapNorCross) {
  // Sharing the texel column x = 4 and the positions of their common side: no texel centre lies
  // on it, and touching edges are no proper crossing.
  AtlasBuilder builder(8);
  builder.rectangle(0, 0, 0, 4, 3, 0, 0, 4, 3);
  builder.rectangle(1, 0, 0, 4, 3, 4, 0, 8, 3);
  MeshWithAtlas built = builder.build();
  const AtlasMetrics metrics = measure(built);
  EXPECT_EQ(metrics.overlapping_texels, 0);
  EXPECT_EQ(metrics.boundary_crossings, 0);
  EXPECT_DOUBLE_EQ(metrics.coverage, 24.0 / 64.0);
}

TEST(AtlasMetrics, CoverageCountsTheTexelCentresStrictlyInside) {
  // A 4 x 3 rectangle: 12 texel centres of 64. The unit square's diagonal, from texel corner to
  // texel corner, passes through the centres (k + 1/2, k + 1/2): strictly inside neither triangle.
  AtlasBuilder rectangle(8);
  rectangle.rectangle(0, 0, 0, 4, 3, 1, 2, 5, 5);
  MeshWithAtlas built_rectangle = rectangle.build();
  EXPECT_DOUBLE_EQ(measure(built_rectangle).coverage, 12.0 / 64.0);

  AtlasBuilder square(8);
  square.rectangle(0, 0, 0, 1, 1, 0, 0, 8, 8);
  MeshWithAtlas built_square = square.build();
  EXPECT_DOUBLE_EQ(measure(built_square).coverage, (64.0 - 8.0) / 64.0);
}

TEST(AtlasMetrics, AGridOfSquaresCoversAllButItsDiagonals) {
  // n x n unit squares in 3D drawn isometrically on an R x R atlas, R / n = 8 texels a side:
  // each square's diagonal holds 8 texel centres (see above), the grid lines hold none. A chart
  // of 2 n^2 = 131072 triangles: an isometry (stretch 1) without flips, overlaps or crossings.
  constexpr int kSquares = 256, kResolution = 2048, kTexelsPerSquare = kResolution / kSquares;
  AtlasBuilder builder(kResolution);
  std::vector<int> grid_vertex((kSquares + 1) * (kSquares + 1));
  for (int j = 0; j <= kSquares; ++j) {
    for (int i = 0; i <= kSquares; ++i) {
      grid_vertex[j * (kSquares + 1) + i] = builder.vertex(Vector3d(i, j, 0));
    }
  }
  for (int j = 0; j < kSquares; ++j) {
    for (int i = 0; i < kSquares; ++i) {
      const int v00 = grid_vertex[j * (kSquares + 1) + i], v10 = v00 + 1;
      const int v01 = v00 + kSquares + 1, v11 = v01 + 1;
      const Vector2d t00(i * kTexelsPerSquare, j * kTexelsPerSquare);
      const Vector2d t10 = t00 + Vector2d(kTexelsPerSquare, 0);
      const Vector2d t11 = t00 + Vector2d(kTexelsPerSquare, kTexelsPerSquare);
      const Vector2d t01 = t00 + Vector2d(0, kTexelsPerSquare);
      builder.face(0, {v00, v10, v11}, {t00, t10, t11});
      builder.face(0, {v00, v11, v01}, {t00, t11, t01});
    }
  }
  MeshWithAtlas built = builder.build();
  const AtlasMetrics metrics = measure(built);
  const double uncovered = double(kSquares) * kSquares * kTexelsPerSquare;
  EXPECT_DOUBLE_EQ(metrics.coverage, 1.0 - uncovered / (double(kResolution) * kResolution));
  EXPECT_EQ(metrics.overlapping_texels, 0);
  EXPECT_EQ(metrics.boundary_crossings, 0);
  EXPECT_EQ(metrics.flipped_triangles, 0);
  EXPECT_NEAR(metrics.l2_stretch, 1.0, kTolerance);
  EXPECT_NEAR(metrics.texels_per_unit, kTexelsPerSquare, kTolerance * kTexelsPerSquare);
}

// ------------------------------------------------------------------------------ orientation

TEST(AtlasMetrics, AMirroredChartIsCountedOnceAndItsTrianglesAreNotFlips) {
  AtlasBuilder builder(16);
  // Chart 0: a square drawn mirrored (u reversed), both triangles clockwise.
  builder.rectangle(0, 0, 0, 1, 1, 4, 0, 0, 4);
  // Chart 1: a fan of three triangles around o, the middle one folded over (clockwise).
  const int o = builder.vertex(Vector3d(0, 0, 1));
  const int r0 = builder.vertex(Vector3d(1, 0, 1)), r1 = builder.vertex(Vector3d(0.5, 0.8, 1));
  const int r2 = builder.vertex(Vector3d(-0.5, 0.8, 1)), r3 = builder.vertex(Vector3d(-1, 0, 1));
  const Vector2d to(8, 8), t0(11, 8), t1(8, 11), t2(10, 10), t3(8, 12);
  builder.face(1, {o, r0, r1}, {to, t0, t1});
  builder.face(1, {o, r1, r2}, {to, t1, t2});
  builder.face(1, {o, r2, r3}, {to, t2, t3});
  // Chart 2: a square whose fourth corner is drawn on the diagonal: one triangle of zero area.
  builder.quad(2, {Vector3d(0, 0, 2), Vector3d(1, 0, 2), Vector3d(1, 1, 2), Vector3d(0, 1, 2)},
               {Vector2d(0, 8), Vector2d(2, 8), Vector2d(2, 10), Vector2d(1, 9)});
  MeshWithAtlas built = builder.build();
  const AtlasMetrics metrics = measure(built);
  EXPECT_EQ(metrics.mirrored_charts, 1);
  // Chart 0: no minority; chart 1: the folded triangle; chart 2: the zero-area triangle.
  EXPECT_EQ(metrics.flipped_triangles, 2);
}

// ------------------------------------------------------------------------------ boundaries

TEST(AtlasMetrics, AFanThatWrapsPastAFullTurnCrossesItsOwnBoundary) {
  // Four triangles around o (on the chart's boundary), each turning counter-clockwise, between
  // the rim points at 0, 90, 180, 270 and 405 degrees. The last triangle comes back over the
  // first: the spoke to 0 degrees crosses the rim edge from 270 to 405 degrees, the spoke to 405
  // (45) degrees crosses the rim edge from 0 to 90 degrees, and those two rim edges cross.
  AtlasBuilder builder(64);
  const Vector2d centre(32, 32);
  constexpr double kRadius = 16;
  const double rim_degrees[5] = {0, 90, 180, 270, 405};
  const int o = builder.vertex(Vector3d(0, 0, 0));
  int rim[5];
  Vector2d rim_texel[5];
  for (int k = 0; k < 5; ++k) {
    const double angle = rim_degrees[k] * std::numbers::pi / 180.0;
    // In 3D an open fan of four 60 degree triangles.
    const double angle_3d = k * std::numbers::pi / 3.0;
    rim[k] = builder.vertex(Vector3d(std::cos(angle_3d), std::sin(angle_3d), 0));
    rim_texel[k] = centre + kRadius * Vector2d(std::cos(angle), std::sin(angle));
  }
  for (int k = 0; k < 4; ++k) {
    builder.face(0, {o, rim[k], rim[k + 1]}, {centre, rim_texel[k], rim_texel[k + 1]});
  }
  MeshWithAtlas built = builder.build();
  const AtlasMetrics metrics = measure(built);
  EXPECT_EQ(metrics.boundary_crossings, 3);
  EXPECT_EQ(metrics.overlapping_texels, 0);  // a chart over itself is no overlap between charts
  EXPECT_EQ(metrics.flipped_triangles, 0);
}

// ------------------------------------------------------------------------------ distortion

TEST(AtlasMetrics, IsometricAndStretchedChartsHaveTheirAnalyticDistortion) {
  // Two unit squares in 3D: chart 0 drawn 2 x 2 texels (an isometry up to scale), chart 1 drawn
  // 4 x 2 (twice as wide as tall). Scaled to its own area chart 1's Jacobian is
  // diag(sqrt 2, 1/sqrt 2): sigma1 / sigma2 = 2 and Sander's L2 = sqrt((1/2 + 2) / 2) =
  // sqrt(1.25). Within each chart the area ratio is constant: no area distortion.
  AtlasBuilder builder(8);
  builder.rectangle(0, 0, 0, 1, 1, 0, 0, 2, 2);
  builder.rectangle(1, 0, 0, 1, 1, 3, 0, 7, 2);
  MeshWithAtlas built = builder.build();
  const AtlasMetrics metrics = measure(built);
  const AtlasChart& isometric = built.atlas.charts[0];
  const AtlasChart& stretched = built.atlas.charts[1];
  EXPECT_NEAR(isometric.l2_stretch, 1.0, kTolerance);
  EXPECT_NEAR(isometric.angle_distortion, 1.0, kTolerance);
  EXPECT_NEAR(isometric.area_distortion, 0.0, kTolerance);
  EXPECT_NEAR(isometric.surface_area, 1.0, kTolerance);
  EXPECT_NEAR(stretched.l2_stretch, std::sqrt(1.25), kTolerance);
  EXPECT_NEAR(stretched.angle_distortion, 2.0, kTolerance);
  EXPECT_NEAR(stretched.area_distortion, 0.0, kTolerance);
  EXPECT_NEAR(stretched.surface_area, 1.0, kTolerance);
  // The atlas: equal 3D areas, so plain means; one scale for the area, 3D area 2 over 4 + 8
  // texels^2, under which chart 0's ratio is 4/6 and chart 1's 8/6: mean |log| = (log(3/2) +
  // log(4/3)) / 2 = log(2) / 2. Texel density sqrt(12 / 2).
  EXPECT_NEAR(metrics.l2_stretch, std::sqrt((1.0 + 1.25) / 2.0), kTolerance);
  EXPECT_NEAR(metrics.angle_distortion, 1.5, kTolerance);
  EXPECT_NEAR(metrics.area_distortion, 0.5 * std::log(2.0), kTolerance);
  EXPECT_NEAR(metrics.texels_per_unit, std::sqrt(6.0), kTolerance);
}

TEST(AtlasMetrics, TheFiguresDoNotDependOnTheModelsUnits) {
  // The same atlas over a surface 1e-150 and 1e150 times as large: ratios unchanged, absolute
  // figures (3D area, texel density) scaled, no overflow or underflow on the way.
  for (const double unit : {1e-150, 1e150}) {
    AtlasBuilder builder(8);
    builder.rectangle(0, 0, 0, unit, unit, 3, 0, 7, 2);
    MeshWithAtlas built = builder.build();
    const AtlasMetrics metrics = measure(built);
    EXPECT_NEAR(metrics.l2_stretch, std::sqrt(1.25), kTolerance) << unit;
    EXPECT_NEAR(built.atlas.charts[0].surface_area / (unit * unit), 1.0, kTolerance) << unit;
    EXPECT_NEAR(metrics.texels_per_unit * unit, std::sqrt(8.0), kTolerance * std::sqrt(8.0))
        << unit;
  }
}

TEST(AtlasMetrics, AFaceOfNoChartIsDroppedAndLeftOutOfEverything) {
  AtlasBuilder builder(8);
  builder.rectangle(0, 0, 0, 1, 1, 0, 0, 2, 2);
  // Over chart 0's texels, clockwise, of no chart: neither an overlap nor a flip.
  const int a = builder.vertex(Vector3d(0, 0, 5)), b = builder.vertex(Vector3d(1, 0, 5)),
            c = builder.vertex(Vector3d(0, 1, 5));
  builder.face(-1, {a, b, c}, {Vector2d(0, 0), Vector2d(0, 2), Vector2d(2, 0)});
  MeshWithAtlas built = builder.build();
  const AtlasMetrics metrics = measure(built);
  EXPECT_EQ(metrics.dropped_faces, 1);
  EXPECT_EQ(metrics.faces, 3);
  EXPECT_EQ(metrics.flipped_triangles, 0);
  EXPECT_EQ(metrics.overlapping_texels, 0);
  EXPECT_NEAR(metrics.l2_stretch, 1.0, kTolerance);
}

TEST(AtlasMetrics, AChartOfZeroSurfaceAreaKeepsNeutralDistortion) {
  // A face whose corners are collinear in 3D, drawn as a small valid triangle: counted, not
  // measured (its ratios are unbounded).
  AtlasBuilder builder(8);
  const int a = builder.vertex(Vector3d(0, 0, 0)), b = builder.vertex(Vector3d(1, 0, 0)),
            c = builder.vertex(Vector3d(2, 0, 0));
  builder.face(0, {a, b, c}, {Vector2d(1, 1), Vector2d(2, 1), Vector2d(1, 2)});
  MeshWithAtlas built = builder.build();
  built.atlas.charts[0].l2_stretch = 7.0;  // a stale value is replaced
  const AtlasMetrics metrics = measure(built);
  EXPECT_EQ(metrics.flipped_triangles, 0);
  EXPECT_EQ(built.atlas.charts[0].l2_stretch, 1.0);
  EXPECT_EQ(built.atlas.charts[0].angle_distortion, 1.0);
  EXPECT_EQ(built.atlas.charts[0].area_distortion, 0.0);
  EXPECT_EQ(built.atlas.charts[0].surface_area, 0.0);
  EXPECT_EQ(metrics.l2_stretch, 1.0);
}

// ------------------------------------------------------------------------------ layout, checks

TEST(AtlasMetrics, TheLayoutSharesAUvPerChartVertexAndPosition) {
  AtlasBuilder builder(8);
  builder.rectangle(0, 0, 0, 1, 1, 0, 0, 2, 2);  // 4 vertices, 2 faces sharing 2 of them
  MeshWithAtlas built = builder.build();
  // A second chart reusing the square's first face's vertices elsewhere in the atlas.
  built.mesh.faces.conservativeResize(3, 3);
  built.mesh.faces.row(2) = built.mesh.faces.row(0);
  built.atlas.corner_uv.conservativeResize(3, 6);
  built.atlas.corner_uv.row(2) << 0.5, 0.5, 0.75, 0.5, 0.75, 0.75;
  built.atlas.chart_of_face.push_back(1);
  built.atlas.charts.resize(2);
  built.atlas.charts[1].faces = {2};
  ASSERT_EQ(detail::atlas_mismatch(built.mesh, built.atlas), "");
  const detail::AtlasUvLayout layout = detail::atlas_uv_layout(built.mesh, built.atlas);
  EXPECT_EQ(layout.uv.rows(), 4 + 3);
  EXPECT_EQ(layout.uv_faces(1, 0), layout.uv_faces(0, 0));
  EXPECT_EQ(layout.uv_faces(1, 1), layout.uv_faces(0, 2));
  for (int corner = 0; corner < 3; ++corner) {
    EXPECT_GE(layout.uv_faces(2, corner), 4);  // new UVs for the other chart
    EXPECT_EQ(layout.uv(layout.uv_faces(2, corner), 0), built.atlas.corner_uv(2, 2 * corner));
  }
}

TEST(AtlasMetrics, AnAtlasThatDoesNotFitTheMeshIsRefusedNamingTheProblem) {
  AtlasBuilder builder(8);
  builder.rectangle(0, 0, 0, 1, 1, 0, 0, 2, 2);
  const MeshWithAtlas good = builder.build();
  auto problem_of = [&](auto change) {
    MeshWithAtlas bad = good;
    change(bad);
    return detail::atlas_mismatch(bad.mesh, bad.atlas);
  };
  EXPECT_EQ(problem_of([](MeshWithAtlas&) {}), "");
  EXPECT_NE(problem_of([](MeshWithAtlas& b) { b.atlas.chart_of_face.pop_back(); })
                .find("chart_of_face has 1 entries but the mesh has 2 faces"),
            std::string::npos);
  EXPECT_NE(problem_of([](MeshWithAtlas& b) { b.atlas.corner_uv.conservativeResize(1, 6); })
                .find("corner_uv has 1 rows"),
            std::string::npos);
  EXPECT_NE(problem_of([](MeshWithAtlas& b) { b.atlas.chart_of_face[1] = 3; })
                .find("chart 0 lists face 1, whose chart_of_face is 3"),
            std::string::npos);
  EXPECT_NE(problem_of([](MeshWithAtlas& b) { b.atlas.charts[0].faces = {0}; })
                .find("face 1 is in chart 0, which does not list it"),
            std::string::npos);
  EXPECT_NE(problem_of([](MeshWithAtlas& b) { b.atlas.resolution = 0; }).find("resolution 0"),
            std::string::npos);
  EXPECT_NE(problem_of([](MeshWithAtlas& b) { b.mesh.faces(1, 2) = 9; })
                .find("face 1 refers to vertex 9"),
            std::string::npos);
  MeshWithAtlas bad = good;
  bad.atlas.chart_of_face.pop_back();
  try {
    (void)detail::measure_atlas(bad.mesh, bad.atlas);
    ADD_FAILURE() << "a mismatched atlas was measured";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
  }
}

}  // namespace
}  // namespace harmonia
