// Texture atlases of any mesh (harmonia/texture_atlas.h): a torus (genus 1), two components, a cube
// (its sides joined in pairs), a sphere with holes, the same charts at scales 1e-6 and 1e6 and for any face order;
// every chart a disk, every face in exactly one chart, no flip, no mirrored chart, no two charts
// on one texel (the atlas measured by rasterizing chart ids), all UVs in [0, 1].
#include <algorithm>
#include <cmath>
#include <functional>
#include <tuple>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "harmonia/texture_atlas.h"
#include "support/test_support.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

using testing::grid_cube;

TextureAtlasOptions test_options() {
  TextureAtlasOptions options;
  options.resolution = 512;
  options.solver.backend = BackendChoice::cpu;
  return options;
}

// A torus of radii 1 and `tube`, `around` x `across` quads split into triangles, faces
// counter-clockwise seen from outside.
Mesh torus(int around, int across, double tube) {
  Mesh mesh;
  mesh.vertices.resize(around * across, 3);
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j) {
      const double u = 2.0 * M_PI * i / around, v = 2.0 * M_PI * j / across;
      mesh.vertices.row(i * across + j) << (1.0 + tube * std::cos(v)) * std::cos(u),
          (1.0 + tube * std::cos(v)) * std::sin(u), tube * std::sin(v);
    }
  mesh.faces.resize(2 * around * across, 3);
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j) {
      const int a = i * across + j, b = ((i + 1) % around) * across + j;
      const int c = ((i + 1) % around) * across + (j + 1) % across, d = i * across + (j + 1) % across;
      mesh.faces.row(2 * (i * across + j)) << a, b, c;
      mesh.faces.row(2 * (i * across + j) + 1) << a, c, d;
    }
  return mesh;
}

Mesh without_faces(const Mesh& mesh, const std::function<bool(const Eigen::Vector3d&)>& removed) {
  std::vector<Eigen::Vector3i> kept;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d centroid = (mesh.vertices.row(mesh.faces(f, 0)) + mesh.vertices.row(mesh.faces(f, 1)) +
                                      mesh.vertices.row(mesh.faces(f, 2))) / 3.0;
    if (!removed(centroid)) kept.emplace_back(mesh.faces.row(f));
  }
  Mesh result;
  result.vertices = mesh.vertices;
  result.faces.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t i = 0; i < kept.size(); ++i) result.faces.row(static_cast<Eigen::Index>(i)) = kept[i];
  return result;
}

Mesh two_components() {
  const Mesh sphere = unit_sphere(3);
  Mesh both;
  both.vertices.resize(2 * sphere.vertices.rows(), 3);
  both.vertices << sphere.vertices, (sphere.vertices * 0.5).rowwise() + Eigen::RowVector3d(3.0, 0.0, 0.0);
  both.faces.resize(2 * sphere.faces.rows(), 3);
  both.faces << sphere.faces, sphere.faces.array() + static_cast<int>(sphere.vertices.rows());
  return both;
}

double signed_area(const TextureAtlas& atlas, Eigen::Index face) {
  const Eigen::Vector2d a(atlas.corner_uv(face, 0), atlas.corner_uv(face, 1));
  const Eigen::Vector2d b(atlas.corner_uv(face, 2), atlas.corner_uv(face, 3));
  const Eigen::Vector2d c(atlas.corner_uv(face, 4), atlas.corner_uv(face, 5));
  const Eigen::Vector2d e1 = b - a, e2 = c - a;
  return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

// A chart as it lies in the atlas: one vertex per 3D position and UV position (a seam the chart
// was cut along gives the point two; vertices a file split at one point, which a chart spans with
// one UV, are one).
Mesh laid_out_chart(const Mesh& mesh, const TextureAtlas& atlas, const AtlasChart& chart) {
  std::map<std::tuple<double, double, double, double, double>, int> vertex_of;
  Mesh laid_out;
  std::vector<Eigen::Vector3d> positions;
  laid_out.faces.resize(static_cast<Eigen::Index>(chart.faces.size()), 3);
  for (std::size_t i = 0; i < chart.faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int f = chart.faces[i];
      const int vertex = mesh.faces(f, k);
      const auto key = std::make_tuple(mesh.vertices(vertex, 0), mesh.vertices(vertex, 1), mesh.vertices(vertex, 2),
                                       atlas.corner_uv(f, 2 * k), atlas.corner_uv(f, 2 * k + 1));
      const auto [entry, added] = vertex_of.emplace(key, static_cast<int>(positions.size()));
      if (added) positions.emplace_back(mesh.vertices.row(vertex));
      laid_out.faces(static_cast<Eigen::Index>(i), k) = entry->second;
    }
  laid_out.vertices.resize(static_cast<Eigen::Index>(positions.size()), 3);
  for (std::size_t v = 0; v < positions.size(); ++v) laid_out.vertices.row(static_cast<Eigen::Index>(v)) = positions[v];
  return laid_out;
}

// A face of no area: its edges' cross product within the rounding of its corners (16 epsilon
// times the product of the two edges' lengths).
bool has_zero_area(const Mesh& mesh, int face) {
  const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(face, 0));
  const Eigen::Vector3d first = Eigen::Vector3d(mesh.vertices.row(mesh.faces(face, 1))) - a;
  const Eigen::Vector3d second = Eigen::Vector3d(mesh.vertices.row(mesh.faces(face, 2))) - a;
  return first.cross(second).norm() <= 16.0 * std::numeric_limits<double>::epsilon() * first.norm() * second.norm();
}

