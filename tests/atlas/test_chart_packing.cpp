// The chart packer (host/atlas/chart_packing.h), checked against rasterizations written here
// independently of it: texel centres strictly inside triangles (the evaluator's rule: no texel in
// two charts, and the coverage the packer reports), and closed texel squares touched by triangles
// (at least `padding` empty texels between two charts). Then the shape of the result: one density
// that fills the atlas with a single square, a thin tilted rectangle laid along an axis, the same
// answer for the same charts in any order, and bad input refused by name.

#include "atlas/chart_packing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "atlas/min_area_rectangle.h"
#include "atlas/texel_bitmap.h"
#include "harmonia/types.h"

namespace harmonia::detail {
namespace {

using Eigen::Vector2d;

// ---------------------------------------------------------------------------------------------
// Charts

//! A uniform number in [0, 1) from the engine's raw output (the standard fixes mt19937's output,
//! not that of its distributions), so that every platform packs the same charts.
double uniform(std::mt19937& engine) { return static_cast<double>(engine()) / 4294967296.0; }

void add_triangle(std::vector<Vector2d>& corners, const Vector2d& a, const Vector2d& b, const Vector2d& c) {
  corners.insert(corners.end(), {a, b, c});
}

void add_rectangle(std::vector<Vector2d>& corners, double left, double bottom, double right, double top) {
  add_triangle(corners, {left, bottom}, {right, bottom}, {right, top});
  add_triangle(corners, {left, bottom}, {right, top}, {left, top});
}

//! A convex polygon (centre, radius, corners) as a fan of counter-clockwise triangles.
void add_disc(std::vector<Vector2d>& corners, double radius, int sides) {
  for (int side = 0; side < sides; ++side) {
    const double from = 2 * std::numbers::pi * side / sides, to = 2 * std::numbers::pi * (side + 1) / sides;
    add_triangle(corners, Vector2d::Zero(), radius * Vector2d(std::cos(from), std::sin(from)),
                 radius * Vector2d(std::cos(to), std::sin(to)));
  }
}

Eigen::MatrixX2d as_chart(const std::vector<Vector2d>& corners, double angle = 0.0,
                          const Vector2d& shift = Vector2d::Zero()) {
  const Eigen::Rotation2Dd turn(angle);
  Eigen::MatrixX2d chart(static_cast<Eigen::Index>(corners.size()), 2);
  for (std::size_t row = 0; row < corners.size(); ++row) chart.row(row) = (turn * corners[row] + shift).transpose();
  return chart;
}

enum class Shape { rectangle, l_shape, sliver, disc, blob };

//! A chart of the given shape and about `size` across, turned and moved at random.
Eigen::MatrixX2d random_chart(Shape shape, double size, std::mt19937& engine) {
  std::vector<Vector2d> corners;
  switch (shape) {
    case Shape::rectangle:
      add_rectangle(corners, 0, 0, size * (0.4 + uniform(engine)), size * (0.4 + uniform(engine)));
      break;
    case Shape::l_shape: {
      const double width = size * (0.6 + uniform(engine)), height = size * (0.6 + uniform(engine));
      const double thickness = size * (0.15 + 0.25 * uniform(engine));
      add_rectangle(corners, 0, 0, width, thickness);
      add_rectangle(corners, 0, thickness, thickness, height);
      break;
    }
    case Shape::sliver:
      add_rectangle(corners, 0, 0, 2.5 * size, size * (0.04 + 0.08 * uniform(engine)));
      break;
    case Shape::disc:
      add_disc(corners, 0.5 * size, 24);
      break;
    case Shape::blob: {
      // Star-shaped about its centre, not convex: a radius that waves around the circle.
      constexpr int sides = 16;
      const double wave = 0.35 * uniform(engine), phase = 2 * std::numbers::pi * uniform(engine);
      std::vector<Vector2d> ring;
      for (int side = 0; side < sides; ++side) {
        const double angle = 2 * std::numbers::pi * side / sides;
        const double radius = 0.5 * size * (1.0 + wave * std::cos(3 * angle + phase));
        ring.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
      }
      for (int side = 0; side < sides; ++side) {
        add_triangle(corners, Vector2d::Zero(), ring[side], ring[(side + 1) % sides]);
      }
      break;
    }
  }
  const double turn = 2 * std::numbers::pi * uniform(engine);
  const Vector2d shift(100 * uniform(engine), -50 * uniform(engine));
  return as_chart(corners, turn, shift);
}

//! `count` charts of the given shapes in turn, their sizes spread over a factor of about 7 (a
//! log-uniform spread, as in real atlases: a few big charts and many small ones).
std::vector<Eigen::MatrixX2d> random_charts(int count, const std::vector<Shape>& shapes, unsigned seed) {
  std::mt19937 engine(seed);
  std::vector<Eigen::MatrixX2d> charts;
  for (int chart = 0; chart < count; ++chart) {
    const double size = std::exp(2.0 * uniform(engine) - 1.0);
    charts.push_back(random_chart(shapes[chart % shapes.size()], size, engine));
  }
  return charts;
}

// ---------------------------------------------------------------------------------------------
// Independent rasterizations of a packing

struct PlacedTriangle {
  int chart = 0;
  int page = 0;
  Vector2d corners[3];
};

std::vector<PlacedTriangle> placed_triangles(const std::vector<Eigen::MatrixX2d>& charts,
                                             const ChartPacking& packing) {
  std::vector<PlacedTriangle> triangles;
  for (std::size_t chart = 0; chart < charts.size(); ++chart) {
    const ChartPlacement& placement = packing.placements[chart];
    const Eigen::Matrix2d map = packing.texels_per_unit * Eigen::Rotation2Dd(placement.angle).toRotationMatrix();
    for (Eigen::Index row = 0; row + 2 < charts[chart].rows(); row += 3) {
      PlacedTriangle triangle;
      triangle.chart = static_cast<int>(chart);
      triangle.page = placement.page;
      for (int corner = 0; corner < 3; ++corner) {
        triangle.corners[corner] = map * charts[chart].row(row + corner).transpose() + placement.offset;
      }
      triangles.push_back(triangle);
    }
  }
  return triangles;
}

double cross(const Vector2d& from, const Vector2d& to, const Vector2d& point) {
  return (to.x() - from.x()) * (point.y() - from.y()) - (to.y() - from.y()) * (point.x() - from.x());
}

//! Texels whose centre lies strictly inside a triangle (atlaseval.py's rule), each with its chart.
struct CentreImage {
  std::vector<int> owner;  //!< -1: none
  long long covered = 0;
  long long in_two_charts = 0;
};

CentreImage rasterize_centres(const std::vector<PlacedTriangle>& triangles, int width, int height) {
  CentreImage image;
  image.owner.assign(static_cast<std::size_t>(width) * height, -1);
  for (const PlacedTriangle& triangle : triangles) {
    Vector2d a = triangle.corners[0], b = triangle.corners[1], c = triangle.corners[2];
    const double twice_area = cross(a, b, c);
    if (twice_area == 0.0) continue;
    if (twice_area < 0.0) std::swap(b, c);
    const int first_x = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int last_x = std::min(width - 1, static_cast<int>(std::floor(std::max({a.x(), b.x(), c.x()}))));
    const int first_y = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int last_y = std::min(height - 1, static_cast<int>(std::floor(std::max({a.y(), b.y(), c.y()}))));
    for (int y = first_y; y <= last_y; ++y) {
      for (int x = first_x; x <= last_x; ++x) {
        const Vector2d centre(x + 0.5, y + 0.5);
        if (!(cross(a, b, centre) > 0 && cross(b, c, centre) > 0 && cross(c, a, centre) > 0)) continue;
        int& owner = image.owner[static_cast<std::size_t>(y) * width + x];
        if (owner < 0) {
          owner = triangle.chart;
          ++image.covered;
        } else if (owner != triangle.chart) {
          ++image.in_two_charts;
        }
      }
    }
  }
  return image;
}

//! Whether the closed texel square [x, x + 1] x [y, y + 1] meets the closed triangle: separating
//! axes, the square's two (its box against the triangle's) and the triangle's three edge normals.
bool square_meets_triangle(int x, int y, const Vector2d& a, const Vector2d& b, const Vector2d& c) {
  if (std::max({a.x(), b.x(), c.x()}) < x || std::min({a.x(), b.x(), c.x()}) > x + 1) return false;
  if (std::max({a.y(), b.y(), c.y()}) < y || std::min({a.y(), b.y(), c.y()}) > y + 1) return false;
  const Vector2d square[4] = {{x, y}, {x + 1.0, y}, {x, y + 1.0}, {x + 1.0, y + 1.0}};
  const Vector2d corners[3] = {a, b, c};
  for (int edge = 0; edge < 3; ++edge) {
    const Vector2d& from = corners[edge];
    const Vector2d& to = corners[(edge + 1) % 3];
    const Vector2d& opposite = corners[(edge + 2) % 3];
    const double inside_sign = cross(from, to, opposite);
    if (inside_sign == 0.0) continue;  // a degenerate triangle: its box settles it
    bool all_outside = true;
    for (const Vector2d& corner : square) all_outside = all_outside && cross(from, to, corner) * inside_sign < 0.0;
    if (all_outside) return false;
  }
  return true;
}

//! Per texel, the chart whose closed triangles touch its square (-1: none); fails the test where
//! two charts touch one texel.
std::vector<int> rasterize_conservatively(const std::vector<PlacedTriangle>& triangles, int width, int height) {
  std::vector<int> owner(static_cast<std::size_t>(width) * height, -1);
  for (const PlacedTriangle& triangle : triangles) {
    const Vector2d& a = triangle.corners[0];
    const Vector2d& b = triangle.corners[1];
    const Vector2d& c = triangle.corners[2];
    const int first_x = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))) - 1);
    const int last_x = std::min(width - 1, static_cast<int>(std::floor(std::max({a.x(), b.x(), c.x()}))));
    const int first_y = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))) - 1);
    const int last_y = std::min(height - 1, static_cast<int>(std::floor(std::max({a.y(), b.y(), c.y()}))));
    for (int y = first_y; y <= last_y; ++y) {
      for (int x = first_x; x <= last_x; ++x) {
        if (!square_meets_triangle(x, y, a, b, c)) continue;
        int& texel = owner[static_cast<std::size_t>(y) * width + x];
        EXPECT_TRUE(texel < 0 || texel == triangle.chart)
            << "charts " << texel << " and " << triangle.chart << " both touch texel (" << x << ", " << y << ")";
        texel = triangle.chart;
      }
    }
  }
  return owner;
}

