// The atlas picture, on atlases built by hand (not by texture_atlas, so that what the picture
// should show is known exactly): the PNG decodes to the requested size with something drawn in
// both halves; the same arguments give the same bytes; on the left an isometric chart is white
// (the distortion colours' undistorted colour) exactly where its UVs put it in the atlas square,
// with its boundary dark and background around it, and a stretched chart takes the colour of its
// stretch; on the right a flat square facing the viewer wears both checker colours, with as many
// squares across as its UVs span; bad arguments are refused, naming the problem, before anything
// is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "harmonia/atlas_picture.h"
#include "harmonia/texture_atlas.h"
#include "harmonia/types.h"
#include "picture/color_map.h"
#include "support/decoded_png.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;
using detail::Rgb;

// ---------------------------------------------------------------------------------------------
// Meshes and atlases

// The unit square [0, 1]^2 of the plane z = 0, facing +z (the viewer), as two triangles.
Mesh flat_square() {
  Mesh mesh;
  mesh.vertices = Eigen::MatrixX3d{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.faces = Eigen::MatrixX3i{{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

// The square laid flat in one chart: corner (x, y) at origin + (x * size.x, y * size.y) in the
// atlas; isometric (up to scale) when both sizes are equal.
TextureAtlas square_atlas(const Mesh& square, const Eigen::Vector2d& origin,
                          const Eigen::Vector2d& size) {
  TextureAtlas atlas;
  atlas.resolution = 256;
  atlas.charts.resize(1);
  atlas.charts[0].faces = {0, 1};
  atlas.chart_of_face = {0, 0};
  atlas.corner_uv.resize(square.faces.rows(), 6);
  for (Eigen::Index f = 0; f < square.faces.rows(); ++f)
    for (int corner = 0; corner < 3; ++corner)
      for (int axis = 0; axis < 2; ++axis)
        atlas.corner_uv(f, 2 * corner + axis) =
            origin[axis] + size[axis] * square.vertices(square.faces(f, corner), axis);
  return atlas;
}

// The unit cube [0, 1]^3, its 8 corners shared by its 6 sides, 2 triangles a side.
struct CubeAtlas {
  Mesh mesh;
  TextureAtlas atlas;
};

// Each side is a chart, laid out isometrically (corners keeping their order, so counter-clockwise
// in UV) in its own 0.3 x 0.3 cell of a 3 x 2 grid over the atlas.
CubeAtlas cube_atlas() {
  constexpr double kCell = 0.3;
  CubeAtlas cube;
  cube.mesh.vertices.resize(8, 3);
  for (int v = 0; v < 8; ++v) cube.mesh.vertices.row(v) << v / 4, (v / 2) % 2, v % 2;
  cube.mesh.faces.resize(12, 3);
  cube.atlas.resolution = 256;
  cube.atlas.charts.resize(6);
  cube.atlas.chart_of_face.resize(12);
  cube.atlas.corner_uv.resize(12, 6);
  const std::vector<std::pair<int, int>> quad = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int side = 0; side < 6; ++side) {
    // The side's outward normal is +-axis; (first, second) span it with first x second = normal.
    const int axis = side / 2;
    const bool positive = side % 2 == 1;
    int first = (axis + 1) % 3, second = (axis + 2) % 3;
    if (!positive) std::swap(first, second);
    const Eigen::Vector2d cell_origin(0.025 + 0.325 * (side % 3), 0.05 + 0.45 * (side / 3));
    std::vector<int> corners;
    std::vector<Eigen::Vector2d> uvs;
    for (const auto& [i, j] : quad) {
      Eigen::Vector3i point = Eigen::Vector3i::Zero();
      point[axis] = positive ? 1 : 0;
      point[first] = i;
      point[second] = j;
      corners.push_back(4 * point.x() + 2 * point.y() + point.z());
      uvs.push_back(cell_origin + kCell * Eigen::Vector2d(i, j));
    }
    for (int half = 0; half < 2; ++half) {
      const int face = 2 * side + half;
      const std::array<int, 3> of_quad = half == 0 ? std::array{0, 1, 2} : std::array{0, 2, 3};
      for (int corner = 0; corner < 3; ++corner) {
        const auto k = static_cast<std::size_t>(of_quad[static_cast<std::size_t>(corner)]);
        cube.mesh.faces(face, corner) = corners[k];
        cube.atlas.corner_uv(face, 2 * corner) = uvs[k].x();
        cube.atlas.corner_uv(face, 2 * corner + 1) = uvs[k].y();
      }
      cube.atlas.chart_of_face[static_cast<std::size_t>(face)] = side;
      cube.atlas.charts[static_cast<std::size_t>(side)].faces.push_back(face);
    }
  }
  return cube;
}

// ---------------------------------------------------------------------------------------------
// Reading the picture

// The pixels of one colour in one half (0 left, 1 right), above the captions and the legend: how
// many, and their bounding box.
struct ColorRegion {
  int count = 0;
  int left = INT_MAX, top = INT_MAX, right = -1, bottom = -1;
};

ColorRegion region_of(const testing::DecodedImage& image, int half, const Rgb& color) {
  ColorRegion region;
  const int half_width = image.width / 2;
  for (int y = 0; y < image.height * 85 / 100; ++y) {
    for (int x = half * half_width; x < (half + 1) * half_width; ++x) {
      if (image.at(x, y) != color) continue;
      ++region.count;
      region.left = std::min(region.left, x);
      region.right = std::max(region.right, x);
      region.top = std::min(region.top, y);
      region.bottom = std::max(region.bottom, y);
    }
  }
  return region;
}

bool is_dark(const Rgb& color) { return color.red < 128 && color.green < 128 && color.blue < 128; }

// How often the colour changes along the run of drawn pixels through `at`, across (a row) or down
// (a column).
int color_changes_through(const testing::DecodedImage& image, std::pair<int, int> at, bool across) {
  const auto pixel = [&](int offset) {
    return across ? image.at(at.first + offset, at.second) : image.at(at.first, at.second + offset);
  };
  const int room = across ? image.width : image.height;
  const int here = across ? at.first : at.second;
  int first = 0, last = 0;
  while (here + first > 0 && !testing::is_background(pixel(first - 1))) --first;
  while (here + last < room - 1 && !testing::is_background(pixel(last + 1))) ++last;
  int changes = 0;
  for (int offset = first + 1; offset <= last; ++offset)
    changes += pixel(offset) != pixel(offset - 1) ? 1 : 0;
  return changes;
}

// The colours drawn in the right half above the captions, with their pixel counts.
std::map<std::array<int, 3>, int> right_view_colors(const testing::DecodedImage& image) {
  std::map<std::array<int, 3>, int> colors;
  for (int y = 0; y < image.height * 85 / 100; ++y) {
    for (int x = image.width / 2; x < image.width; ++x) {
      const Rgb color = image.at(x, y);
      if (!testing::is_background(color)) ++colors[{color.red, color.green, color.blue}];
    }
  }
  return colors;
}

class AtlasPictureTest : public ::testing::Test {
 protected:
  testing::ScratchFolder scratch_{"atlas-picture"};
  const Mesh square_ = flat_square();
  // The flat square isometric in [0.1, 0.9]^2.
  const TextureAtlas square_atlas_ = square_atlas(square_, {0.1, 0.1}, {0.8, 0.8});
};

// ---------------------------------------------------------------------------------------------
// The tests

TEST_F(AtlasPictureTest, IsAPngOfTheRequestedSizeWithSomethingInEachHalf) {
  const CubeAtlas cube = cube_atlas();
  const fs::path standard = scratch_.file("cube.png");
  write_atlas_picture(standard, cube.mesh, cube.atlas);
  const fs::path small = scratch_.file("small.png");
  AtlasPictureOptions options;
  options.width = 901;
  options.height = 500;
  options.title = "cube.obj - 6 charts, 256 x 256 texels";
  write_atlas_picture(small, cube.mesh, cube.atlas, options);
  for (const auto& [path, width, height] :
       {std::tuple{standard, 1600, 800}, std::tuple{small, 901, 500}}) {
    const testing::DecodedImage image = testing::decode_png(path);
    ASSERT_EQ(image.width, width) << path;
    ASSERT_EQ(image.height, height) << path;
    for (const auto& [x, y] : testing::corner_pixels(image))
      EXPECT_TRUE(testing::is_background(image.at(x, y))) << path << " corner " << x << ", " << y;
    for (int half = 0; half < 2; ++half)
      EXPECT_GT(testing::count_in_view(
                    image, half, [](const Rgb& color) { return !testing::is_background(color); }),
                width * height / 20)
          << path << " half " << half;
  }
}

TEST_F(AtlasPictureTest, TheSameArgumentsGiveTheSameBytes) {
  const CubeAtlas cube = cube_atlas();
  AtlasPictureOptions options;
  options.width = 800;
  options.height = 400;
  options.title = "cube";
  for (const std::string name : {"first.png", "second.png"})
    write_atlas_picture(scratch_.file(name), cube.mesh, cube.atlas, options);
  const std::string first = testing::file_bytes(scratch_.file("first.png"));
  EXPECT_FALSE(first.empty());
  EXPECT_EQ(first, testing::file_bytes(scratch_.file("second.png")));
}

TEST_F(AtlasPictureTest, AnIsometricChartIsWhiteWhereItsUvsPutItAndBackgroundAroundIt) {
  const fs::path png = scratch_.file("square.png");
  write_atlas_picture(png, square_, square_atlas_);
  const testing::DecodedImage image = testing::decode_png(png);
  ASSERT_EQ(image.width, 1600);

  // The chart: a white square, white all through (no triangle is distorted).
  const Rgb undistorted = detail::conformal_color(1.0);
  ASSERT_EQ(undistorted, (Rgb{255, 255, 255}));
  const ColorRegion chart = region_of(image, 0, undistorted);
  ASSERT_GT(chart.count, 10000);
  const int side = chart.right - chart.left + 1;
  EXPECT_NEAR(chart.bottom - chart.top + 1, side, 2);
  EXPECT_GT(chart.count, (side - 4) * (side - 4));

  // Its boundary is dark; around it, between the chart and the atlas' edge (the chart spans 0.8
  // of the atlas, so the edge lies 0.1 / 0.8 of the chart's side beyond it), is background; at
  // the atlas' edge is its outline.
  const int middle_x = (chart.left + chart.right) / 2, middle_y = (chart.top + chart.bottom) / 2;
  const int margin = static_cast<int>(std::lround(0.125 * side));
  const std::vector<std::pair<int, int>> outward = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
  for (const auto& [dx, dy] : outward) {
    // The chart's edge on this side, on the line through its middle.
    const int edge_x = dx < 0 ? chart.left : dx > 0 ? chart.right : middle_x;
    const int edge_y = dy < 0 ? chart.top : dy > 0 ? chart.bottom : middle_y;
    EXPECT_TRUE(is_dark(image.at(edge_x + dx, edge_y + dy))) << dx << ", " << dy;
    const int half_margin = margin / 2;
    EXPECT_TRUE(testing::is_background(
        image.at(edge_x + dx * half_margin, edge_y + dy * half_margin)))
        << dx << ", " << dy;
    bool outline = false;
    for (int step = margin - 3; step <= margin + 3; ++step)
      outline = outline || is_dark(image.at(edge_x + dx * step, edge_y + dy * step));
    EXPECT_TRUE(outline) << dx << ", " << dy;
  }
}

TEST_F(AtlasPictureTest, AStretchedChartTakesTheColourOfItsStretch) {
  // Four times as wide as high in the atlas: sigma1/sigma2 = 4, where the colours saturate.
  const fs::path png = scratch_.file("stretched.png");
  write_atlas_picture(png, square_, square_atlas(square_, {0.1, 0.4}, {0.8, 0.2}));
  const testing::DecodedImage image = testing::decode_png(png);
  const ColorRegion chart = region_of(image, 0, detail::conformal_color(4.0));
  EXPECT_GT(chart.count, 10000);
  EXPECT_NEAR(static_cast<double>(chart.right - chart.left + 1) / (chart.bottom - chart.top + 1),
              4.0, 0.2);
  EXPECT_EQ(region_of(image, 0, detail::conformal_color(1.0)).count, 0);
}

TEST_F(AtlasPictureTest, AFlatSquareFacingTheViewerWearsTheCheckerAsItsUvsSpanIt) {
  const fs::path png = scratch_.file("checker.png");
  write_atlas_picture(png, square_, square_atlas_);
  const testing::DecodedImage image = testing::decode_png(png);

  // The square faces the viewer: one shade, so the checker's two colours only, in equal parts.
  const std::map<std::array<int, 3>, int> colors = right_view_colors(image);
  int drawn = 0;
  for (const auto& [color, count] : colors) drawn += count;
  ASSERT_EQ(colors.size(), 2u);
  for (const auto& [color, count] : colors) EXPECT_NEAR(count, drawn / 2, drawn / 20);

  // Across the square u runs from 0.1 to 0.9 of the atlas: from checker column 3.2 to 28.8, over
  // the 25 boundaries of columns 4 to 28; along v the same.
  const std::pair<int, int> middle{image.width * 3 / 4, image.height * 85 / 200};
  EXPECT_EQ(color_changes_through(image, middle, true), 25);
  EXPECT_EQ(color_changes_through(image, middle, false), 25);
}

TEST_F(AtlasPictureTest, EveryChartOfTheCubeHasADarkBoundary) {
  const CubeAtlas cube = cube_atlas();
  const fs::path png = scratch_.file("cube.png");
  write_atlas_picture(png, cube.mesh, cube.atlas);
  const testing::DecodedImage image = testing::decode_png(png);
  // Six white squares, each ringed by its boundary: no white pixel touches the background.
  const Rgb white = detail::conformal_color(1.0);
  const ColorRegion charts = region_of(image, 0, white);
  EXPECT_GT(charts.count, 6 * 10000);
  int white_beside_background = 0;
  for (int y = charts.top; y <= charts.bottom; ++y)
    for (int x = charts.left; x <= charts.right; ++x)
      if (image.at(x, y) == white)
        for (const auto& [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}})
          white_beside_background += testing::is_background(image.at(x + dx, y + dy)) ? 1 : 0;
  EXPECT_EQ(white_beside_background, 0);
  // The front side faces the viewer (the others are seen edge-on) and wears the checker.
  EXPECT_EQ(right_view_colors(image).size(), 2u);
}

TEST_F(AtlasPictureTest, RefusesBadArgumentsNamingTheProblemAndWritesNothing) {
  using Refusal = std::pair<Status, std::string>;  // Status::ok and "" when nothing is refused.
  const auto refusal = [&](const std::string& name, const Mesh& mesh, const TextureAtlas& atlas,
                           const AtlasPictureOptions& options = {}) -> Refusal {
    try {
      write_atlas_picture(scratch_.file(name), mesh, atlas, options);
    } catch (const Error& error) {
      return {error.status(), error.what()};
    }
    return {Status::ok, ""};
  };
  const auto expect_refused = [](const Refusal& refused, Status status,
                                 const std::string& problem) {
    EXPECT_EQ(refused.first, status) << refused.second;
    EXPECT_NE(refused.second.find("write_atlas_picture"), std::string::npos) << refused.second;
    EXPECT_NE(refused.second.find(problem), std::string::npos) << refused.second;
  };
  expect_refused(refusal("atlas.svg", square_, square_atlas_), Status::io_error, "PNG only");
  expect_refused(refusal("atlas.jpg", square_, square_atlas_), Status::io_error, "atlas.jpg");
  AtlasPictureOptions narrow;
  narrow.width = 100;
  expect_refused(refusal("narrow.png", square_, square_atlas_, narrow), Status::invalid_input,
                 "width 100 is outside [320, 16384]");

  TextureAtlas rows = square_atlas_;
  rows.corner_uv.conservativeResize(1, 6);
  expect_refused(refusal("rows.png", square_, rows), Status::invalid_input,
                 "corner_uv has 1 rows but the mesh has 2 faces");
  TextureAtlas chart_id = square_atlas_;
  chart_id.charts[0].faces = {0};
  chart_id.chart_of_face[1] = 3;
  expect_refused(refusal("chart.png", square_, chart_id), Status::invalid_input,
                 "face 1 is in chart 3, but the atlas has 1 charts");
  TextureAtlas not_finite = square_atlas_;
  not_finite.corner_uv(1, 3) = std::nan("");
  expect_refused(refusal("nan.png", square_, not_finite), Status::invalid_input,
                 "face 1 corner 1 has a UV that is not finite");
  TextureAtlas outside = square_atlas_;
  outside.corner_uv(0, 4) = 1.5;
  expect_refused(refusal("outside.png", square_, outside), Status::invalid_input,
                 "outside the atlas' [0, 1] square");
  Mesh bad_vertex = square_;
  bad_vertex.vertices(2, 0) = std::nan("");
  expect_refused(refusal("vertex.png", bad_vertex, square_atlas_), Status::invalid_input,
                 "mesh position of vertex 2 is not finite");
  Mesh bad_face = square_;
  bad_face.faces(1, 2) = 9;
  expect_refused(refusal("face.png", bad_face, square_atlas_), Status::invalid_input,
                 "refers to vertex 9");
  EXPECT_TRUE(fs::is_empty(scratch_.path()));
}

}  // namespace
}  // namespace harmonia
