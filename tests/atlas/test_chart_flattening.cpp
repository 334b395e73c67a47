// A chart whose linear ABF layout crosses its own boundary (atlas/chart_flattening.h): a ribbon
// that winds 400 degrees around an axis, climbing slowly, flattens to an annulus sector that laps
// over itself. flatten_chart reports the crossing (a valid layout otherwise, and a pair of chart
// faces on boundary edges that cross); split_between puts those faces in different halves; the
// texture atlas cuts the ribbon there (and a piece that still laps over itself again), and every
// chart it returns is valid and within the limit.
#include <algorithm>
#include <map>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "atlas/chart_flattening.h"
#include "atlas/chart_mesh.h"
#include "atlas/face_geometry.h"
#include "harmonia/linear_abf.h"
#include "harmonia/metrics.h"
#include "harmonia/procedural.h"
#include "harmonia/texture_atlas.h"
#include "planar/boundary_crossings.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

// `steps` quads around (split in two triangles each) times `rings` across, radii 1 to 2, turning
// by `degrees` in all and rising by `rise` per radian: faces counter-clockwise seen from above.
Mesh winding_ribbon(int steps, int rings, double degrees, double rise) {
  Mesh mesh;
  mesh.vertices.resize((steps + 1) * (rings + 1), 3);
  for (int i = 0; i <= steps; ++i)
    for (int j = 0; j <= rings; ++j) {
      const double angle = degrees * std::numbers::pi / 180.0 * i / steps;
      const double radius = 1.0 + static_cast<double>(j) / rings;
      mesh.vertices.row(i * (rings + 1) + j) << radius * std::cos(angle), radius * std::sin(angle), rise * angle;
    }
  mesh.faces.resize(2 * steps * rings, 3);
  for (int i = 0; i < steps; ++i)
    for (int j = 0; j < rings; ++j) {
      const int a = i * (rings + 1) + j, b = a + 1, c = a + rings + 2, d = a + rings + 1;
      // a inner, b outer at angle i; d inner, c outer at angle i + 1.
      mesh.faces.row(2 * (i * rings + j)) << a, d, c;
      mesh.faces.row(2 * (i * rings + j) + 1) << a, c, b;
    }
  return mesh;
}

std::vector<int> all_faces(const Mesh& mesh) {
  std::vector<int> faces(static_cast<std::size_t>(mesh.faces.rows()));
  for (std::size_t f = 0; f < faces.size(); ++f) faces[f] = static_cast<int>(f);
  return faces;
}

TEST(ChartFlattening, BoundaryThatCrossesItselfIsReportedForACut) {
  const Mesh ribbon = winding_ribbon(80, 4, 400.0, 0.02);
  const detail::FaceGeometry geometry = detail::face_geometry(ribbon);
  const detail::ChartMesh chart = detail::chart_mesh(ribbon, geometry, all_faces(ribbon));
  ASSERT_TRUE(detail::is_disk(chart));
  SolverOptions solver;
  solver.backend = BackendChoice::cpu;
  const detail::ChartFlattening flattening = detail::flatten_chart(chart, 1.006, solver);
  EXPECT_FALSE(flattening.chart);
  ASSERT_TRUE(flattening.crossing);
  const detail::CrossingLayout& crossing = *flattening.crossing;
  ASSERT_EQ(crossing.uv.rows(), chart.mesh.vertices.rows());
  // Valid but for the boundary: no flipped or zero-area triangle, and the boundary crosses.
  const FlipCount flips = count_flips(crossing.uv, chart.mesh.faces);
  EXPECT_EQ(flips.flipped, 0);
  EXPECT_EQ(flips.zero_area, 0);
  EXPECT_GT(count_boundary_self_intersections(crossing.uv, chart.mesh.faces), 0);
  // The two faces hold boundary edges that cross: the first crossing of the layout, face by face.
  ASSERT_NE(crossing.faces[0], crossing.faces[1]);
  const std::optional<detail::BoundaryCrossing> first = detail::first_boundary_crossing(crossing.uv, chart.mesh.faces);
  ASSERT_TRUE(first);
  const auto has_edge = [&](int face, const std::array<int, 2>& edge) {
    int found = 0;
    for (int k = 0; k < 3; ++k) found += chart.mesh.faces(face, k) == edge[0] || chart.mesh.faces(face, k) == edge[1];
    return found == 2;
  };
  EXPECT_TRUE(has_edge(crossing.faces[0], first->first));
  EXPECT_TRUE(has_edge(crossing.faces[1], first->second));

  // Cut between them, the faces of the crossing edges end up apart.
  const int first_face = chart.surface_face[static_cast<std::size_t>(crossing.faces[0])];
  const int second_face = chart.surface_face[static_cast<std::size_t>(crossing.faces[1])];
  const std::vector<std::vector<int>> halves =
      detail::split_between(geometry, all_faces(ribbon), first_face, second_face);
  ASSERT_EQ(halves.size(), 2U);
  EXPECT_EQ(halves[0].size() + halves[1].size(), static_cast<std::size_t>(ribbon.faces.rows()));
  EXPECT_NE(std::find(halves[0].begin(), halves[0].end(), first_face), halves[0].end());
  EXPECT_NE(std::find(halves[1].begin(), halves[1].end(), second_face), halves[1].end());
}

