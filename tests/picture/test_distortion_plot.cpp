// The comparison plot and the per-triangle angle distortion it shows: exactly zero for a layout
// that is the surface itself (or its mirror image), the value of a known shear, NaN exactly where
// the metrics leave a face out; the plot's SVG holds every label and one sorted step curve per
// layout and panel, the PNG shows each layout's colour and repeats its bytes; bad input is refused
// before anything is written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>


#include "harmonia/distortion_plot.h"
#include "harmonia/metrics.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "picture/axis_ticks.h"
#include "picture/color_map.h"
#include "support/decoded_png.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;

using testing::count_occurrences;

// ------------------------------------------------------------------------ face_angle_distortion

TEST(FaceAngleDistortion, ALayoutThatIsThePlanarSurfaceItselfIsExactlyZero) {
  const Mesh disk = planar_disk(5, 0.2);
  const Eigen::MatrixX2d own = disk.vertices.leftCols<2>();
  const Eigen::VectorXd distortion = face_angle_distortion(disk, own, disk.faces);
  ASSERT_EQ(distortion.size(), disk.face_count());
  for (Eigen::Index f = 0; f < distortion.size(); ++f) EXPECT_EQ(distortion[f], 0.0) << f;
  // Angles are unsigned: the mirror image keeps every angle (its flips are counted elsewhere).
  Eigen::MatrixX2d mirrored = own;
  mirrored.col(0) *= -1.0;
  const Eigen::VectorXd mirror_distortion = face_angle_distortion(disk, mirrored, disk.faces);
  for (Eigen::Index f = 0; f < distortion.size(); ++f) EXPECT_EQ(mirror_distortion[f], 0.0) << f;
}

TEST(FaceAngleDistortion, ARightIsoscelesTriangleLaidOutEquilateralScoresOneThird) {
  // Angles 90, 45, 45 degrees become 60, 60, 60: relative errors 1/3, 1/3, 1/3.
  Mesh triangle;
  triangle.vertices.resize(3, 3);
  triangle.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  triangle.faces.resize(1, 3);
  triangle.faces << 0, 1, 2;
  Eigen::MatrixX2d uv(3, 2);
  uv << 0, 0, 1, 0, 0.5, std::sqrt(3.0) / 2.0;
  const double distortion = face_angle_distortion(triangle, uv, triangle.faces)[0];
  // Each angle is an atan2 of rounded inputs, a few ulps of pi/2 off; three relative errors of
  // that size, each divided by an angle of at least pi/4, averaged.
  const double ulp_bound = 8.0 * std::numeric_limits<double>::epsilon();
  EXPECT_NEAR(distortion, 1.0 / 3.0, ulp_bound);
}

TEST(FaceAngleDistortion, IsNanExactlyWhereTheMetricsLeaveAFaceOutOfTheAngleFigures) {
  // Face 0 a proper triangle, face 1 collinear in 3D (degenerate input), face 2 a proper
  // triangle whose UV corner is not finite.
  Mesh mesh;
  mesh.vertices.resize(6, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0, 1, 1, 0;
  mesh.faces.resize(3, 3);
  mesh.faces << 0, 1, 2, 1, 3, 4, 1, 5, 2;
  Eigen::MatrixX2d uv = mesh.vertices.leftCols<2>();
  uv(5, 0) = NAN;
  const Eigen::VectorXd distortion = face_angle_distortion(mesh, uv, mesh.faces);
  EXPECT_EQ(distortion[0], 0.0);
  EXPECT_TRUE(std::isnan(distortion[1]));
  EXPECT_TRUE(std::isnan(distortion[2]));
  const DistortionMetrics metrics = evaluate_map(mesh, uv, mesh.faces);
  EXPECT_EQ(metrics.degenerate_input_triangles, 1);
}

TEST(FaceAngleDistortion, RefusesIndicesThatDoNotMatch) {
  const Mesh disk = planar_disk(2);
  const Eigen::MatrixX2d uv = disk.vertices.leftCols<2>();
  const auto expect_invalid = [&](const Eigen::MatrixX3i& uv_faces, const std::string& part) {
    try {
      (void)face_angle_distortion(disk, uv, uv_faces);
      FAIL() << "no error";
    } catch (const Error& error) {
      EXPECT_EQ(error.status(), Status::invalid_input);
      EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
    }
  };
  expect_invalid(disk.faces.topRows(3), "faces");
  Eigen::MatrixX3i out_of_range = disk.faces;
  out_of_range(2, 1) = static_cast<int>(uv.rows());
  expect_invalid(out_of_range, "uv_faces row 2");
}

// --------------------------------------------------------------------------------------- ticks

TEST(AxisTicks, RoundStepsCoverTheRangeWithLabelsOfTheStepsPrecision) {
  const detail::AxisTicks fraction = detail::axis_ticks(0.0, 1.0, 5);
  EXPECT_EQ(fraction.labels, (std::vector<std::string>{"0.0", "0.2", "0.4", "0.6", "0.8", "1.0"}));
  const detail::AxisTicks angle = detail::axis_ticks(0.0, 0.847, 5);
  EXPECT_EQ(angle.low, 0.0);
  EXPECT_DOUBLE_EQ(angle.high, 1.0);
  EXPECT_EQ(angle.labels.back(), "1.0");
  const detail::AxisTicks area = detail::axis_ticks(-6.05, 6.05, 6);
  EXPECT_EQ(area.labels,
            (std::vector<std::string>{"-8", "-6", "-4", "-2", "0", "2", "4", "6", "8"}));
  EXPECT_EQ(area.low, -8.0);
  EXPECT_EQ(area.high, 8.0);
}

// ---------------------------------------------------------------------------------------- plot

class DistortionPlotTest : public ::testing::Test {
 protected:
  testing::ScratchFolder scratch_{"distortion-plot"};
};

LayoutDistortion layout_of(std::string label, std::vector<double> angle, std::vector<double> area) {
  return {std::move(label), Eigen::Map<Eigen::VectorXd>(angle.data(), angle.size()),
          Eigen::Map<Eigen::VectorXd>(area.data(), area.size())};
}

struct Point {
  double x, y;
};

// The points of every <polyline> in the SVG, in order.
std::vector<std::vector<Point>> polylines(const std::string& svg) {
  std::vector<std::vector<Point>> lines;
  static const std::regex polyline("<polyline[^>]* points=\"([^\"]*)\"");
  for (std::sregex_iterator it(svg.begin(), svg.end(), polyline), end; it != end; ++it) {
    std::vector<Point> points;
    std::istringstream pairs((*it)[1].str());
    for (std::string pair; pairs >> pair;) {
      const std::size_t comma = pair.find(',');
      points.push_back({std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1))});
    }
    lines.push_back(points);
  }
  return lines;
}