// Whether every corner of `inner`'s UV triangle is strictly inside `outer`'s (all three
// barycentric coordinates positive).
bool uv_triangle_inside(const TextureAtlas& atlas, int inner, int outer) {
  const auto corner = [&atlas](int face, int k) {
    return Eigen::Vector2d(atlas.corner_uv(face, 2 * k), atlas.corner_uv(face, 2 * k + 1));
  };
  const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  const Eigen::Vector2d a = corner(outer, 0), b = corner(outer, 1), c = corner(outer, 2);
  const double area = cross(b - a, c - a);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d p = corner(inner, k);
    if (!(cross(b - p, c - p) / area > 0.0 && cross(c - p, a - p) / area > 0.0 && cross(a - p, b - p) / area > 0.0))
      return false;
  }
  return true;
}

// What every atlas must be: each face in exactly one chart, the faces of area of each chart a
// disk and its faces of zero area each drawn strictly inside one of them, every UV triangle
// counter-clockwise with positive area inside [0, 1]^2, and the measured atlas free of flips,
// mirrored charts, shared texels and crossing chart boundaries.
void expect_valid_atlas(const Mesh& mesh, const TextureAtlas& atlas) {
  ASSERT_TRUE(atlas.report.ok()) << atlas.report.message;
  ASSERT_EQ(atlas.corner_uv.rows(), mesh.faces.rows());
  ASSERT_EQ(atlas.chart_of_face.size(), static_cast<std::size_t>(mesh.faces.rows()));
  std::vector<int> seen(static_cast<std::size_t>(mesh.faces.rows()), 0);
  for (std::size_t c = 0; c < atlas.charts.size(); ++c) {
    const AtlasChart& chart = atlas.charts[c];
    ASSERT_FALSE(chart.faces.empty());
    for (const int f : chart.faces) {
      ++seen[static_cast<std::size_t>(f)];
      EXPECT_EQ(atlas.chart_of_face[static_cast<std::size_t>(f)], static_cast<int>(c));
    }
    AtlasChart of_area = chart;
    std::vector<int> zero_area;
    of_area.faces.clear();
    for (const int f : chart.faces) (has_zero_area(mesh, f) ? zero_area : of_area.faces).push_back(f);
    if (of_area.faces.empty()) continue;  // a face of zero area alone: a chart of its own
    std::string problem;
    EXPECT_EQ(check_disk(laid_out_chart(mesh, atlas, of_area), &problem), Status::ok) << "chart " << c << ": " << problem;
    for (const int f : zero_area)
      EXPECT_TRUE(std::any_of(of_area.faces.begin(), of_area.faces.end(),
                              [&](int host) { return uv_triangle_inside(atlas, f, host); }))
          << "face " << f << " of zero area lies inside no face of its chart " << c;
  }
  for (std::size_t f = 0; f < seen.size(); ++f) EXPECT_EQ(seen[f], 1) << "face " << f;
  EXPECT_GE(atlas.corner_uv.minCoeff(), 0.0);
  EXPECT_LE(atlas.corner_uv.maxCoeff(), 1.0);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) EXPECT_GT(signed_area(atlas, f), 0.0) << "face " << f;
  EXPECT_EQ(atlas.metrics.dropped_faces, 0);
  EXPECT_EQ(atlas.metrics.flipped_triangles, 0);
  EXPECT_EQ(atlas.metrics.mirrored_charts, 0);
  EXPECT_EQ(atlas.metrics.overlapping_texels, 0);
  EXPECT_EQ(atlas.metrics.boundary_crossings, 0);
  EXPECT_GT(atlas.metrics.coverage, 0.0);
}