//! How many texels touched by one chart have a texel touched by another chart within `padding`
//! texels along both axes, the atlas wrapping around at its edges as a texture sampled with
//! wrapping does (the packer's promise: none).
long long texels_too_close(const std::vector<int>& owner, int width, int height, int padding) {
  long long too_close = 0;
  const auto wrapped = [](int k, int size) { return ((k % size) + size) % size; };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int chart = owner[static_cast<std::size_t>(y) * width + x];
      if (chart < 0) continue;
      bool close = false;
      for (int near_y = y - padding; near_y <= y + padding && !close; ++near_y) {
        for (int near_x = x - padding; near_x <= x + padding; ++near_x) {
          const int other = owner[static_cast<std::size_t>(wrapped(near_y, height)) * width + wrapped(near_x, width)];
          if (other >= 0 && other != chart) {
            close = true;
            break;
          }
        }
      }
      too_close += close ? 1 : 0;
    }
  }
  return too_close;
}

//! Every check of a packing that needs no expectation of its coverage; returns the coverage the
//! independent rasterization measures.
double check_packing(const std::vector<Eigen::MatrixX2d>& charts, const ChartPacking& packing,
                     const PackingOptions& options) {
  EXPECT_EQ(packing.placements.size(), charts.size());
  EXPECT_GT(packing.texels_per_unit, 0.0);
  const std::vector<PlacedTriangle> triangles = placed_triangles(charts, packing);
  // Every corner inside [margin, width - margin] x [margin, height - margin], the margin half the
  // padding rounded up, so that two charts facing each other across an edge of a wrapping texture
  // are `padding` apart (up to the rounding of the final coordinates, far below a millionth of a
  // texel).
  const int width = options.resolution, height = options.height > 0 ? options.height : options.resolution;
  const int margin = (options.padding + 1) / 2;
  constexpr double rounding = 1e-9;
  for (const PlacedTriangle& triangle : triangles) {
    for (const Vector2d& corner : triangle.corners) {
      EXPECT_GE(corner.minCoeff(), margin - rounding) << "chart " << triangle.chart;
      EXPECT_LE(corner.x(), width - margin + rounding) << "chart " << triangle.chart;
      EXPECT_LE(corner.y(), height - margin + rounding) << "chart " << triangle.chart;
    }
  }
  // Page by page: no texel in two charts, none too close, the coverage as measured.
  EXPECT_GE(packing.pages, 1);
  EXPECT_EQ(packing.page_coverage.size(), static_cast<std::size_t>(packing.pages));
  const double texels = static_cast<double>(width) * height;
  long long covered = 0;
  for (int page = 0; page < packing.pages; ++page) {
    std::vector<PlacedTriangle> on_page;
    for (const PlacedTriangle& triangle : triangles) {
      EXPECT_TRUE(triangle.page >= 0 && triangle.page < packing.pages) << "chart " << triangle.chart;
      if (triangle.page == page) on_page.push_back(triangle);
    }
    EXPECT_FALSE(on_page.empty()) << "page " << page << " holds no chart";
    const CentreImage centres = rasterize_centres(on_page, width, height);
    EXPECT_EQ(centres.in_two_charts, 0) << "page " << page;
    EXPECT_EQ(packing.page_coverage[static_cast<std::size_t>(page)], static_cast<double>(centres.covered) / texels);
    covered += centres.covered;
    const std::vector<int> touched = rasterize_conservatively(on_page, width, height);
    EXPECT_EQ(texels_too_close(touched, width, height, options.padding), 0) << "page " << page;
  }
  const double coverage = static_cast<double>(covered) / (texels * packing.pages);
  EXPECT_EQ(packing.coverage, coverage);
  return coverage;
}