TEST(ChartFlattening, NoCrossingInALayoutThatDoesNotLapOver) {
  const Mesh ribbon = winding_ribbon(40, 4, 200.0, 0.02);
  const detail::FaceGeometry geometry = detail::face_geometry(ribbon);
  const detail::ChartMesh chart = detail::chart_mesh(ribbon, geometry, all_faces(ribbon));
  SolverOptions solver;
  solver.backend = BackendChoice::cpu;
  const detail::ChartFlattening flattening = detail::flatten_chart(chart, 1.006, solver);
  ASSERT_TRUE(flattening.chart);
  EXPECT_FALSE(flattening.crossing);
  EXPECT_FALSE(detail::first_boundary_crossing(flattening.chart->uv, chart.mesh.faces));
}

TEST(ChartFlattening, AtlasOfARibbonThatLapsOverItselfIsCutIntoValidCharts) {
  const Mesh ribbon = winding_ribbon(80, 4, 400.0, 0.02);
  TextureAtlasOptions options;
  options.resolution = 512;
  options.solver.backend = BackendChoice::cpu;
  const TextureAtlas atlas = texture_atlas(ribbon, options);
  ASSERT_TRUE(atlas.report.ok()) << atlas.report.message;
  // One chart cannot hold it without lapping over: cut, each piece within the limit, and pieces
  // keep their part of the first layout (the cut ran, rather than splits solved anew).
  EXPECT_GE(atlas.charts.size(), 2U);
  EXPECT_GE(std::count_if(atlas.charts.begin(), atlas.charts.end(),
                          [](const AtlasChart& chart) { return chart.piece_of_a_cut; }),
            1);
  for (const AtlasChart& chart : atlas.charts) EXPECT_LE(chart.l2_stretch, options.max_distortion);
  EXPECT_EQ(atlas.metrics.boundary_crossings, 0);
  EXPECT_EQ(atlas.metrics.overlapping_texels, 0);
  EXPECT_EQ(atlas.metrics.flipped_triangles, 0);
  EXPECT_EQ(atlas.metrics.dropped_faces, 0);
  EXPECT_EQ(atlas.metrics.mirrored_charts, 0);
}