// The charts as sets of faces, in a form that does not depend on the chart numbering.
std::set<std::vector<int>> chart_sets(const TextureAtlas& atlas, const std::vector<int>& original_face = {}) {
  std::set<std::vector<int>> sets;
  for (const AtlasChart& chart : atlas.charts) {
    std::vector<int> faces;
    for (const int f : chart.faces) faces.push_back(original_face.empty() ? f : original_face[static_cast<std::size_t>(f)]);
    std::sort(faces.begin(), faces.end());
    sets.insert(faces);
  }
  return sets;
}

// Two sides of a cube that share an edge unfold into the plane exactly (the edge is a hinge), so
// the sides go two by two into charts, never three (they would hold a corner's curvature).
TEST(TextureAtlas, CubeSidesJoinInPairsAcrossTheirEdges) {
  const Mesh mesh = grid_cube(4);
  const TextureAtlas atlas = texture_atlas(mesh, test_options());
  expect_valid_atlas(mesh, atlas);
  EXPECT_GE(atlas.charts.size(), 3u);
  EXPECT_LE(atlas.charts.size(), 4u);  // a greedy pairing may leave two opposite sides alone
  for (const AtlasChart& chart : atlas.charts) {
    EXPECT_TRUE(chart.faces.size() == 32u || chart.faces.size() == 64u) << chart.faces.size();
    // A square, or two squares unfolded across their edge, flattens exactly.
    EXPECT_NEAR(chart.l2_stretch, 1.0, 1e-9);
    EXPECT_NEAR(chart.angle_distortion, 1.0, 1e-9);
  }
}

// A long box (1 x 0.3 x 3.5): its long sides pair up across their long edges, and each end joins
// a pair along one edge with its edge against the pair's other side cut, so that the corner stays
// on the chart's boundary. Two charts of three sides around opposite corners, each an exact
// unfolding, none cut again for its length (that would add charts for little coverage).
TEST(TextureAtlas, ALongBoxIsTwoChartsOfThreeSidesAroundACorner) {
  Mesh mesh = grid_cube(3);
  mesh.vertices.col(1) *= 0.3;
  mesh.vertices.col(2) *= 3.5;
  const TextureAtlas atlas = texture_atlas(mesh, test_options());
  expect_valid_atlas(mesh, atlas);
  ASSERT_EQ(atlas.charts.size(), 2u);
  for (const AtlasChart& chart : atlas.charts) {
    EXPECT_EQ(chart.faces.size(), 3u * 18u);
    EXPECT_FALSE(chart.piece_of_a_cut);
    // Its three sides' normals are the three axes, one sign each: one corner's sides.
    std::set<std::pair<int, int>> axes;
    for (const int f : chart.faces) {
      const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)), b = mesh.vertices.row(mesh.faces(f, 1)),
                            c = mesh.vertices.row(mesh.faces(f, 2));
      Eigen::Index axis = 0;
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      normal.cwiseAbs().maxCoeff(&axis);
      axes.insert({static_cast<int>(axis), normal(axis) > 0.0 ? 1 : -1});
    }
    EXPECT_EQ(axes.size(), 3u);
    EXPECT_NEAR(chart.l2_stretch, 1.0, 1e-9);
    EXPECT_NEAR(chart.angle_distortion, 1.0, 1e-9);
  }
}

// Left to choose its backend, the atlas of a small mesh does not look for a device (finding one
// costs more than the atlas): no "device" phase, the CPU backend, and a notice that says why.
TEST(TextureAtlas, ASmallMeshDoesNotLookForADevice) {
  TextureAtlasOptions options = test_options();
  options.solver.backend = BackendChoice::automatic;
  const Mesh mesh = grid_cube(2);
  ASSERT_LT(mesh.faces.rows(), kSmallestAtlasForDevice);
  const TextureAtlas atlas = texture_atlas(mesh, options);
  expect_valid_atlas(mesh, atlas);
  EXPECT_EQ(atlas.report.backend, BackendKind::cpu);
  EXPECT_NE(atlas.report.backend_notice.find(std::to_string(kSmallestAtlasForDevice)), std::string::npos)
      << atlas.report.backend_notice;
  for (const PhaseTiming& timing : atlas.report.timings) EXPECT_NE(timing.phase, "device");
}