// ---------------------------------------------------------------------------------------------
// Tests

TEST(ChartPacking, OneSquareFillsTheAtlasAtTheLargestDensity) {
  PackingOptions options;
  options.resolution = 256;
  options.padding = 2;
  constexpr double side = 3.0;
  std::vector<Vector2d> corners;
  add_rectangle(corners, 0, 0, side, side);
  // Tilted, so that the packer has to find the turn that lays it along the axes.
  const std::vector<Eigen::MatrixX2d> charts = {as_chart(corners, 0.3, Vector2d(-7, 11))};
  const ChartPacking packing = pack_charts(charts, options);
  // A margin of half the padding along each edge.
  const double inside = options.resolution - 2 * (options.padding / 2);
  EXPECT_NEAR(packing.texels_per_unit, inside / side, 0.01 * inside / side);
  EXPECT_GT(packing.coverage, 0.975);  // (254 / 256)^2 = 0.984, less the texels on the edges
  check_packing(charts, packing, options);
}

//! A ring (inner and outer radius, `sides` segments) as counter-clockwise triangles.
void add_ring(std::vector<Vector2d>& corners, double inner, double outer, int sides) {
  for (int side = 0; side < sides; ++side) {
    const Vector2d from(std::cos(2 * std::numbers::pi * side / sides), std::sin(2 * std::numbers::pi * side / sides));
    const Vector2d to(std::cos(2 * std::numbers::pi * (side + 1) / sides),
                      std::sin(2 * std::numbers::pi * (side + 1) / sides));
    add_triangle(corners, inner * from, outer * from, outer * to);
    add_triangle(corners, inner * from, outer * to, inner * to);
  }
}