// A flat ring of long thin triangles, as the planar faces of CAD parts around a bore are (box.STL
// of ../shared/data/wild: 26 segments, 52 faces): `segments` quads around between radii 1 and
// 1 + width, each split in two, counter-clockwise seen from +z.
Mesh flat_ring(int segments, double width) {
  Mesh mesh;
  mesh.vertices.resize(2 * segments, 3);
  for (int i = 0; i < segments; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / segments;
    mesh.vertices.row(2 * i) << std::cos(angle), std::sin(angle), 0.0;
    mesh.vertices.row(2 * i + 1) << (1.0 + width) * std::cos(angle), (1.0 + width) * std::sin(angle), 0.0;
  }
  mesh.faces.resize(2 * segments, 3);
  for (int i = 0; i < segments; ++i) {
    const int a = 2 * i, b = a + 1, c = 2 * ((i + 1) % segments) + 1, d = 2 * ((i + 1) % segments);
    mesh.faces.row(2 * i) << a, b, c;
    mesh.faces.row(2 * i + 1) << a, c, d;
  }
  return mesh;
}

// The distance between the segments [p1, p2] and [q1, q2] of a layout that do not cross (as
// every boundary pair of a valid layout): the least distance from an endpoint to the other one.
double segment_gap(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, const Eigen::Vector2d& q1,
                   const Eigen::Vector2d& q2) {
  const auto to_segment = [](const Eigen::Vector2d& x, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return (x - a - t * (b - a)).norm();
  };
  return std::min({to_segment(p1, q1, q2), to_segment(p2, q1, q2), to_segment(q1, p1, p2), to_segment(q2, p1, p2)});
}

// The ring cut open into a disk has a slit whose two sides the isometric layout puts on top of each
// other, apart or crossing by rounding only; placed in the atlas (scaled and shifted, rounded)
// they crossed (4 crossings on box.STL). The flattening must not hand such a layout on: it is cut
// like a crossing one, or every two boundary edges that share no corner keep clear of each other.
TEST(ChartFlattening, AFlatRingCutOpenIsNotLaidOutWithItsSlitClosed) {
  const Mesh ring = flat_ring(26, 0.04);
  const detail::FaceGeometry geometry = detail::face_geometry(ring);
  const detail::ChartMesh chart = detail::opened_chart(ring, geometry, all_faces(ring));
  ASSERT_TRUE(detail::is_disk(chart));
  SolverOptions solver;
  solver.backend = BackendChoice::cpu;
  const detail::ChartFlattening flattening = detail::flatten_chart(chart, 1.006, solver);
  ASSERT_TRUE(flattening.chart || flattening.crossing);
  if (flattening.chart) {
    const Eigen::MatrixX2d& uv = flattening.chart->uv;
    std::map<std::pair<int, int>, int> uses;
    for (Eigen::Index f = 0; f < chart.mesh.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = chart.mesh.faces(f, k), b = chart.mesh.faces(f, (k + 1) % 3);
        ++uses[{std::min(a, b), std::max(a, b)}];
      }
    std::vector<std::pair<int, int>> boundary;
    for (const auto& [edge, count] : uses)
      if (count == 1) boundary.push_back(edge);
    const double diameter = (uv.colwise().maxCoeff() - uv.colwise().minCoeff()).norm();
    for (std::size_t i = 0; i < boundary.size(); ++i)
      for (std::size_t j = i + 1; j < boundary.size(); ++j) {
        const auto [a, b] = boundary[i];
        const auto [c, d] = boundary[j];
        if (a == c || a == d || b == c || b == d) continue;
        EXPECT_GT(segment_gap(uv.row(a), uv.row(b), uv.row(c), uv.row(d)), 1e-9 * diameter)
            << "boundary edges " << a << "-" << b << " and " << c << "-" << d;
      }
  }
  // The atlas of the ring: valid, its slit cut apart, the pieces keeping their layout.
  TextureAtlasOptions options;
  options.solver.backend = BackendChoice::cpu;
  const TextureAtlas atlas = texture_atlas(ring, options);
  ASSERT_TRUE(atlas.report.ok()) << atlas.report.message;
  EXPECT_GE(atlas.charts.size(), 2U);
  EXPECT_TRUE(std::any_of(atlas.charts.begin(), atlas.charts.end(),
                          [](const AtlasChart& chart) { return chart.piece_of_a_cut; }));
  EXPECT_EQ(atlas.metrics.boundary_crossings, 0);
  EXPECT_EQ(atlas.metrics.overlapping_texels, 0);
  EXPECT_EQ(atlas.metrics.flipped_triangles, 0);
}

