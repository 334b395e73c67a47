// Pictures of spherical maps: the PNG decodes to the requested size with the sphere drawn as two
// disks on the background, coloured by area distortion, with triangles turned over on the sphere
// shown in the marker colour and the date line in its own colour; the same map gives the same
// bytes; bad arguments are refused before anything is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "harmonia/procedural.h"
#include "harmonia/sphere_picture.h"
#include "harmonia/spherical_metrics.h"
#include "harmonia/types.h"
#include "picture/color_map.h"
#include "support/decoded_png.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;
using detail::Rgb;

// The date line's core colour, as host/picture/sphere_picture.cpp draws it.
constexpr Rgb kDateLineCore{255, 204, 0};

class SpherePictureTest : public ::testing::Test {
 protected:
  testing::ScratchFolder scratch_{"sphere-picture"};
};

// The icosphere mapped onto itself, with its topmost and bottommost vertices as poles and a date
// line along edges between them (each step to the neighbour nearest the south pole).
struct SphereMap {
  Mesh mesh;
  Eigen::MatrixX3d points;
  SpherePictureOptions options;
};

SphereMap identity_map(int subdivisions = 3) {
  SphereMap map;
  map.mesh = unit_sphere(subdivisions);
  map.points = map.mesh.vertices;
  Eigen::Index north = 0, south = 0;
  map.mesh.vertices.col(2).maxCoeff(&north);
  map.mesh.vertices.col(2).minCoeff(&south);
  map.options.north_pole = static_cast<int>(north);
  map.options.south_pole = static_cast<int>(south);
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(map.mesh.vertex_count()));
  for (Eigen::Index f = 0; f < map.mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      neighbours[map.mesh.faces(f, k)].push_back(map.mesh.faces(f, (k + 1) % 3));
  const Eigen::Vector3d target = map.mesh.vertices.row(south);
  int at = static_cast<int>(north);
  map.options.date_line = {at};
  while (at != south && map.options.date_line.size() < neighbours.size()) {
    at = *std::min_element(neighbours[at].begin(), neighbours[at].end(), [&](int a, int b) {
      return (map.mesh.vertices.row(a).transpose() - target).norm() <
             (map.mesh.vertices.row(b).transpose() - target).norm();
    });
    map.options.date_line.push_back(at);
  }
  return map;
}

bool is_background(const Rgb& color) { return color == detail::kBackground; }

// How many pixels of `color` the views hold (the band between the title and the legend: the
// legend has a swatch of every marker).
int count_in_views(const testing::DecodedImage& image, const Rgb& color) {
  int count = 0;
  for (int y = image.height / 12; y < image.height * 85 / 100; ++y)
    for (int x = 0; x < image.width; ++x) count += image.at(x, y) == color;
  return count;
}

TEST_F(SpherePictureTest, DrawsTheTwoSidesAsDisksOnTheBackgroundAtTheRequestedSize) {
  const SphereMap map = identity_map();
  const fs::path path = scratch_.file("sphere.png");
  write_sphere_picture(path, map.mesh, map.points, map.options);
  const testing::DecodedImage image = testing::decode_png(path);
  ASSERT_EQ(image.width, 1600);
  ASSERT_EQ(image.height, 900);
  for (const auto& [x, y] : testing::corner_pixels(image))
    EXPECT_TRUE(is_background(image.at(x, y))) << "corner " << x << ", " << y;
  // Between the views there is background; around each view's middle the sphere, in every
  // direction out to a third of its half of the picture.
  EXPECT_TRUE(is_background(image.at(image.width / 2, image.height / 2)));
  for (const int centre_x : {image.width / 4, 3 * image.width / 4}) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        const int x = centre_x + dx * image.width / 12,
                  y = image.height / 2 + dy * image.width / 12;
        EXPECT_FALSE(is_background(image.at(x, y))) << "pixel " << x << ", " << y;
      }
    }
    // Each disk's row through its middle: one run of sphere, as wide as most of the height.
    int first = -1, last = -1;
    for (int x = centre_x - image.width / 4 + 1; x < centre_x + image.width / 4 - 1; ++x) {
      if (is_background(image.at(x, image.height / 2))) continue;
      if (first < 0) first = x;
      last = x;
    }
    EXPECT_GT(last - first, image.height / 2) << "disk around x = " << centre_x;
  }
}