// A texel density asked for is the atlas' density: a cube of side 2 at 100 texels per unit has
// sides of 200 texels, whatever the resolution; its charts are the ones the searched density
// makes; charts that do not fit one page go on further pages, and beyond max_pages the atlas is
// refused with a reason, nothing placed.
TEST(TextureAtlas, AFixedTexelDensityIsKeptOnAsManyPagesAsItNeeds) {
  const Mesh mesh = grid_cube(4);  // Side 2.
  TextureAtlasOptions options = test_options();
  options.resolution = 1024;
  const TextureAtlas searched = texture_atlas(mesh, options);
  options.texels_per_unit = 100.0;
  const TextureAtlas fixed = texture_atlas(mesh, options);
  expect_valid_atlas(mesh, fixed);
  EXPECT_NEAR(fixed.metrics.texels_per_unit, 100.0, 100.0 * 64 * std::numeric_limits<double>::epsilon());
  EXPECT_EQ(fixed.charts.size(), searched.charts.size());
  EXPECT_LT(fixed.metrics.coverage, searched.metrics.coverage);
  // Six sides of 2 x 2 units at 100 texels per unit: 240,000 texels of a 1024^2 atlas; the texel
  // centres inside them differ from that only along the charts' edges.
  const double expected = 6 * 200.0 * 200.0 / (1024.0 * 1024.0);
  EXPECT_NEAR(fixed.metrics.coverage, expected, 0.01);
  EXPECT_EQ(fixed.pages, 1);
  // 800 texels a side: two sides cannot share a page of 1020 x 1020 inside, so each chart (a
  // side, or two sides unfolded across their edge: 800 x 1600, larger than a page, halved) takes
  // a page of its own.
  options.texels_per_unit = 400.0;
  const TextureAtlas paged = texture_atlas(mesh, options);
  expect_valid_atlas(mesh, paged);
  EXPECT_NEAR(paged.metrics.texels_per_unit, 400.0, 400.0 * 64 * std::numeric_limits<double>::epsilon());
  EXPECT_EQ(paged.pages, 6);
  std::set<int> pages;
  for (const AtlasChart& chart : paged.charts) {
    pages.insert(chart.page);
    EXPECT_NEAR(chart.l2_stretch, 1.0, 1e-9);
  }
  EXPECT_EQ(pages.size(), 6u);
  // The six sides' 6 x 800^2 texels over six pages (but for the charts' edges), page by page.
  ASSERT_EQ(paged.metrics.page_coverage.size(), 6u);
  double page_sum = 0.0;
  for (const double coverage : paged.metrics.page_coverage) page_sum += coverage;
  EXPECT_NEAR(paged.metrics.coverage, 800.0 * 800.0 / (1024.0 * 1024.0), 0.01);
  EXPECT_NEAR(page_sum / 6.0, paged.metrics.coverage, 1e-12);
  options.max_pages = 5;
  const TextureAtlas refused = texture_atlas(mesh, options);
  EXPECT_EQ(refused.report.status, Status::invalid_input);
  EXPECT_NE(refused.report.message.find("more pages"), std::string::npos) << refused.report.message;
  options.max_pages = -1;
  EXPECT_EQ(texture_atlas(mesh, options).report.status, Status::invalid_input);
  options.max_pages = 0;
  options.texels_per_unit = -1.0;
  EXPECT_EQ(texture_atlas(mesh, options).report.status, Status::invalid_input);
}

// A non-square atlas: the cube's charts laid out isometric in texels (no stretch or angle
// distortion measured in the atlas' own proportions), every chart inside 512 x 256 texels.
TEST(TextureAtlas, ANonSquareAtlasKeepsChartsIsometricInTexels) {
  const Mesh mesh = grid_cube(4);
  TextureAtlasOptions options = test_options();
  options.resolution = 512;
  options.height = 256;
  const TextureAtlas atlas = texture_atlas(mesh, options);
  expect_valid_atlas(mesh, atlas);
  EXPECT_EQ(atlas.resolution, 512);
  EXPECT_EQ(atlas.height_texels(), 256);
  EXPECT_NEAR(atlas.metrics.l2_stretch, 1.0, 1e-9);
  EXPECT_NEAR(atlas.metrics.angle_distortion, 1.0, 1e-9);
  for (const AtlasChart& chart : atlas.charts) {
    EXPECT_GE(chart.texel_box.min().minCoeff(), 0.0);
    EXPECT_LE(chart.texel_box.max().x(), 512.0);
    EXPECT_LE(chart.texel_box.max().y(), 256.0);
  }
  // Six 2 x 2 sides in 512 x 256: at least a quarter of it covered (two rows of three sides fit).
  EXPECT_GT(atlas.metrics.coverage, 0.25);
  options.height = 8;
  EXPECT_EQ(texture_atlas(mesh, options).report.status, Status::invalid_input);
}

TEST(TextureAtlas, TorusOfGenusOne) {
  const Mesh mesh = torus(48, 16, 0.35);
  const TextureAtlas atlas = texture_atlas(mesh, test_options());
  expect_valid_atlas(mesh, atlas);
  EXPECT_GE(atlas.charts.size(), 2u);
}