// A thin ring of radius 1 and four squares of side 0.6, each of more area than the ring: largest
// first places the squares and then the ring beside them, leaving its inside empty. A 2 x 2 block
// of the squares (1.2 wide, corners 0.85 from its centre) fits inside the ring (radius 0.95), so
// the atlas needs only the ring's 2 x 2 box, and the packer finds it by placing the widest box
// first: the density comes out above the 252 / 2.6 that any layout with the ring beside a
// square (2 + 0.6 side by side) allows.
TEST(ChartPacking, ChartsFillTheInsideOfARing) {
  PackingOptions options;
  options.resolution = 256;
  options.padding = 2;
  std::vector<Vector2d> ring;
  add_ring(ring, 0.95, 1.0, 96);
  std::vector<Eigen::MatrixX2d> charts = {as_chart(ring)};
  for (int k = 0; k < 4; ++k) {
    std::vector<Vector2d> square;
    add_rectangle(square, 0, 0, 0.6, 0.6);
    charts.push_back(as_chart(square, 0.0, Vector2d(3.0 * k, 5.0)));
  }
  const ChartPacking packing = pack_charts(charts, options);
  const double inside = options.resolution - 2 * (options.padding / 2);
  EXPECT_GT(packing.texels_per_unit, inside / 2.6);
  check_packing(charts, packing, options);
}

