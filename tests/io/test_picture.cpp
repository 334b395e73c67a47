// Pictures of UV layouts: the SVG has one polygon per triangle with flipped ones marked, the PNG
// decodes to the requested size with the right colours in the right places, and failed writes
// throw io_error without leaving temporary files behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

// The decoder, compiled here only (third-party code: its warnings are silenced locally).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include "harmonia/picture.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "io/color_map.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder per test, removed afterwards.
class PictureTest : public ::testing::Test {
 protected:
  // Names of everything in the folder (leftover temporary files would show here).
  [[nodiscard]] std::vector<std::string> files_in_folder() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(scratch_.path()))
      names.push_back(entry.path().filename());
    return names;
  }

  testing::ScratchFolder scratch_{"picture"};
};

std::string read_text(const fs::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

int count_occurrences(const std::string& text, const std::string& pattern) {
  int count = 0;
  for (std::size_t at = text.find(pattern); at != std::string::npos;
       at = text.find(pattern, at + 1)) {
    ++count;
  }
  return count;
}

// Unit square split along (0,0)-(1,1): face 0 = (0,0)(1,0)(1,1), face 1 = (0,0)(1,1)(0,1).
Mesh unit_square() {
  Mesh square;
  square.vertices.resize(4, 3);
  square.vertices << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  square.faces.resize(2, 3);
  square.faces << 0, 1, 2, 0, 2, 3;
  return square;
}

TEST_F(PictureTest, SvgHasOnePolygonPerTriangleAndTheFlippedOneIsBlack) {
  // A strip whose corner vertex (0, 1) belongs to one triangle only; reflected across that
  // triangle's diagonal, exactly that triangle turns over.
  Mesh strip = developable_strip(4, 1, 2.0, 1.0, 1.0);
  for (int j = 0; j <= 1; ++j) {
    for (int i = 0; i <= 4; ++i) strip.vertices.row(j * 5 + i) << 0.5 * i, j, 0.0;
  }
  Eigen::MatrixX2d uv = strip.vertices.leftCols<2>();
  const Eigen::Vector2d diagonal = Eigen::Vector2d(0.5, 1.0).normalized();
  const Eigen::Vector2d corner = uv.row(5);
  uv.row(5) = 2.0 * corner.dot(diagonal) * diagonal - corner;

  const fs::path path = scratch_.path() / "strip.svg";
  write_picture(path, strip, uv, strip.faces);
  const std::string svg = read_text(path);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(count_occurrences(svg, "<polygon"), strip.face_count());
  int black_polygons = 0;
  std::istringstream lines(svg);
  for (std::string line; std::getline(lines, line);) {
    black_polygons +=
        line.rfind("<polygon", 0) == 0 && line.find("fill=\"#000000\"") != std::string::npos;
  }
  EXPECT_EQ(black_polygons, 1);
  EXPECT_EQ(count_occurrences(svg, "fill=\"#000000\" stroke=\"#ff00ff\""), 1);
  EXPECT_NE(svg.find("mean"), std::string::npos);
  EXPECT_NE(svg.find("flipped 1"), std::string::npos);
  EXPECT_EQ(files_in_folder(), std::vector<std::string>{"strip.svg"});
}

TEST_F(PictureTest, SvgColoursFollowTheDistortion) {
  // The identity map is white everywhere; stretching x by 4 saturates the conformal colour on
  // every face.
  const Mesh disk = planar_disk(3, 0.0);
  const std::string white = "fill=\"" + detail::hex_color(detail::conformal_color(1.0)) + "\"";
  const std::string red = "fill=\"" + detail::hex_color(detail::conformal_color(4.0)) + "\"";
  ASSERT_EQ(white, "fill=\"#ffffff\"");
  const fs::path path = scratch_.path() / "disk.svg";
  write_picture(path, disk, disk.vertices.leftCols<2>(), disk.faces);
  EXPECT_EQ(count_occurrences(read_text(path), white), disk.face_count());
  Eigen::MatrixX2d stretched = disk.vertices.leftCols<2>();
  stretched.col(0) *= 4.0;
  write_picture(path, disk, stretched, disk.faces);
  EXPECT_EQ(count_occurrences(read_text(path), red), disk.face_count());
  // In area colouring the same stretch is white: areas are compared after normalization.
  write_picture(path, disk, stretched, disk.faces,
                PictureOptions{PictureColoring::area_distortion, 256, true});
  EXPECT_EQ(count_occurrences(read_text(path), white), disk.face_count());
}

struct DecodedImage {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  [[nodiscard]] detail::Rgb at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

DecodedImage decode_png(const fs::path& path) {
  DecodedImage image;
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &image.width, &image.height, &channels, 3);
  if (data == nullptr) return image;
  image.rgb.assign(data, data + static_cast<std::size_t>(image.width) * image.height * 3);
  stbi_image_free(data);
  return image;
}

// Pixel bounds of everything that is not background: where the layout's bounding box landed.
struct PixelBox {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};
PixelBox drawn_box(const DecodedImage& image) {
  PixelBox box;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (image.at(x, y) == detail::kBackground) continue;
      box.x0 = std::min(box.x0, x);
      box.x1 = std::max(box.x1, x);
      box.y0 = std::min(box.y0, y);
      box.y1 = std::max(box.y1, y);
    }
  }
  return box;
}

