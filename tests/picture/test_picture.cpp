// Pictures of UV layouts: the SVG has one polygon per triangle with flipped ones marked, the PNG
// decodes to the requested size with the right colours in the right places, both carry the title
// and the colour bar with its labelled ticks (the PNG's text drawn from the embedded font, the same
// bytes on every run), and failed writes throw io_error without leaving temporary files behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>


#include "harmonia/metrics.h"
#include "harmonia/picture.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "picture/color_map.h"
#include "picture/picture_frame.h"
#include "support/decoded_png.h"
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

using testing::count_occurrences;

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
  const std::string svg = testing::file_bytes(path);
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
  // The flipped polygon and the legend's swatch.
  EXPECT_EQ(count_occurrences(svg, "fill=\"#000000\" stroke=\"#ff00ff\""), 2);
  EXPECT_NE(svg.find(">flipped triangles (1)</text>"), std::string::npos);
  // No title given: the headline numbers.
  EXPECT_NE(svg.find(">1 flipped, conformal "), std::string::npos);
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
  EXPECT_EQ(count_occurrences(testing::file_bytes(path), white), disk.face_count());
  Eigen::MatrixX2d stretched = disk.vertices.leftCols<2>();
  stretched.col(0) *= 4.0;
  write_picture(path, disk, stretched, disk.faces);
  EXPECT_EQ(count_occurrences(testing::file_bytes(path), red), disk.face_count());
  // In area colouring the same stretch is white: areas are compared after normalization.
  write_picture(path, disk, stretched, disk.faces,
                PictureOptions{PictureColoring::area_distortion, 256, true});
  EXPECT_EQ(count_occurrences(testing::file_bytes(path), white), disk.face_count());
}

using testing::DecodedImage;
using testing::decode_png;