// At a fixed density, squares that do not fit one page go on further pages: three squares each
// wider than half the page take a page each, twelve small ones fill the gaps of the first, and
// a page limit or a square wider than a page is refused.
TEST(ChartPacking, ChartsThatDoNotFitOnePageOpenMorePages) {
  PackingOptions options;
  options.resolution = 128;
  options.padding = 2;
  options.fixed_scale = 10.0;  // texels per unit
  options.max_pages = 0;
  std::vector<Eigen::MatrixX2d> charts;
  for (int k = 0; k < 3; ++k) {
    std::vector<Vector2d> corners;
    add_rectangle(corners, 0, 0, 8.0, 8.0);  // 80 texels a side: two cannot share 126 inside
    charts.push_back(as_chart(corners, 0.1 * k, Vector2d(k, -k)));
  }
  for (int k = 0; k < 12; ++k) {
    std::vector<Vector2d> corners;
    add_rectangle(corners, 0, 0, 1.0, 1.0);  // 10 texels a side
    charts.push_back(as_chart(corners, 0.0, Vector2d(2 * k, 0)));
  }
  const ChartPacking packing = pack_charts(charts, options);
  EXPECT_EQ(packing.texels_per_unit, 10.0);
  EXPECT_EQ(packing.pages, 3);
  std::set<int> pages_of_large;
  for (int k = 0; k < 3; ++k) pages_of_large.insert(packing.placements[static_cast<std::size_t>(k)].page);
  EXPECT_EQ(pages_of_large.size(), 3u);
  // Charts go to the first page with room: the small ones fit around the first large one.
  for (std::size_t k = 3; k < charts.size(); ++k) EXPECT_EQ(packing.placements[k].page, 0) << "chart " << k;
  check_packing(charts, packing, options);

  options.max_pages = 2;
  EXPECT_THROW((void)pack_charts(charts, options), Error);
  options.max_pages = 1;
  EXPECT_THROW((void)pack_charts(charts, options), Error);
  options.max_pages = 0;
  EXPECT_TRUE(fits_one_page(charts[0], options));
  options.fixed_scale = 16.0;  // 128 texels a side: more than the 126 inside
  EXPECT_FALSE(fits_one_page(charts[0], options));
  EXPECT_THROW((void)pack_charts(charts, options), Error);
}

// A non-square atlas: a 10 x 1 rectangle fills a 256 x 32 atlas along its width (turned there
// from upright), and random charts pack into 512 x 128 as into a square, apart and inside.
TEST(ChartPacking, ANonSquareAtlasIsFilledAlongItsLongerSide) {
  std::vector<Vector2d> corners;
  add_rectangle(corners, 0, 0, 1.0, 10.0);
  const std::vector<Eigen::MatrixX2d> rod = {as_chart(corners, 0.0, Vector2d(0, 0))};
  PackingOptions options;
  options.resolution = 256;
  options.height = 32;
  options.padding = 2;
  const ChartPacking packing = pack_charts(rod, options);
  // Along the width, 10 units fill the 254 texels inside a margin of 1 (the 30 inside the height
  // cap 1 unit at 30 texels, higher than 25.4).
  EXPECT_NEAR(packing.texels_per_unit, (256 - 2 * 1) / 10.0, 0.01 * (256 - 2 * 1) / 10.0);
  check_packing(rod, packing, options);
  options.height = 16;  // 14 inside: the rod's thickness caps the density at 14 texels per unit
  EXPECT_NEAR(pack_charts(rod, options).texels_per_unit, 14.0, 0.01 * 14.0);

  const std::vector<Eigen::MatrixX2d> charts = random_charts(120, {Shape::rectangle, Shape::disc, Shape::blob}, 3);
  options.resolution = 512;
  options.height = 128;
  const double coverage = check_packing(charts, pack_charts(charts, options), options);
  EXPECT_GT(coverage, 0.5);
  options.height = 8;  // below the smallest side
  EXPECT_THROW((void)pack_charts(charts, options), Error);
}

