// Pictures of a UV layout: every triangle filled with the colour of its distortion, flipped ones
// black with a magenta outline, as SVG text or as a PNG rasterized here (stb_image_write encodes).
#include "harmonia/picture.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <stb_image_write.h>

#include "harmonia/metrics.h"
#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "io/color_map.h"
#include "planar/uv_layout_checks.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;
using detail::Rgb;

enum class PictureFormat { svg, png };

PictureFormat format_of(const fs::path& path) {
  std::string extension = path.extension().string();
  for (char& letter : extension)
    letter = static_cast<char>(std::tolower(static_cast<unsigned char>(letter)));
  if (extension == ".svg") return PictureFormat::svg;
  if (extension == ".png") return PictureFormat::png;
  throw Error(Status::io_error, "write_picture: unknown picture format '" + extension + "' of '" +
                                    path.string() + "' (use .svg or .png)");
}

// One triangle as drawn: pixel coordinates (y down), fill colour, whether it is flipped.
struct DrawnTriangle {
  std::array<Eigen::Vector2d, 3> corners;
  Rgb fill;
  bool flipped = false;
};

// What both formats draw: triangles in drawing order (flipped ones last, so they stay visible on
// top of whatever overlaps them) and the legend line.
struct PictureContent {
  int size = 0;
  std::vector<DrawnTriangle> triangles;
  std::string legend;
  double legend_font_size = 0.0;
  bool draw_edges = false;
};

std::string fixed_number(double value, int decimals) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value,
                                    std::chars_format::fixed, decimals);
  return std::string(buffer.data(), result.ptr);
}

std::string legend_text(const PictureOptions& options, const DistortionMetrics& metrics) {
  std::string text;
  if (options.coloring == PictureColoring::conformal_distortion) {
    text = "conformal distortion sigma1/sigma2 (white 1, red &gt;= " +
           fixed_number(detail::kConformalSaturation, 0) + "): mean " +
           fixed_number(metrics.conformal_distortion_mean, 4);
  } else {
    text = "area distortion log(uv/3D area) (blue -" + fixed_number(detail::kAreaSaturation, 2) +
           ", white 0, red +" + fixed_number(detail::kAreaSaturation, 2) + "): mean |log| " +
           fixed_number(metrics.area_distortion_mean, 4);
  }
  return text + ", flipped " + std::to_string(metrics.flipped_triangles) + " (black)";
}

PictureContent lay_out(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                       const Eigen::MatrixX3i& uv_faces, const PictureOptions& options,
                       PictureFormat format) {
  if (options.size_pixels < 16 || options.size_pixels > 16384) {
    throw Error(Status::invalid_input, "write_picture: size_pixels " +
                                           std::to_string(options.size_pixels) +
                                           " is outside [16, 16384]");
  }
  const DistortionMetrics metrics = evaluate_map(mesh3d, uv, uv_faces);
  PictureContent content;
  content.size = options.size_pixels;
  content.legend = legend_text(options, metrics);
  content.legend_font_size = std::max(8.0, options.size_pixels / 56.0);

  // Fit the bounding box of the used UVs inside the square (in SVG below the legend line; PNG has
  // no text).
  Eigen::Vector2d low = Eigen::Vector2d::Constant(INFINITY),
                  high = Eigen::Vector2d::Constant(-INFINITY);
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) {
    for (int corner = 0; corner < 3; ++corner) {
      const Eigen::Vector2d point = uv.row(uv_faces(f, corner));
      if (!point.allFinite()) continue;
      low = low.cwiseMin(point);
      high = high.cwiseMax(point);
    }
  }
  const double size = options.size_pixels;
  const double margin = 0.04 * size;
  const double top =
      format == PictureFormat::svg ? margin + 1.5 * content.legend_font_size : margin;
  const double room_x = size - 2.0 * margin, room_y = size - margin - top;
  const Eigen::Vector2d extent = (high - low).cwiseMax(1e-300);
  const double scale = std::min(room_x / extent.x(), room_y / extent.y());
  const Eigen::Vector2d centre = 0.5 * (low + high);
  const auto to_pixels = [&](const Eigen::Vector2d& point) {
    return Eigen::Vector2d(margin + 0.5 * room_x + scale * (point.x() - centre.x()),
                           top + 0.5 * room_y - scale * (point.y() - centre.y()));
  };

  const std::vector<double> areas = detail::signed_uv_areas(uv, uv_faces);
  std::vector<DrawnTriangle> flipped;
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) {
    DrawnTriangle triangle;
    bool finite = true;
    for (int corner = 0; corner < 3; ++corner) {
      const Eigen::Vector2d point = uv.row(uv_faces(f, corner));
      finite = finite && point.allFinite();
      triangle.corners[corner] = to_pixels(point);
    }
    if (!finite) continue;  // Cannot be placed; reported as zero-area by the metrics.
    triangle.flipped = detail::classify_uv_triangle(uv, uv_faces, f, areas[f]) ==
                       detail::TriangleState::flipped;
    if (triangle.flipped) {
      triangle.fill = detail::kFlippedFill;
      flipped.push_back(triangle);
      continue;
    }
    triangle.fill = options.coloring == PictureColoring::conformal_distortion
                        ? detail::conformal_color(metrics.face_conformal_distortion[f])
                        : detail::area_color(metrics.face_area_log_ratio[f]);
    content.triangles.push_back(triangle);
  }
  content.triangles.insert(content.triangles.end(), flipped.begin(), flipped.end());
  content.draw_edges = options.draw_edges;
  return content;
}