TEST_F(DistortionPlotTest, SvgNamesEverythingAndDrawsSortedStepCurves) {
  // Layout "a & b": angle values 0.5, NaN (left out), 0.25; area -1, 1, 0.
  const std::vector<LayoutDistortion> layouts = {
      layout_of("a & b", {0.5, NAN, 0.25}, {-1.0, 1.0, 0.0}),
      layout_of("lscm", {0.1, 0.2, 0.3}, {0.0, 0.0, 0.0})};
  const fs::path path = scratch_.path() / "plot.svg";
  DistortionPlotOptions options;
  options.title = "face.obj - 2 layouts";
  write_distortion_plot(path, layouts, options);
  const std::string svg = testing::file_bytes(path);
  for (const char* text :
       {">face.obj - 2 layouts</text>", ">a &amp; b</text>", ">lscm</text>",
        ">angle distortion per triangle</text>", ">area distortion per triangle</text>",
        ">fraction of triangles (sorted by value)</text>",
        ">log(normalized UV area / 3D area)</text>",
        ">|UV angle − 3D angle| / 3D angle, mean of the 3 corners</text>", ">0.0</text>",
        ">0.2</text>", ">1.0</text>", ">0.5</text>"}) {
    EXPECT_NE(svg.find(text), std::string::npos) << text;
  }
  EXPECT_EQ(count_occurrences(svg, "rotate(-90.0"), 2);  // The two y-axis labels.
  // One curve per layout and panel: angle panel first, then the area panel.
  const std::vector<std::vector<Point>> curves = polylines(svg);
  ASSERT_EQ(curves.size(), 4u);
  // "a & b" in the angle panel: two values, so two steps of two points each, across the plot box
  // and rising from 0.25 (halfway up: the axis runs from 0 to the largest value, 0.5) to the top.
  static const std::regex clip(
      "<clipPath id=\"panel-0\"><rect x=\"([^\"]*)\" y=\"([^\"]*)\" width=\"([^\"]*)\" "
      "height=\"([^\"]*)\"");
  std::smatch box;
  ASSERT_TRUE(std::regex_search(svg, box, clip));
  const double left = std::stod(box[1]), top = std::stod(box[2]);
  const double right = left + std::stod(box[3]), bottom = top + std::stod(box[4]);
  const std::vector<Point>& steps = curves[0];
  ASSERT_EQ(steps.size(), 4u);
  constexpr double kWritten = 0.005;  // Coordinates are written with two decimals.
  EXPECT_NEAR(steps[0].x, left, 2 * kWritten);
  EXPECT_NEAR(steps[1].x, 0.5 * (left + right), 2 * kWritten);
  EXPECT_EQ(steps[2].x, steps[1].x);
  EXPECT_NEAR(steps[3].x, right, 2 * kWritten);
  EXPECT_NEAR(steps[0].y, 0.5 * (top + bottom), 2 * kWritten);
  EXPECT_EQ(steps[1].y, steps[0].y);
  EXPECT_NEAR(steps[2].y, top, 2 * kWritten);
  EXPECT_EQ(steps[3].y, steps[2].y);
  // The colours: layout i is drawn in palette colour i.
  EXPECT_EQ(
      count_occurrences(svg, "stroke=\"" + detail::hex_color(detail::kLayoutColors[0]) + "\""), 2);
  EXPECT_EQ(
      count_occurrences(svg, "stroke=\"" + detail::hex_color(detail::kLayoutColors[1]) + "\""), 2);
}