TEST(ChartPacking, ALongThinRectangleTiltedBy30DegreesLiesAlongAnAxis) {
  std::vector<Vector2d> corners;
  add_rectangle(corners, 0, 0, 10.0, 1.0);
  const double tilt = std::numbers::pi / 6;
  const std::vector<Eigen::MatrixX2d> charts = {as_chart(corners, tilt, Vector2d(5, 5))};
  PackingOptions options;
  options.resolution = 128;
  const ChartPacking packing = pack_charts(charts, options);
  // Its angle undoes the tilt, up to quarter turns.
  const double quarter_turn = std::numbers::pi / 2;
  EXPECT_NEAR(std::remainder(packing.placements[0].angle + tilt, quarter_turn), 0.0, 1e-12);
  // Along an axis, 10 units fill the inside of the atlas (a margin of 1 along each edge).
  EXPECT_NEAR(packing.texels_per_unit, (128 - 2 * 1) / 10.0, 0.01 * (128 - 2 * 1) / 10.0);
  check_packing(charts, packing, options);
}

TEST(ChartPacking, RandomRectanglesPackWithoutOverlapAndCoverMostOfTheAtlas) {
  const std::vector<Eigen::MatrixX2d> charts = random_charts(200, {Shape::rectangle}, 1);
  PackingOptions options;
  options.resolution = 512;
  options.padding = 2;
  const ChartPacking packing = pack_charts(charts, options);
  const double coverage = check_packing(charts, packing, options);
  // Measured 0.799: at about 32 x 32 texels a chart, the padding (2 texels) and the texel a
  // chart's edge only touches take about a sixth of the atlas whatever the packing.
  EXPECT_GT(coverage, 0.75);
}

TEST(ChartPacking, MixedShapesPackWithoutOverlap) {
  const std::vector<Eigen::MatrixX2d> charts =
      random_charts(300, {Shape::rectangle, Shape::l_shape, Shape::sliver, Shape::disc, Shape::blob}, 2);
  PackingOptions options;
  options.resolution = 512;
  options.padding = 2;
  const ChartPacking packing = pack_charts(charts, options);
  const double coverage = check_packing(charts, packing, options);
  // Measured 0.682 (between discs and blobs lie gaps that only the smallest charts fill).
  EXPECT_GT(coverage, 0.63);
}

TEST(ChartPacking, EveryPaddingKeepsChartsApart) {
  const std::vector<Eigen::MatrixX2d> charts =
      random_charts(60, {Shape::l_shape, Shape::blob, Shape::sliver}, 3);
  for (const int padding : {0, 1, 3, 4}) {  // odd ones: a margin of half, rounded up
    PackingOptions options;
    options.resolution = 200;  // not a whole number of 64-texel words
    options.padding = padding;
    const ChartPacking packing = pack_charts(charts, options);
    SCOPED_TRACE("padding " + std::to_string(padding));
    check_packing(charts, packing, options);
  }
}