TEST_F(SpherePictureTest, AnUndistortedMapIsWhiteAndAShiftedOneShrinksOneSideAndEnlargesTheOther) {
  const SphereMap map = identity_map();
  EXPECT_EQ(sphere_picture_headline(spherical_metrics(map.mesh, map.points)),
            "0 flipped, area distortion 0.00");
  // Shaded white (all channels equal) and no strongly coloured pixel.
  const auto coloured = [](const testing::DecodedImage& image, bool red) {
    int count = 0;
    for (int y = image.height / 12; y < image.height * 85 / 100; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const Rgb c = image.at(x, y);
        const int hue = red ? c.red : c.blue;
        count += hue > c.green + 60 && hue > (red ? c.blue : c.red) + 60;
      }
    }
    return count;
  };
  const fs::path undistorted = scratch_.file("undistorted.png");
  write_sphere_picture(undistorted, map.mesh, map.points, map.options);
  const testing::DecodedImage plain = testing::decode_png(undistorted);
  EXPECT_EQ(coloured(plain, true), 0);
  EXPECT_EQ(coloured(plain, false), 0);

  // Points pushed towards the north pole: the north shrinks (blue), the south grows (red).
  Eigen::MatrixX3d shifted = map.points;
  for (Eigen::Index v = 0; v < shifted.rows(); ++v) {
    shifted(v, 2) += 0.6;
    shifted.row(v).normalize();
  }
  const fs::path distorted = scratch_.file("distorted.png");
  write_sphere_picture(distorted, map.mesh, shifted, map.options);
  const testing::DecodedImage image = testing::decode_png(distorted);
  EXPECT_GT(coloured(image, true), 10000);
  EXPECT_GT(coloured(image, false), 10000);
}

TEST_F(SpherePictureTest, TrianglesTurnedOverShowInTheMarkerColourAndAreCounted) {
  const SphereMap map = identity_map();
  const fs::path good = scratch_.file("good.png");
  write_sphere_picture(good, map.mesh, map.points, map.options);
  EXPECT_EQ(count_in_views(testing::decode_png(good), detail::kFlippedOutline), 0);

  // Two neighbours swap places: the triangles on their common edge turn over.
  Eigen::MatrixX3d swapped = map.points;
  const int a = map.mesh.faces(100, 0), b = map.mesh.faces(100, 1);
  swapped.row(a) = map.points.row(b);
  swapped.row(b) = map.points.row(a);
  const SphericalMetrics metrics = spherical_metrics(map.mesh, swapped);
  ASSERT_GT(metrics.flipped_triangles, 0);
  EXPECT_EQ(sphere_picture_headline(metrics).rfind(
                std::to_string(metrics.flipped_triangles) + " flipped, area distortion ", 0),
            0u);
  const fs::path bad = scratch_.file("bad.png");
  write_sphere_picture(bad, map.mesh, swapped, map.options);
  EXPECT_GT(count_in_views(testing::decode_png(bad), detail::kFlippedOutline), 50);
}

TEST_F(SpherePictureTest, TheDateLineIsDrawnInItsColour) {
  SphereMap map = identity_map();
  const fs::path with = scratch_.file("with.png");
  write_sphere_picture(with, map.mesh, map.points, map.options);
  EXPECT_GT(count_in_views(testing::decode_png(with), kDateLineCore), 200);
  map.options.date_line.clear();
  const fs::path without = scratch_.file("without.png");
  write_sphere_picture(without, map.mesh, map.points, map.options);
  EXPECT_EQ(count_in_views(testing::decode_png(without), kDateLineCore), 0);
}