using testing::DecodedImage;
using testing::decode_png;

int pixels_of_color(const DecodedImage& image, const detail::Rgb& color) {
  int count = 0;
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
    count += image.rgb[i] == color.red && image.rgb[i + 1] == color.green &&
             image.rgb[i + 2] == color.blue;
  }
  return count;
}

// Pixels darker than every colour of the plot but its text.
int ink_pixels(const DecodedImage& image, int first_row, int end_row) {
  int count = 0;
  for (int y = first_row; y < end_row; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 3;
      count += image.rgb[i] < 110 && image.rgb[i + 1] < 110 && image.rgb[i + 2] < 110;
    }
  }
  return count;
}

TEST_F(DistortionPlotTest, PngShowsEveryLayoutsCurvesInItsColourAndRepeatsItsBytes) {
  // Three layouts whose values lie on parallel lines 0.1 apart (in shuffled order), so that no
  // curve hides another.
  std::vector<LayoutDistortion> layouts;
  for (int i = 0; i < 3; ++i) {
    LayoutDistortion layout{"layout " + std::to_string(i), Eigen::VectorXd(400),
                            Eigen::VectorXd(400)};
    for (int k = 0; k < 400; ++k) {
      const double fraction = ((k * 7) % 400) / 400.0;
      layout.face_angle_distortion[k] = 0.1 * (i + 1) + 0.3 * fraction;
      layout.face_area_log_ratio[k] = -1.0 + 0.5 * i + fraction;
    }
    layouts.push_back(std::move(layout));
  }
  DistortionPlotOptions options;
  options.title = "three layouts of one mesh";
  write_distortion_plot(scratch_.path() / "a.png", layouts, options);
  write_distortion_plot(scratch_.path() / "b.PNG", layouts, options);
  const DecodedImage image = decode_png(scratch_.path() / "a.png");
  ASSERT_EQ(image.width, 1600);
  ASSERT_EQ(image.height, 800);
  // A 2-pixel stroke covers fully the pixel nearest its middle line in every column it crosses;
  // each curve spans its panel's plot box, well over 500 columns wide in a 1600-pixel plot, in
  // both panels.
  for (int i = 0; i < 3; ++i) EXPECT_GT(pixels_of_color(image, detail::kLayoutColors[i]), 1000) << i;
  EXPECT_EQ(pixels_of_color(image, detail::kLayoutColors[3]), 0);
  // The title, in the top 5 % of the plot.
  EXPECT_GT(ink_pixels(image, 0, image.height / 20), 100);
  EXPECT_EQ(testing::file_bytes(scratch_.path() / "a.png"), testing::file_bytes(scratch_.path() / "b.PNG"));
}

TEST_F(DistortionPlotTest, RefusesWhatItCannotDrawBeforeWritingAnything) {
  const LayoutDistortion one = layout_of("one", {0.1}, {0.0});
  const auto expect_error =
      [&](const std::string& file, const std::vector<LayoutDistortion>& layouts,
          const DistortionPlotOptions& options, Status status, const std::string& part) {
        try {
          write_distortion_plot(scratch_.path() / file, layouts, options);
          FAIL() << "no error for " << part;
        } catch (const Error& error) {
          EXPECT_EQ(error.status(), status);
          EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
        }
      };
  expect_error("plot.svg", {}, {}, Status::invalid_input, "no layouts");
  expect_error("plot.svg", std::vector<LayoutDistortion>(11, one), {}, Status::invalid_input,
               "11 layouts");
  expect_error("plot.svg", {layout_of("", {0.1}, {0.0})}, {}, Status::invalid_input,
               "layout 0 has no label");
  expect_error("plot.png", {one}, {"", 100, 800}, Status::invalid_input, "width_pixels 100");
  expect_error("plot.png", {one}, {"", 800, 100}, Status::invalid_input, "height_pixels 100");
  expect_error("plot.jpg", {one}, {}, Status::io_error, "'.jpg'");
  EXPECT_TRUE(fs::is_empty(scratch_.path()));
}

}  // namespace
}  // namespace harmonia