TEST(ChartPacking, TheSameChartsGiveTheSamePlacementsInAnyOrder) {
  const std::vector<Eigen::MatrixX2d> charts =
      random_charts(120, {Shape::rectangle, Shape::l_shape, Shape::blob}, 4);
  PackingOptions options;
  options.resolution = 256;
  const ChartPacking first = pack_charts(charts, options);
  const ChartPacking again = pack_charts(charts, options);
  EXPECT_EQ(first.texels_per_unit, again.texels_per_unit);
  for (std::size_t chart = 0; chart < charts.size(); ++chart) {
    EXPECT_EQ(first.placements[chart].angle, again.placements[chart].angle);
    EXPECT_EQ(first.placements[chart].offset, again.placements[chart].offset);
  }
  // Reversed and shuffled: no two charts here are the same size, so the order the packer takes
  // them in, and so every placement, is the same.
  std::vector<int> permutation(charts.size());
  std::iota(permutation.begin(), permutation.end(), 0);
  std::mt19937 engine(5);
  for (std::size_t index = permutation.size() - 1; index > 0; --index) {
    std::swap(permutation[index], permutation[engine() % (index + 1)]);
  }
  std::vector<Eigen::MatrixX2d> permuted;
  for (const int chart : permutation) permuted.push_back(charts[chart]);
  const ChartPacking shuffled = pack_charts(permuted, options);
  EXPECT_EQ(shuffled.texels_per_unit, first.texels_per_unit);
  EXPECT_EQ(shuffled.coverage, first.coverage);
  for (std::size_t index = 0; index < permutation.size(); ++index) {
    const ChartPlacement& expected = first.placements[permutation[index]];
    EXPECT_EQ(shuffled.placements[index].angle, expected.angle) << "chart " << permutation[index];
    EXPECT_EQ(shuffled.placements[index].offset, expected.offset) << "chart " << permutation[index];
  }
}

TEST(ChartPacking, TheSamePlacementsOnAnyNumberOfThreads) {
  // Two densities are tried side by side on two threads, one after the other on one: the same
  // trials, so the same packing, and the same number of trials.
  const std::vector<Eigen::MatrixX2d> charts =
      random_charts(150, {Shape::rectangle, Shape::l_shape, Shape::blob, Shape::sliver}, 6);
  PackingOptions options;
  options.resolution = 300;
  options.threads = 1;
  const ChartPacking alone = pack_charts(charts, options);
  check_packing(charts, alone, options);
  for (const int threads : {2, 3, 4}) {
    options.threads = threads;
    const ChartPacking packing = pack_charts(charts, options);
    SCOPED_TRACE("threads " + std::to_string(threads));
    EXPECT_EQ(packing.texels_per_unit, alone.texels_per_unit);
    EXPECT_EQ(packing.trials, alone.trials);
    EXPECT_EQ(packing.coverage, alone.coverage);
    for (std::size_t chart = 0; chart < charts.size(); ++chart) {
      EXPECT_EQ(packing.placements[chart].angle, alone.placements[chart].angle) << "chart " << chart;
      EXPECT_EQ(packing.placements[chart].offset, alone.placements[chart].offset) << "chart " << chart;
    }
  }
}

TEST(ChartPacking, ChartsOfNoExtentAndDegenerateTrianglesArePlaced) {
  std::vector<Vector2d> point = {{1, 1}, {1, 1}, {1, 1}};
  std::vector<Vector2d> segment = {{0, 0}, {2, 0}, {1, 0}};
  std::vector<Vector2d> square;
  add_rectangle(square, 0, 0, 1, 1);
  const std::vector<Eigen::MatrixX2d> charts = {as_chart(point), as_chart(segment), as_chart(square)};
  PackingOptions options;
  options.resolution = 64;
  const ChartPacking packing = pack_charts(charts, options);
  check_packing(charts, packing, options);
}