TEST_F(SpherePictureTest, TheSameMapGivesTheSameBytes) {
  const SphereMap map = identity_map();
  Eigen::MatrixX3d shifted = map.points;
  for (Eigen::Index v = 0; v < shifted.rows(); ++v) {
    shifted(v, 0) += 0.3;
    shifted.row(v).normalize();
  }
  SpherePictureOptions options = map.options;
  options.title = "icosphere - sphere (test) - shifted";
  options.width = 900;
  options.height = 500;
  write_sphere_picture(scratch_.file("first.png"), map.mesh, shifted, options);
  write_sphere_picture(scratch_.file("second.png"), map.mesh, shifted, options);
  const std::string first = testing::file_bytes(scratch_.file("first.png"));
  EXPECT_FALSE(first.empty());
  EXPECT_EQ(first, testing::file_bytes(scratch_.file("second.png")));
  const testing::DecodedImage image = testing::decode_png(scratch_.file("first.png"));
  EXPECT_EQ(image.width, 900);
  EXPECT_EQ(image.height, 500);
}

TEST_F(SpherePictureTest, WithoutPolesTheViewsStillShowTheWholeSphere) {
  const Mesh mesh = unit_sphere(2);
  const fs::path path = scratch_.file("plain.png");
  write_sphere_picture(path, mesh, mesh.vertices);
  const testing::DecodedImage image = testing::decode_png(path);
  ASSERT_EQ(image.width, 1600);
  EXPECT_FALSE(is_background(image.at(image.width / 4, image.height / 2)));
  EXPECT_FALSE(is_background(image.at(3 * image.width / 4, image.height / 2)));
}

TEST_F(SpherePictureTest, RefusesOtherFormatsAndBadArgumentsWritingNothing) {
  const SphereMap map = identity_map(1);
  const auto status_of = [&](const fs::path& path, const Eigen::MatrixX3d& points,
                             const SpherePictureOptions& options) {
    try {
      write_sphere_picture(path, map.mesh, points, options);
    } catch (const Error& error) {
      return error.status();
    }
    return Status::ok;
  };
  EXPECT_EQ(status_of(scratch_.file("sphere.svg"), map.points, map.options), Status::io_error);
  EXPECT_EQ(status_of(scratch_.file("sphere.jpg"), map.points, map.options), Status::io_error);
  SpherePictureOptions tiny = map.options;
  tiny.width = 100;
  EXPECT_EQ(status_of(scratch_.file("tiny.png"), map.points, tiny), Status::invalid_input);
  SpherePictureOptions bad_pole = map.options;
  bad_pole.south_pole = map.mesh.vertex_count();
  EXPECT_EQ(status_of(scratch_.file("pole.png"), map.points, bad_pole), Status::invalid_input);
  SpherePictureOptions bad_line = map.options;
  bad_line.date_line.push_back(-2);
  EXPECT_EQ(status_of(scratch_.file("line.png"), map.points, bad_line), Status::invalid_input);
  EXPECT_EQ(status_of(scratch_.file("rows.png"), map.points.topRows(3), map.options),
            Status::invalid_input);
  EXPECT_TRUE(fs::is_empty(scratch_.path()));
  EXPECT_EQ(status_of(scratch_.path() / "missing" / "sphere.png", map.points, map.options),
            Status::io_error);
}

TEST(SpherePictureHeadline, NamesDegenerateTrianglesOnlyWhenThereAreAny) {
  SphericalMetrics metrics;
  metrics.flipped_triangles = 3;
  metrics.area_distortion_mean = 0.237;
  EXPECT_EQ(sphere_picture_headline(metrics), "3 flipped, area distortion 0.24");
  metrics.degenerate_triangles = 1;
  EXPECT_EQ(sphere_picture_headline(metrics), "3 flipped, 1 degenerate, area distortion 0.24");
}

}  // namespace
}  // namespace harmonia