TEST(ChartFlattening, RibbonThatLapsTwiceIsCutUntilNoPieceLaps) {
  // 800 degrees: a piece of the first cut may still lap over itself, and is cut again.
  const Mesh ribbon = winding_ribbon(160, 4, 800.0, 0.02);
  TextureAtlasOptions options;
  options.resolution = 512;
  options.solver.backend = BackendChoice::cpu;
  const TextureAtlas atlas = texture_atlas(ribbon, options);
  ASSERT_TRUE(atlas.report.ok()) << atlas.report.message;
  EXPECT_GE(atlas.charts.size(), 3U);
  EXPECT_GE(std::count_if(atlas.charts.begin(), atlas.charts.end(),
                          [](const AtlasChart& chart) { return chart.piece_of_a_cut; }),
            2);
  for (const AtlasChart& chart : atlas.charts) EXPECT_LE(chart.l2_stretch, options.max_distortion);
  EXPECT_EQ(atlas.metrics.boundary_crossings, 0);
  EXPECT_EQ(atlas.metrics.overlapping_texels, 0);
  EXPECT_EQ(atlas.metrics.flipped_triangles, 0);
}

// A flat annulus (radii 1 and 2) turned into a tilted plane is one chart with a hole: laid out as
// it lies, every edge keeps its 3D length (to the rounding of a projection, 1e-12 of the
// chart), every face stays counter-clockwise, and the stretch is 1. Bent into a bowl (z = 0.3 r^2)
// it is not planar, and the projection is refused (the chart is cut open and flattened instead).
// A curved chart's linear ABF layout (conformal: its scale varies over the chart) is relaxed toward
// an isometry, which stretches it less; a planar chart, laid out isometrically already, is kept.
TEST(ChartFlattening, ACurvedChartIsRelaxedBelowLinearAbfsStretchAndAPlanarOneIsKept) {
  SolverOptions solver;
  solver.backend = BackendChoice::cpu;
  const Mesh cap = hemisphere(6);
  const detail::FaceGeometry geometry = detail::face_geometry(cap);
  const detail::ChartMesh chart = detail::chart_mesh(cap, geometry, all_faces(cap));
  const AngleMapResult conformal = linear_abf(chart.mesh, detail::chart_linear_abf_options(solver));
  ASSERT_TRUE(conformal.report.ok()) << conformal.report.message;
  const double conformal_stretch = evaluate_map(chart.mesh, conformal.uv, chart.mesh.faces).l2_stretch;
  const detail::ChartFlattening flattening = detail::flatten_chart(chart, 1.5, solver);
  ASSERT_TRUE(flattening.chart);
  EXPECT_EQ(flattening.chart->method, ChartMethod::relaxed_linear_abf);
  const Eigen::MatrixX2d& uv = flattening.chart->uv;
  const FlipCount flips = count_flips(uv, chart.mesh.faces);
  EXPECT_EQ(flips.flipped + flips.zero_area, 0);
  EXPECT_FALSE(detail::first_boundary_crossing(uv, chart.mesh.faces));
  const double relaxed_stretch = evaluate_map(chart.mesh, uv, chart.mesh.faces).l2_stretch;
  EXPECT_NEAR(flattening.chart->l2_stretch, relaxed_stretch, 1e-12);
  EXPECT_LT(relaxed_stretch - 1.0, 0.8 * (conformal_stretch - 1.0));

  const Mesh disk = planar_disk(8, 0.2);
  const detail::FaceGeometry disk_geometry = detail::face_geometry(disk);
  const detail::ChartMesh disk_chart = detail::chart_mesh(disk, disk_geometry, all_faces(disk));
  const detail::ChartFlattening flat = detail::flatten_chart(disk_chart, 1.006, solver);
  ASSERT_TRUE(flat.chart);
  EXPECT_EQ(flat.chart->method, ChartMethod::linear_abf);
  EXPECT_NEAR(flat.chart->l2_stretch, 1.0, 1e-12);
}