// ---------------------------------------------------------------------------------------------
// SVG

constexpr Eigen::Index kSvgEdgeLimit = 200000;  // Above this many faces edges would hide the fill.

std::string render_svg(const PictureContent& content) {
  const std::string size = std::to_string(content.size);
  std::string svg;
  svg.reserve(200 + content.triangles.size() * 120);
  svg += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + size + "\" height=\"" + size +
         "\" viewBox=\"0 0 " + size + " " + size + "\">\n";
  svg += "<rect width=\"" + size + "\" height=\"" + size + "\" fill=\"" +
         detail::hex_color(detail::kBackground) + "\"/>\n";
  const bool edges =
      content.draw_edges && static_cast<Eigen::Index>(content.triangles.size()) <= kSvgEdgeLimit;
  const double edge_width = std::max(0.2, content.size / 4000.0);
  const std::string edge_style = edges
                                     ? " stroke=\"" + detail::hex_color(detail::kEdgeColor) +
                                           "\" stroke-width=\"" + fixed_number(edge_width, 2) + "\""
                                     : std::string(" stroke=\"none\"");
  const std::string flipped_style = " stroke=\"" + detail::hex_color(detail::kFlippedOutline) +
                                    "\" stroke-width=\"" + fixed_number(2.0 * edge_width, 2) + "\"";
  for (const DrawnTriangle& triangle : content.triangles) {
    svg += "<polygon points=\"";
    for (int corner = 0; corner < 3; ++corner) {
      if (corner > 0) svg += ' ';
      svg += fixed_number(triangle.corners[corner].x(), 2) + "," +
             fixed_number(triangle.corners[corner].y(), 2);
    }
    svg += "\" fill=\"" + detail::hex_color(triangle.fill) + "\"";
    svg += triangle.flipped ? flipped_style : edge_style;
    svg += " stroke-linejoin=\"round\"/>\n";
  }
  svg += "<text x=\"" + fixed_number(0.04 * content.size, 1) + "\" y=\"" +
         fixed_number(0.04 * content.size + content.legend_font_size, 1) +
         "\" font-family=\"sans-serif\" font-size=\"" + fixed_number(content.legend_font_size, 1) +
         "\" fill=\"" + detail::hex_color(detail::kLegendColor) + "\">" + content.legend +
         "</text>\n</svg>\n";
  return svg;
}

// ---------------------------------------------------------------------------------------------
// PNG

class RgbImage {
 public:
  explicit RgbImage(int size) : size_(size), pixels_(static_cast<std::size_t>(size) * size * 3) {
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) set(x, y, detail::kBackground);
    }
  }

  void set(int x, int y, const Rgb& color) {
    if (x < 0 || y < 0 || x >= size_ || y >= size_) return;
    const std::size_t at = (static_cast<std::size_t>(y) * size_ + x) * 3;
    pixels_[at] = color.red;
    pixels_[at + 1] = color.green;
    pixels_[at + 2] = color.blue;
  }

  [[nodiscard]] int size() const { return size_; }
  [[nodiscard]] const std::vector<std::uint8_t>& pixels() const { return pixels_; }

 private:
  int size_;
  std::vector<std::uint8_t> pixels_;
};