TEST(TextureAtlas, TwoComponents) {
  const Mesh mesh = two_components();
  const TextureAtlas atlas = texture_atlas(mesh, test_options());
  expect_valid_atlas(mesh, atlas);
  // No chart spans both spheres.
  const int first_half = static_cast<int>(mesh.faces.rows() / 2);
  for (const AtlasChart& chart : atlas.charts) {
    const bool first = chart.faces.front() < first_half;
    for (const int f : chart.faces) EXPECT_EQ(f < first_half, first);
  }
}

TEST(TextureAtlas, SphereWithHoles) {
  const Mesh mesh = without_faces(unit_sphere(4), [](const Eigen::Vector3d& p) {
    return (p - Eigen::Vector3d(0, 0, 1)).norm() < 0.3 || (p - Eigen::Vector3d(1, 0, 0)).norm() < 0.4 ||
           (p - Eigen::Vector3d(0, -0.7, -0.7)).norm() < 0.2;
  });
  const TextureAtlas atlas = texture_atlas(mesh, test_options());
  expect_valid_atlas(mesh, atlas);
}

// A closed rod along x: a cylinder of radius `radius` and length `length`, `around` x `along`
// quads split in two, with a fan at each end; faces counter-clockwise seen from outside.
Mesh capped_rod(int around, int along, double radius, double length) {
  Mesh mesh;
  mesh.vertices.resize(around * (along + 1) + 2, 3);
  for (int i = 0; i <= along; ++i)
    for (int j = 0; j < around; ++j) {
      const double angle = 2.0 * M_PI * j / around;
      mesh.vertices.row(i * around + j) << length * i / along, radius * std::cos(angle), radius * std::sin(angle);
    }
  const int start = around * (along + 1), end = start + 1;
  mesh.vertices.row(start) << 0.0, 0.0, 0.0;
  mesh.vertices.row(end) << length, 0.0, 0.0;
  std::vector<Eigen::Vector3i> faces;
  const auto vertex = [around](int i, int j) { return i * around + (j % around); };
  for (int i = 0; i < along; ++i)
    for (int j = 0; j < around; ++j) {
      faces.emplace_back(vertex(i, j), vertex(i, j + 1), vertex(i + 1, j + 1));
      faces.emplace_back(vertex(i, j), vertex(i + 1, j + 1), vertex(i + 1, j));
    }
  for (int j = 0; j < around; ++j) {
    faces.emplace_back(start, vertex(0, j + 1), vertex(0, j));
    faces.emplace_back(end, vertex(along, j), vertex(along, j + 1));
  }
  mesh.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) mesh.faces.row(static_cast<Eigen::Index>(f)) = faces[f];
  return mesh;
}

TEST(TextureAtlas, ChartsAsLongAsTheRodAreCutToFitTheSquare) {
  // Its charts are strips as long as the rod; one of them alone would cap the density at
  // (resolution - 2 margin) / length texels per unit (the margin along each edge is half the
  // padding, rounded up), where the strips fill a sixth of the atlas. Cut across their length,
  // they pack denser than that cap.
  const double length = 4.0;
  const Mesh mesh = capped_rod(32, 160, 0.1, length);
  const TextureAtlasOptions options = test_options();
  const TextureAtlas atlas = texture_atlas(mesh, options);
  expect_valid_atlas(mesh, atlas);
  const double capped_density = (options.resolution - 2.0 * ((options.padding + 1) / 2)) / length;
  EXPECT_GT(atlas.metrics.texels_per_unit, 1.5 * capped_density);
  // The long charts were cut, their pieces keeping their part of the layout.
  EXPECT_TRUE(std::any_of(atlas.charts.begin(), atlas.charts.end(),
                          [](const AtlasChart& chart) { return chart.piece_of_a_cut; }));
  for (const AtlasChart& chart : atlas.charts) EXPECT_LE(chart.l2_stretch, options.max_distortion);
}

TEST(TextureAtlas, SameChartsAtAnyScale) {
  const Mesh mesh = torus(40, 14, 0.4);
  const TextureAtlas reference = texture_atlas(mesh, test_options());
  ASSERT_TRUE(reference.report.ok()) << reference.report.message;
  for (const double scale : {1e-6, 1e6}) {
    Mesh scaled = mesh;
    scaled.vertices *= scale;
    const TextureAtlas atlas = texture_atlas(scaled, test_options());
    expect_valid_atlas(scaled, atlas);
    EXPECT_EQ(chart_sets(atlas), chart_sets(reference)) << "scale " << scale;
  }
}