TEST_F(PictureTest, PngHasTheRequestedSizeAndColoursEachTriangle) {
  // Face 0 keeps its shape (white); face 1's corner (0,1) goes to (-1,1): a shear with
  // sigma1/sigma2 = golden ratio squared. UV bounding box: [-1, 1] x [0, 1].
  const Mesh square = unit_square();
  Eigen::MatrixX2d uv = square.vertices.leftCols<2>();
  uv.row(3) << -1.0, 1.0;
  const fs::path path = scratch_.path() / "square.png";
  write_picture(path, square, uv, square.faces,
                PictureOptions{PictureColoring::conformal_distortion, 300, true});
  const DecodedImage image = decode_png(path);
  ASSERT_EQ(image.width, 300);
  ASSERT_EQ(image.height, 300);

  // Map UV to pixels through the drawn bounding box (y points down in the image).
  const PixelBox box = drawn_box(image);
  ASSERT_GT(box.x1 - box.x0, 200);
  EXPECT_NEAR(box.x1 - box.x0, 2.0 * (box.y1 - box.y0), 3.0);  // Aspect ratio kept.
  const auto pixel = [&](double u, double v) {
    const int x = static_cast<int>(std::lround(box.x0 + (u + 1.0) / 2.0 * (box.x1 - box.x0)));
    const int y = static_cast<int>(std::lround(box.y1 - v * (box.y1 - box.y0)));
    return image.at(x, y);
  };
  const double golden = (1.0 + std::sqrt(5.0)) / 2.0;
  EXPECT_EQ(pixel(2.0 / 3.0, 1.0 / 3.0), (detail::Rgb{255, 255, 255}));  // Centroid of face 0.
  const detail::Rgb sheared = pixel(0.0, 2.0 / 3.0);                     // Centroid of face 1.
  EXPECT_EQ(sheared, detail::conformal_color(golden * golden));
  EXPECT_GT(sheared.red, sheared.green + 100);       // Clearly red.
  EXPECT_EQ(pixel(-0.8, 0.1), detail::kBackground);  // Left of face 1, inside the bounding box.
  EXPECT_EQ(image.at(2, 2), detail::kBackground);
  EXPECT_EQ(image.at(297, 297), detail::kBackground);
}

TEST_F(PictureTest, PngMarksFlippedTrianglesBlackOnTop) {
  // Corner (0,1) moved to (1.5, 0.5): face 1 turns clockwise and lies partly over face 0.
  const Mesh square = unit_square();
  Eigen::MatrixX2d uv = square.vertices.leftCols<2>();
  uv.row(3) << 1.5, 0.5;
  const fs::path path = scratch_.path() / "flipped.png";
  write_picture(path, square, uv, square.faces,
                PictureOptions{PictureColoring::area_distortion, 200, false});
  const DecodedImage image = decode_png(path);
  ASSERT_EQ(image.width, 200);
  const PixelBox box = drawn_box(image);  // UV bounding box [0, 1.5] x [0, 1]
  const auto pixel = [&](double u, double v) {
    const int x = static_cast<int>(std::lround(box.x0 + u / 1.5 * (box.x1 - box.x0)));
    const int y = static_cast<int>(std::lround(box.y1 - v * (box.y1 - box.y0)));
    return image.at(x, y);
  };
  EXPECT_EQ(pixel(2.5 / 3.0, 0.5), detail::kFlippedFill);  // Centroid of the flipped face.
  EXPECT_EQ(pixel(1.3, 0.5), detail::kFlippedFill);        // Where only the flipped face lies.
  EXPECT_NE(pixel(0.9, 0.1), detail::kFlippedFill);        // Face 0 alone.
  EXPECT_NE(pixel(0.9, 0.1), detail::kBackground);
}