// Twice the signed area of (a, b, p): which side of the line a -> b the point p lies on.
double edge_function(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

// A one-pixel line: samples at least one per pixel along the longer axis.
void draw_line(RgbImage& image, const Eigen::Vector2d& from, const Eigen::Vector2d& to,
               const Rgb& color) {
  const Eigen::Vector2d delta = to - from;
  const int steps =
      static_cast<int>(std::ceil(std::max(std::abs(delta.x()), std::abs(delta.y())))) + 1;
  for (int step = 0; step <= steps; ++step) {
    const Eigen::Vector2d point = from + delta * (static_cast<double>(step) / steps);
    image.set(static_cast<int>(std::floor(point.x())), static_cast<int>(std::floor(point.y())),
              color);
  }
}

// Fills the pixels whose centres lie inside the triangle (edges included), whatever its winding.
void fill_triangle(RgbImage& image, const std::array<Eigen::Vector2d, 3>& corners,
                   const Rgb& color) {
  const Eigen::Vector2d& a = corners[0];
  Eigen::Vector2d b = corners[1], c = corners[2];
  const double twice_area = edge_function(a, b, c);
  if (twice_area == 0.0) {  // A sliver with no interior: still show it as its outline.
    draw_line(image, a, b, color);
    draw_line(image, b, c, color);
    return;
  }
  if (twice_area < 0.0) std::swap(b, c);
  const double last = image.size() - 1;
  const int x0 =
      static_cast<int>(std::clamp(std::floor(std::min({a.x(), b.x(), c.x()})), 0.0, last));
  const int x1 =
      static_cast<int>(std::clamp(std::ceil(std::max({a.x(), b.x(), c.x()})), 0.0, last));
  const int y0 =
      static_cast<int>(std::clamp(std::floor(std::min({a.y(), b.y(), c.y()})), 0.0, last));
  const int y1 =
      static_cast<int>(std::clamp(std::ceil(std::max({a.y(), b.y(), c.y()})), 0.0, last));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector2d centre(x + 0.5, y + 0.5);
      if (edge_function(a, b, centre) >= 0.0 && edge_function(b, c, centre) >= 0.0 &&
          edge_function(c, a, centre) >= 0.0) {
        image.set(x, y, color);
      }
    }
  }
}

// Below this mean triangle area (in pixels) edges would cover the colours; they are left out.
constexpr double kPngEdgeMinimumArea = 40.0;

void append_bytes(void* context, void* data, int size) {
  auto* bytes = static_cast<std::string*>(context);
  bytes->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

std::string render_png(const PictureContent& content) {
  RgbImage image(content.size);
  double pixel_area = 0.0;
  for (const DrawnTriangle& triangle : content.triangles) {
    fill_triangle(image, triangle.corners, triangle.fill);
    pixel_area += 0.5 * std::abs(edge_function(triangle.corners[0], triangle.corners[1],
                                               triangle.corners[2]));
  }
  const bool edges =
      content.draw_edges && !content.triangles.empty() &&
      pixel_area / static_cast<double>(content.triangles.size()) >= kPngEdgeMinimumArea;
  for (const DrawnTriangle& triangle : content.triangles) {
    if (!edges && !triangle.flipped) continue;
    const Rgb color = triangle.flipped ? detail::kFlippedOutline : detail::kEdgeColor;
    for (int corner = 0; corner < 3; ++corner) {
      draw_line(image, triangle.corners[corner], triangle.corners[(corner + 1) % 3], color);
    }
  }
  std::string bytes;
  if (stbi_write_png_to_func(append_bytes, &bytes, image.size(), image.size(), 3,
                             image.pixels().data(), image.size() * 3) == 0) {
    throw Error(Status::io_error, "write_picture: the PNG encoder failed");
  }
  return bytes;
}

}  // namespace

void write_picture(const fs::path& path, const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                   const Eigen::MatrixX3i& uv_faces, const PictureOptions& options) {
  const PictureFormat format = format_of(path);  // Before any work: a typo fails fast.
  const PictureContent content = lay_out(mesh3d, uv, uv_faces, options, format);
  detail::write_file_atomically(path, format == PictureFormat::svg ? render_svg(content)
                                                                  : render_png(content));
}

}  // namespace harmonia