TEST(TextureAtlas, SameChartsForAnyFaceOrder) {
  const Mesh mesh = unit_sphere(4);
  std::vector<int> order(static_cast<std::size_t>(mesh.faces.rows()));
  std::iota(order.begin(), order.end(), 0);
  std::mt19937 shuffle_source(7);
  std::shuffle(order.begin(), order.end(), shuffle_source);
  Mesh shuffled = mesh;
  for (std::size_t i = 0; i < order.size(); ++i) shuffled.faces.row(static_cast<Eigen::Index>(i)) = mesh.faces.row(order[i]);
  const TextureAtlas atlas = texture_atlas(mesh, test_options());
  const TextureAtlas shuffled_atlas = texture_atlas(shuffled, test_options());
  expect_valid_atlas(shuffled, shuffled_atlas);
  EXPECT_EQ(chart_sets(shuffled_atlas, order), chart_sets(atlas));
}

TEST(TextureAtlas, ZeroAreaFacesAreKept) {
  // A flat strip with a face whose corners are collinear (a sliver of zero area) and a face
  // whose corners coincide.
  Mesh mesh = planar_disk(4);
  const Eigen::Index first = mesh.vertices.rows();
  mesh.vertices.conservativeResize(first + 5, 3);
  mesh.vertices.row(first) << 3.0, 0.0, 0.0;
  mesh.vertices.row(first + 1) << 4.0, 0.0, 0.0;
  mesh.vertices.row(first + 2) << 5.0, 0.0, 0.0;
  mesh.vertices.row(first + 3) << 3.0, 0.0, 0.0;
  mesh.vertices.row(first + 4) << 3.0, 0.0, 0.0;
  const Eigen::Index faces = mesh.faces.rows();
  mesh.faces.conservativeResize(faces + 2, 3);
  mesh.faces.row(faces) << static_cast<int>(first), static_cast<int>(first + 1), static_cast<int>(first + 2);
  mesh.faces.row(faces + 1) << static_cast<int>(first), static_cast<int>(first + 3), static_cast<int>(first + 4);
  const TextureAtlas atlas = texture_atlas(mesh, test_options());
  ASSERT_TRUE(atlas.report.ok()) << atlas.report.message;
  EXPECT_EQ(atlas.metrics.dropped_faces, 0);
  for (const Eigen::Index f : {faces, faces + 1}) {
    const AtlasChart& chart = atlas.charts[static_cast<std::size_t>(atlas.chart_of_face[static_cast<std::size_t>(f)])];
    EXPECT_EQ(chart.method, ChartMethod::degenerate);
    EXPECT_GT(signed_area(atlas, f), 0.0);
  }
  EXPECT_EQ(atlas.metrics.overlapping_texels, 0);
}

// A pole as many exporters write a UV sphere's: the pole vertex repeated once per column, each
// copy in one triangle of area, and between them triangles of zero area (two corners on the pole),
// here around the centre of a flat disk, with also a triangle whose three corners are the pole.
// The faces of zero area cover nothing: they go inside the chart around them, strictly inside
// faces of area (several in one face apart), and the disk stays one chart, exactly flat.
TEST(TextureAtlas, ZeroAreaFacesGoInsideTheChartAroundThem) {
  constexpr int kColumns = 12;
  Mesh mesh;
  mesh.vertices.resize(2 * kColumns + 1, 3);
  for (int i = 0; i < kColumns; ++i) {
    const double angle = 2.0 * std::acos(-1.0) * i / kColumns;
    mesh.vertices.row(i) << 0.0, 0.0, 0.0;  // the pole's copies
    mesh.vertices.row(kColumns + i) << std::cos(angle), std::sin(angle), 0.0;
  }
  mesh.vertices.row(2 * kColumns) << 0.0, 0.0, 0.0;
  std::vector<Eigen::RowVector3i> faces;
  for (int i = 0; i < kColumns; ++i) {
    const int next = (i + 1) % kColumns;
    faces.emplace_back(i, kColumns + i, kColumns + next);  // of area
    faces.emplace_back(i, kColumns + next, next);          // zero area: the pole twice
  }
  faces.emplace_back(0, 2 * kColumns, 1);  // the pole three times
  mesh.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) mesh.faces.row(static_cast<Eigen::Index>(f)) = faces[f];
  const TextureAtlas atlas = texture_atlas(mesh, test_options());
  expect_valid_atlas(mesh, atlas);
  ASSERT_EQ(atlas.charts.size(), 1u);
  EXPECT_EQ(atlas.charts[0].faces.size(), faces.size());
  // The faces of area are laid out as they lie, at one scale: each UV edge is the same multiple
  // of its 3D length (to rounding, relative 1e-9).
  int zero_area = 0;
  double scale = 0.0;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    if (has_zero_area(mesh, static_cast<int>(f))) {
      ++zero_area;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int j = (k + 1) % 3;
      const double uv = std::hypot(atlas.corner_uv(f, 2 * j) - atlas.corner_uv(f, 2 * k),
                                   atlas.corner_uv(f, 2 * j + 1) - atlas.corner_uv(f, 2 * k + 1));
      const double length = (mesh.vertices.row(mesh.faces(f, j)) - mesh.vertices.row(mesh.faces(f, k))).norm();
      if (scale == 0.0) scale = uv / length;
      EXPECT_NEAR(uv / length / scale, 1.0, 1e-9) << "face " << f << " edge " << k;
    }
  }
  EXPECT_EQ(zero_area, kColumns + 1);
}