TEST(ChartPacking, BadInputIsRefusedByName) {
  std::vector<Vector2d> corners;
  add_rectangle(corners, 0, 0, 1, 1);
  const Eigen::MatrixX2d square = as_chart(corners);
  auto refusal = [](const std::vector<Eigen::MatrixX2d>& charts, const PackingOptions& options) -> std::string {
    try {
      (void)pack_charts(charts, options);
    } catch (const Error& error) {
      EXPECT_EQ(error.status(), Status::invalid_input);
      return error.what();
    }
    ADD_FAILURE() << "accepted";
    return "";
  };
  PackingOptions options;
  options.resolution = 8;
  EXPECT_NE(refusal({square}, options).find("resolution"), std::string::npos);
  options.resolution = 65536;
  EXPECT_NE(refusal({square}, options).find("resolution"), std::string::npos);
  options.resolution = 64;
  options.padding = -1;
  EXPECT_NE(refusal({square}, options).find("padding"), std::string::npos);
  options.padding = 65;
  EXPECT_NE(refusal({square}, options).find("padding"), std::string::npos);
  options.padding = 2;
  EXPECT_NE(refusal({}, options).find("no chart"), std::string::npos);
  Eigen::MatrixX2d four_rows(4, 2);
  four_rows.setZero();
  EXPECT_NE(refusal({square, four_rows}, options).find("chart 1"), std::string::npos);
  Eigen::MatrixX2d not_finite = square;
  not_finite(2, 1) = std::numeric_limits<double>::quiet_NaN();
  const std::string message = refusal({square, not_finite}, options);
  EXPECT_NE(message.find("chart 1, row 2"), std::string::npos) << message;
  // More charts than single texels, `padding` apart, fit in the atlas.
  options.resolution = 16;
  EXPECT_NE(refusal(std::vector<Eigen::MatrixX2d>(100, square), options).find("cannot fit"), std::string::npos);
}

TEST(ChartPacking, TheTightestBoxOfAConvexHull) {
  // A 4 x 1 rectangle turned by 0.4 rad: its hull has its 4 corners, its tightest box is itself.
  std::vector<Vector2d> points;
  const Eigen::Rotation2Dd turn(0.4);
  for (const Vector2d& corner : {Vector2d(0, 0), Vector2d(4, 0), Vector2d(4, 1), Vector2d(0, 1), Vector2d(2, 0.5)}) {
    points.push_back(turn * corner);
  }
  const std::vector<Vector2d> hull = convex_hull(points);
  EXPECT_EQ(hull.size(), 4u);
  const OrientedRectangle box = min_area_rectangle(hull);
  EXPECT_NEAR(box.angle, -0.4, 1e-12);
  EXPECT_NEAR(box.width, 4.0, 1e-12);
  EXPECT_NEAR(box.height, 1.0, 1e-12);
}

// The turn, done 64 x 64 texels at a time, against its definition texel by texel, on random
// images of every size around the word's edges.
TEST(ChartPacking, QuarterTurnsMoveEveryTexelWhereTheDefinitionSays) {
  std::mt19937 random(7);
  for (const int width : {1, 5, 63, 64, 65, 130, 200})
    for (const int height : {1, 7, 63, 64, 65, 129, 190}) {
      TexelBitmap bitmap(width, height);
      std::bernoulli_distribution set(0.3);
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          if (set(random)) bitmap.set(x, y);
      const TexelBitmap turned = bitmap.quarter_turned();
      ASSERT_EQ(turned.width(), height);
      ASSERT_EQ(turned.height(), width);
      EXPECT_EQ(turned.count(), bitmap.count()) << width << " x " << height;
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          ASSERT_EQ(turned.test(height - 1 - y, x), bitmap.test(x, y)) << width << " x " << height << " at " << x << ", " << y;
    }
}

TEST(ChartPacking, TexelBitmapsTurnAndGrowAsTheGridDoes) {
  TexelBitmap bitmap(70, 3);  // wider than a word
  bitmap.set(0, 0);
  bitmap.set(69, 2);
  const TexelBitmap turned = bitmap.quarter_turned();  // (x, y) -> (height - 1 - y, x)
  EXPECT_EQ(turned.width(), 3);
  EXPECT_EQ(turned.height(), 70);
  EXPECT_TRUE(turned.test(2, 0));
  EXPECT_TRUE(turned.test(0, 69));
  EXPECT_EQ(turned.count(), 2);
  TexelBitmap grown(70, 5);
  grown.set(63, 2);  // at a word's last bit
  grown.dilate(1);
  EXPECT_EQ(grown.count(), 9);
  for (int y = 1; y <= 3; ++y) {
    for (int x = 62; x <= 64; ++x) EXPECT_TRUE(grown.test(x, y)) << x << ", " << y;
  }
}

}  // namespace
}  // namespace harmonia::detail