TEST_F(PictureTest, SamePictureTwiceGivesTheSameBytes) {
  const Mesh cap = hemisphere(6);
  const Eigen::MatrixX2d uv = cap.vertices.leftCols<2>();
  write_picture(scratch_.path() / "a.png", cap, uv, cap.faces,
                PictureOptions{PictureColoring::conformal_distortion, 128, true});
  write_picture(scratch_.path() / "b.png", cap, uv, cap.faces,
                PictureOptions{PictureColoring::conformal_distortion, 128, true});
  const std::string first = read_text(scratch_.path() / "a.png");
  EXPECT_GT(first.size(), 100u);
  EXPECT_EQ(first, read_text(scratch_.path() / "b.png"));
}

void expect_io_error(const fs::path& path, const std::string& message_part) {
  const Mesh square = unit_square();
  try {
    write_picture(path, square, square.vertices.leftCols<2>(), square.faces);
    FAIL() << "no error writing " << path;
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::io_error);
    EXPECT_NE(std::string(error.what()).find(message_part), std::string::npos) << error.what();
  }
}

TEST_F(PictureTest, UnknownExtensionIsAnIoErrorNamingIt) {
  expect_io_error(scratch_.path() / "picture.jpg", "'.jpg'");
  EXPECT_TRUE(files_in_folder().empty());
}

TEST_F(PictureTest, SizeOutsideTheSupportedRangeIsRejected) {
  const Mesh square = unit_square();
  try {
    write_picture(scratch_.path() / "tiny.png", square, square.vertices.leftCols<2>(), square.faces,
                  PictureOptions{PictureColoring::conformal_distortion, 8, true});
    FAIL() << "no error for an 8-pixel picture";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("size_pixels 8"), std::string::npos) << error.what();
  }
  EXPECT_TRUE(files_in_folder().empty());
}

TEST_F(PictureTest, MissingFolderIsAnIoErrorAndLeavesNothing) {
  expect_io_error(scratch_.path() / "no_such_folder" / "picture.png", "no_such_folder");
  EXPECT_TRUE(files_in_folder().empty());
}

TEST_F(PictureTest, FailedRenameRemovesTheTemporaryFile) {
  // The target name is taken by a non-empty folder: the temporary file is written, the rename
  // fails, and the temporary file must be gone afterwards.
  fs::create_directories(scratch_.path() / "taken.svg" / "inside");
  expect_io_error(scratch_.path() / "taken.svg", "taken.svg");
  EXPECT_EQ(files_in_folder(), std::vector<std::string>{"taken.svg"});
}

TEST_F(PictureTest, ReadOnlyFolderIsAnIoErrorAndLeavesNothing) {
  if (::geteuid() != 0) {
    fs::permissions(scratch_.path(), fs::perms::owner_read | fs::perms::owner_exec,
                    fs::perm_options::replace);
    expect_io_error(scratch_.path() / "picture.svg", "picture.svg");
    fs::permissions(scratch_.path(), fs::perms::owner_all, fs::perm_options::replace);
    EXPECT_TRUE(files_in_folder().empty());
    return;
  }
  // Permissions do not stop root; /proc refuses new files to everyone.
  expect_io_error("/proc/self/harmonia_picture.svg", "harmonia_picture.svg");
  for (const auto& entry : fs::directory_iterator("/proc/self")) {
    EXPECT_EQ(entry.path().filename().string().find("harmonia_picture"), std::string::npos);
  }
}

}  // namespace
}  // namespace harmonia