TEST(TextureAtlas, BadOptionsAndMeshesAreRefused) {
  const Mesh mesh = grid_cube(2);
  TextureAtlasOptions options = test_options();
  options.resolution = 8;
  EXPECT_EQ(texture_atlas(mesh, options).report.status, Status::invalid_input);
  options = test_options();
  options.max_distortion = 1.0;
  EXPECT_NE(texture_atlas(mesh, options).report.message.find("max_distortion"), std::string::npos);
  Mesh broken = mesh;
  broken.faces(3, 1) = 1000;
  const TextureAtlas atlas = texture_atlas(broken, test_options());
  EXPECT_EQ(atlas.report.status, Status::invalid_input);
  EXPECT_NE(atlas.report.message.find("f3 uses vertex index 1000"), std::string::npos) << atlas.report.message;
}

// The mesh as a flat-shaded asset stores it: every face with three vertices of its own.
Mesh split_at_every_face(const Mesh& mesh) {
  Mesh split;
  split.vertices.resize(3 * mesh.faces.rows(), 3);
  split.faces.resize(mesh.faces.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      split.vertices.row(3 * f + k) = mesh.vertices.row(mesh.faces(f, k));
      split.faces(f, k) = static_cast<int>(3 * f + k);
    }
  return split;
}

// A flat-shaded model (every vertex split, as exporters write hard edges) is charted as the
// surface it describes: the same charts as the welded mesh, and the corners that meet at one point
// inside a chart get one UV, so a texture painted through the atlas shows no seam there. With
// keep_splits every split is a chart boundary: one chart per face.
TEST(TextureAtlas, ChartsSpanTheSplitsOfTheFile) {
  const Mesh welded = unit_sphere(2);
  const Mesh split = split_at_every_face(welded);
  const TextureAtlas reference = texture_atlas(welded, test_options());
  const TextureAtlas atlas = texture_atlas(split, test_options());
  expect_valid_atlas(split, atlas);
  EXPECT_EQ(atlas.welded_vertices, split.vertex_count() - welded.vertex_count());
  EXPECT_EQ(atlas.charts.size(), reference.charts.size());
  EXPECT_EQ(atlas.chart_of_face, reference.chart_of_face);
  // Per chart, the corners at one vertex of the welded sphere share their UV.
  std::map<std::pair<int, int>, Eigen::Vector2d> uv_at;  // (chart, welded vertex) -> uv
  for (Eigen::Index f = 0; f < split.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d uv(atlas.corner_uv(f, 2 * k), atlas.corner_uv(f, 2 * k + 1));
      const auto [entry, added] = uv_at.try_emplace({atlas.chart_of_face[static_cast<std::size_t>(f)], welded.faces(f, k)}, uv);
      if (!added) {
        EXPECT_EQ(entry->second, uv) << "face " << f << " corner " << k;
      }
    }
  TextureAtlasOptions keep = test_options();
  keep.keep_splits = true;
  const TextureAtlas kept = texture_atlas(split, keep);
  expect_valid_atlas(split, kept);
  EXPECT_EQ(kept.welded_vertices, 0);
  EXPECT_EQ(kept.charts.size(), static_cast<std::size_t>(split.face_count()));
}