// Pixel bounds of everything inside the layout's part of the picture (between the title and the
// legend) that is not background: where the layout's bounding box landed.
struct PixelBox {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};
PixelBox drawn_box(const DecodedImage& image) {
  const detail::PictureFrame frame = detail::picture_frame(image.width);
  PixelBox box;
  for (int y = static_cast<int>(frame.layout.top); y < static_cast<int>(frame.layout.bottom); ++y) {
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
  const std::string first = testing::file_bytes(scratch_.path() / "a.png");
  EXPECT_GT(first.size(), 100u);
  EXPECT_EQ(first, testing::file_bytes(scratch_.path() / "b.png"));
}

TEST_F(PictureTest, PictureHeadlineGivesFlipsAndMeansWithTwoDecimals) {
  DistortionMetrics metrics;
  metrics.flipped_triangles = 3;
  metrics.conformal_distortion_mean = 1.9139;
  metrics.area_distortion_mean = 0.952163;
  EXPECT_EQ(picture_headline(metrics), "3 flipped, conformal 1.91, area 0.95");
}

// The x at which the SVG's text with this content starts (or is centred), or NaN.
double svg_text_x(const std::string& svg, const std::string& content) {
  const std::size_t end = svg.find(">" + content + "</text>");
  if (end == std::string::npos) return NAN;
  const std::size_t start = svg.rfind("<text x=\"", end);
  if (start == std::string::npos) return NAN;
  return std::stod(svg.substr(start + 9));
}

TEST_F(PictureTest, SvgHasTheTitleAndTheColourBarWithItsTicksOnTheLogScale) {
  const Mesh disk = planar_disk(3, 0.1);
  PictureOptions options;
  options.title = "disk & <co> - conformal (cotangent)";
  const fs::path path = scratch_.path() / "disk.svg";
  write_picture(path, disk, disk.vertices.leftCols<2>(), disk.faces, options);
  std::string svg = testing::file_bytes(path);
  EXPECT_NE(svg.find(">disk &amp; &lt;co&gt; - conformal (cotangent)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">conformal distortion σ1/σ2 (log scale)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">flipped triangles (0)</text>"), std::string::npos);
  // Each tick label sits at its value's place on the log scale from 1 to 4 along the bar.
  const detail::PictureFrame frame = detail::picture_frame(options.size_pixels);
  const std::vector<std::pair<std::string, double>> conformal_ticks = {
      {"1", 1.0}, {"1.5", 1.5}, {"2", 2.0}, {"3", 3.0}, {"≥4", 4.0}};
  for (const auto& [label, value] : conformal_ticks) {
    SCOPED_TRACE(label);
    const double expected =
        frame.color_bar.left + std::log(value) / std::log(4.0) * frame.color_bar.width();
    EXPECT_NEAR(svg_text_x(svg, label), expected, 0.05);  // Written with one decimal.
  }
  // The gradient runs from the colour of 1 to the colour of the saturation.
  EXPECT_NE(svg.find("stop-color=\"" + detail::hex_color(detail::conformal_color(1.0)) + "\""),
            std::string::npos);
  EXPECT_NE(svg.find("stop-color=\"" + detail::hex_color(detail::conformal_color(4.0)) + "\""),
            std::string::npos);

  options.coloring = PictureColoring::area_distortion;
  write_picture(path, disk, disk.vertices.leftCols<2>(), disk.faces, options);
  svg = testing::file_bytes(path);
  const std::vector<std::pair<std::string, double>> area_ticks = {
      {"≤1/4", 0.25}, {"1/2", 0.5}, {"1", 1.0}, {"2", 2.0}, {"≥4", 4.0}};
  for (const auto& [label, factor] : area_ticks) {
    SCOPED_TRACE(label);
    const double expected = frame.color_bar.left + (std::log(factor) / std::log(4.0) + 1.0) / 2.0 *
                                                       frame.color_bar.width();
    EXPECT_NEAR(svg_text_x(svg, label), expected, 0.05);
  }
  for (const double log_ratio : {-std::log(4.0), 0.0, std::log(4.0)}) {
    EXPECT_NE(svg.find("stop-color=\"" + detail::hex_color(detail::area_color(log_ratio)) + "\""),
              std::string::npos)
        << log_ratio;
  }
}

// Pixels darker than any colour of a layout or the background: text (black ink).
int ink_pixels(const DecodedImage& image, int top, int bottom, int left, int right) {
  int count = 0;
  for (int y = top; y < bottom; ++y) {
    for (int x = left; x < right; ++x) {
      const detail::Rgb pixel = image.at(x, y);
      count += pixel.red < 110 && pixel.green < 110 && pixel.blue < 110;
    }
  }
  return count;
}

TEST_F(PictureTest, PngTitleBandHoldsTheTitleText) {
  const Mesh disk = planar_disk(4, 0.1);
  const Eigen::MatrixX2d uv = disk.vertices.leftCols<2>();
  PictureOptions options{PictureColoring::conformal_distortion, 512, true, "x"};
  write_picture(scratch_.path() / "short.png", disk, uv, disk.faces, options);
  options.title = "planar disk - conformal (cotangent) - 0 flipped, conformal 1.00, area 0.00";
  write_picture(scratch_.path() / "long.png", disk, uv, disk.faces, options);
  const DecodedImage short_title = decode_png(scratch_.path() / "short.png");
  const DecodedImage long_title = decode_png(scratch_.path() / "long.png");
  ASSERT_EQ(long_title.width, 512);
  const detail::PictureFrame frame = detail::picture_frame(512);
  const int band = static_cast<int>(frame.layout.top);
  const int short_ink = ink_pixels(short_title, 0, band, 0, 512);
  const int long_ink = ink_pixels(long_title, 0, band, 0, 512);
  EXPECT_GT(short_ink, 0);
  // About 70 glyphs against one: far more ink, spread along the line from the left margin.
  EXPECT_GT(long_ink, 20 * short_ink);
  EXPECT_GT(ink_pixels(long_title, 0, band, 256, 512), 0);
  const int margin = static_cast<int>(frame.margin);
  EXPECT_EQ(ink_pixels(long_title, 0, band, 0, margin - 1), 0);
  EXPECT_EQ(ink_pixels(long_title, 0, margin - 1, 0, 512), 0);
}

TEST_F(PictureTest, PngColourBarShowsTheTriangleColoursAtItsTicksAndTheFlippedSwatch) {
  const Mesh disk = planar_disk(3, 0.1);
  const fs::path path = scratch_.path() / "bar.png";
  for (const PictureColoring coloring :
       {PictureColoring::conformal_distortion, PictureColoring::area_distortion}) {
    write_picture(path, disk, disk.vertices.leftCols<2>(), disk.faces,
                  PictureOptions{coloring, 1024, true, ""});
    const DecodedImage image = decode_png(path);
    ASSERT_EQ(image.width, 1024);
    const detail::PictureFrame frame = detail::picture_frame(1024);
    const PixelBox bar{
        static_cast<int>(frame.color_bar.left), static_cast<int>(frame.color_bar.top),
        static_cast<int>(frame.color_bar.right), static_cast<int>(frame.color_bar.bottom)};
    const int middle_row = (bar.y0 + bar.y1) / 2;
    // At an inner tick the bar shows what a triangle of that value is filled with, up to the
    // colour change across the one pixel column between the tick and the column's centre: a
    // channel moves by at most 235 levels (255 to 20) over half the bar's width (the area bar's
    // halves), plus one level of rounding.
    const int tolerance = static_cast<int>(std::ceil(2.0 * 235.0 / (bar.x1 - bar.x0))) + 1;
    const std::vector<std::pair<double, detail::Rgb>> inner_ticks =
        coloring == PictureColoring::conformal_distortion
            ? std::vector<std::pair<double, detail::Rgb>>{{std::log(2.0) / std::log(4.0),
                                                           detail::conformal_color(2.0)},
                                                          {std::log(3.0) / std::log(4.0),
                                                           detail::conformal_color(3.0)}}
            : std::vector<std::pair<double, detail::Rgb>>{
                  {0.25, detail::area_color(std::log(0.5))},
                  {0.75, detail::area_color(std::log(2.0))}};
    for (const auto& [position, expected] : inner_ticks) {
      const int x = static_cast<int>(frame.color_bar.left + position * frame.color_bar.width());
      const detail::Rgb shown = image.at(x, middle_row);
      EXPECT_NEAR(shown.red, expected.red, tolerance) << position;
      EXPECT_NEAR(shown.green, expected.green, tolerance) << position;
      EXPECT_NEAR(shown.blue, expected.blue, tolerance) << position;
    }
    // Tick labels below the bar are ink.
    EXPECT_GT(ink_pixels(image, bar.y1 + 1, static_cast<int>(frame.tick_label_baseline) + 1,
                         bar.x0 - 10, bar.x1 + 10),
              0);
    // The swatch: black inside, magenta at its edge.
    const detail::PixelBox& swatch = frame.flipped_swatch;
    const int swatch_x = static_cast<int>(0.5 * (swatch.left + swatch.right));
    const int swatch_y = static_cast<int>(0.5 * (swatch.top + swatch.bottom));
    EXPECT_EQ(image.at(swatch_x, swatch_y), detail::kFlippedFill);
    EXPECT_EQ(image.at(static_cast<int>(swatch.left) + 1, swatch_y), detail::kFlippedOutline);
  }
}

TEST_F(PictureTest, TinyPicturesStillHaveEveryPart) {
  const Mesh disk = planar_disk(3, 0.1);
  const fs::path path = scratch_.path() / "tiny.png";
  write_picture(path, disk, disk.vertices.leftCols<2>(), disk.faces,
                PictureOptions{PictureColoring::conformal_distortion, 16, true, ""});
  const DecodedImage image = decode_png(path);
  EXPECT_EQ(image.width, 16);
  EXPECT_EQ(image.height, 16);
  const detail::PictureFrame frame = detail::picture_frame(16);
  EXPECT_GT(frame.layout.height(), 0.6 * 16);
  EXPECT_LT(frame.color_bar.bottom, 16.0);
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