TEST(ChartFlattening, APlanarChartWithAHoleIsLaidOutAsItLies) {
  Mesh ring = testing::annulus(32, 4);
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  ring.vertices = ring.vertices * tilt.transpose();
  const detail::FaceGeometry geometry = detail::face_geometry(ring);
  const detail::ChartMesh chart = detail::chart_mesh(ring, geometry, all_faces(ring));
  ASSERT_FALSE(detail::is_disk(chart));
  const std::optional<detail::FlattenedChart> layout = detail::projected_layout(chart, 1.006);
  ASSERT_TRUE(layout);
  EXPECT_EQ(layout->method, ChartMethod::projection);
  EXPECT_NEAR(layout->l2_stretch, 1.0, 1e-12);
  const Eigen::MatrixX2d& uv = layout->uv;
  for (Eigen::Index f = 0; f < chart.mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = chart.mesh.faces(f, k), b = chart.mesh.faces(f, (k + 1) % 3);
      const double in_3d = (chart.mesh.vertices.row(a) - chart.mesh.vertices.row(b)).norm();
      EXPECT_NEAR((uv.row(a) - uv.row(b)).norm(), in_3d, 1e-12 * 4.0) << "face " << f;
    }
    const Eigen::Vector2d e1 = uv.row(chart.mesh.faces(f, 1)) - uv.row(chart.mesh.faces(f, 0));
    const Eigen::Vector2d e2 = uv.row(chart.mesh.faces(f, 2)) - uv.row(chart.mesh.faces(f, 0));
    EXPECT_GT(e1.x() * e2.y() - e1.y() * e2.x(), 0.0) << "face " << f;
  }

  Mesh bowl = testing::annulus(32, 4);
  for (Eigen::Index v = 0; v < bowl.vertices.rows(); ++v)
    bowl.vertices(v, 2) = 0.3 * bowl.vertices.row(v).head<2>().squaredNorm();
  const detail::FaceGeometry bowl_geometry = detail::face_geometry(bowl);
  const detail::ChartMesh bowl_chart = detail::chart_mesh(bowl, bowl_geometry, all_faces(bowl));
  EXPECT_FALSE(detail::projected_layout(bowl_chart, 1.006));
}

// A square plate of 4 x 4 unit squares with a 2 x 2 window in the middle, as walls and CAD plates
// come: its atlas is one chart laid out as it lies (cutting the window open would lay the cut's two
// sides on top of each other, and the plate was split into pieces), isometric, and valid.
TEST(ChartFlattening, APlateWithAWindowIsOneChart) {
  std::vector<std::array<Eigen::Vector3d, 4>> plate;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      if ((i == 1 || i == 2) && (j == 1 || j == 2)) continue;
      const Eigen::Vector3d corner(i, j, 0.0);
      plate.push_back({corner, corner + Eigen::Vector3d(1, 0, 0), corner + Eigen::Vector3d(1, 1, 0),
                       corner + Eigen::Vector3d(0, 1, 0)});
    }
  const Mesh mesh = testing::squares(plate);
  TextureAtlasOptions options;
  options.solver.backend = BackendChoice::cpu;
  const TextureAtlas atlas = texture_atlas(mesh, options);
  ASSERT_TRUE(atlas.report.ok()) << atlas.report.message;
  ASSERT_EQ(atlas.charts.size(), 1U);
  EXPECT_EQ(atlas.charts[0].method, ChartMethod::projection);
  EXPECT_NEAR(atlas.metrics.l2_stretch, 1.0, 1e-9);
  EXPECT_EQ(atlas.metrics.boundary_crossings, 0);
  EXPECT_EQ(atlas.metrics.overlapping_texels, 0);
  EXPECT_EQ(atlas.metrics.flipped_triangles, 0);
}

}  // namespace
}  // namespace harmonia