// Joining charts whose union flattens within the limit (TextureAtlasOptions::join_charts): on a
// sphere segmented in a 30-degree cone (at the default 60 the segmentation already leaves about
// the charts a sphere needs), fewer charts than without, a valid atlas, and every chart within
// the limit as the atlas' own measure finds it; the report names the phase.
TEST(TextureAtlas, JoinedChartsAreFewerAndStayWithinTheLimit) {
  const Mesh sphere = unit_sphere(4);  // 5,120 faces
  TextureAtlasOptions narrow = test_options();
  narrow.max_normal_deviation_degrees = 30.0;
  const TextureAtlas separate = texture_atlas(sphere, narrow);
  TextureAtlasOptions join = narrow;
  join.join_charts = true;
  const TextureAtlas joined = texture_atlas(sphere, join);
  expect_valid_atlas(sphere, joined);
  EXPECT_LT(joined.charts.size(), separate.charts.size());
  for (const AtlasChart& chart : joined.charts) EXPECT_LE(chart.l2_stretch, join.max_distortion);
  const auto phases = joined.report.timings;
  EXPECT_TRUE(std::any_of(phases.begin(), phases.end(), [](const PhaseTiming& t) { return t.phase == "joining"; }));
  EXPECT_FALSE(std::any_of(separate.report.timings.begin(), separate.report.timings.end(),
                           [](const PhaseTiming& t) { return t.phase == "joining"; }));
}

// Three squares on one edge (a fin on a plate, as welding a hard edge shared by several surfaces
// makes it): the edge held by three faces' pairs is a chart boundary, not a refusal.
TEST(TextureAtlas, AnEdgeOfThreeSurfacesIsAChartBoundary) {
  Mesh fin;
  fin.vertices.resize(8, 3);
  fin.vertices << 0, 0, 0, 0, 1, 0,  // the shared edge
      1, 0, 0, 1, 1, 0,              // a square on +x
      -1, 0, 0, -1, 1, 0,            // on -x
      0, 0, 1, 0, 1, 1;              // on +z
  fin.faces.resize(6, 3);
  fin.faces << 0, 2, 3, 0, 3, 1, 0, 1, 5, 0, 5, 4, 0, 6, 7, 0, 7, 1;
  const TextureAtlas atlas = texture_atlas(fin, test_options());
  expect_valid_atlas(fin, atlas);
  EXPECT_GE(atlas.charts.size(), 2u);
}

// One step of 1-to-4 midpoint subdivision without smoothing (../shared/tools/subdivide.py's): the
// same surface with four times the faces, each split into four similar triangles.
Mesh subdivided(const Mesh& mesh) {
  std::map<std::pair<int, int>, int> midpoint;
  std::vector<Eigen::RowVector3d> points;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) points.push_back(mesh.vertices.row(v));
  const auto middle = [&](int a, int b) {
    const auto [entry, added] = midpoint.try_emplace({std::min(a, b), std::max(a, b)}, static_cast<int>(points.size()));
    if (added) points.push_back(0.5 * (mesh.vertices.row(a) + mesh.vertices.row(b)));
    return entry->second;
  };
  Mesh fine;
  fine.faces.resize(4 * mesh.faces.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const int a = mesh.faces(f, 0), b = mesh.faces(f, 1), c = mesh.faces(f, 2);
    const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
    fine.faces.row(4 * f) << a, ab, ca;
    fine.faces.row(4 * f + 1) << ab, b, bc;
    fine.faces.row(4 * f + 2) << ca, bc, c;
    fine.faces.row(4 * f + 3) << ab, bc, ca;
  }
  fine.vertices.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v) fine.vertices.row(static_cast<Eigen::Index>(v)) = points[v];
  return fine;
}

// The closed corpus meshes: valid atlases, with the figures docs/methods.md ("Texture atlases")
// promises at the default options (1024 texels): coverage at least 0.65 (ours 0.67-0.72 there;
// xatlas's 0.55-0.62 on the same meshes, bench/corpus_atlas_benchmark), every chart within the
// stretch limit, and charts that do not multiply with the resolution of the mesh (at most twice the
// base mesh's after a 4x subdivision of the same surface; xatlas: up to 64 times at 16x).
TEST(TextureAtlas, ClosedCorpusMeshes) {
  const std::vector<std::filesystem::path> meshes = testing::corpus_meshes("closed");
  if (meshes.size() < 8) HARMONIA_SKIP_WITHOUT_CORPUS("the 8 closed corpus meshes are not at " << testing::shared_data_dir());
  TextureAtlasOptions options;
  options.solver.backend = BackendChoice::cpu;
  for (const auto& path : meshes) {
    SCOPED_TRACE(path.filename().string());
    const Mesh mesh = read_mesh(path);
    const TextureAtlas atlas = texture_atlas(mesh, options);
    expect_valid_atlas(mesh, atlas);
    EXPECT_GE(atlas.metrics.coverage, 0.65);
    for (const AtlasChart& chart : atlas.charts) EXPECT_LE(chart.l2_stretch, options.max_distortion);
    const TextureAtlas fine = texture_atlas(subdivided(mesh), options);
    ASSERT_TRUE(fine.report.ok()) << fine.report.message;
    EXPECT_LE(fine.charts.size(), 2 * atlas.charts.size());
  }
}

}  // namespace
}  // namespace harmonia
