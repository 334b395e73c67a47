// Pictures of a UV layout: every triangle filled with the colour of its distortion, flipped ones
// black with a magenta outline, under a title and above the colour bar that says what the colours
// mean; as SVG text or as a PNG rasterized here (picture/raster_image.h) with its text drawn from the
// embedded font (picture/text_rasterizer.h). Both formats take their geometry from one PictureFrame.
#include "harmonia/picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "harmonia/metrics.h"
#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "picture/color_bar_drawing.h"
#include "picture/color_map.h"
#include "picture/picture_format.h"
#include "picture/picture_frame.h"
#include "picture/raster_image.h"
#include "picture/svg_markup.h"
#include "picture/text_rasterizer.h"
#include "planar/uv_layout_checks.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;
using detail::fixed_number;
using detail::PictureFormat;
using detail::PixelBox;
using detail::Rgb;

// One triangle as drawn: pixel coordinates (y down), fill colour, whether it is flipped.
struct DrawnTriangle {
  std::array<Eigen::Vector2d, 3> corners;
  Rgb fill;
  bool flipped = false;
};

// What both formats draw: the frame, the triangles in drawing order (flipped ones last, so they
// stay visible on top of whatever overlaps them) and the texts with the sizes that fit them.
struct PictureContent {
  int size = 0;
  detail::PictureFrame frame;
  std::vector<DrawnTriangle> triangles;
  bool draw_edges = false;
  std::string title;
  double title_size = 0.0;
  detail::ColorBar color_bar;
  double caption_size = 0.0;
  double tick_label_size = 0.0;
  std::string flipped_label;
  double flipped_label_size = 0.0;
};


// Text sizes: the frame's, or smaller where a text would not fit its room.
void fit_texts(PictureContent& content, const detail::TextRasterizer& font) {
  const detail::PictureFrame& frame = content.frame;
  content.title_size =
      detail::fitted_size(font, content.title, frame.title_size, content.size - 2.0 * frame.margin);
  content.caption_size = detail::fitted_size(font, content.color_bar.caption, frame.label_size,
                                     content.size - frame.margin - frame.color_bar.left);
  // Tick labels no wider than 0.8 of the closest ticks' distance, so that neighbours stay apart.
  double closest_ticks = frame.color_bar.width(), widest_label = 0.0;
  const std::vector<detail::ColorBarTick>& ticks = content.color_bar.ticks;
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    widest_label = std::max(widest_label, font.width(ticks[i].label, frame.label_size));
    if (i > 0) {
      closest_ticks = std::min(closest_ticks, (ticks[i].position - ticks[i - 1].position) *
                                                  frame.color_bar.width());
    }
  }
  content.tick_label_size =
      widest_label > 0.8 * closest_ticks ? frame.label_size * 0.8 * closest_ticks / widest_label
                                         : frame.label_size;
  content.flipped_label_size = detail::fitted_size(font, content.flipped_label, frame.label_size,
                                           content.size - frame.margin - frame.flipped_label_x);
}

PictureContent lay_out(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                       const Eigen::MatrixX3i& uv_faces, const PictureOptions& options,
                       const detail::TextRasterizer& font) {
  if (options.size_pixels < 16 || options.size_pixels > 16384) {
    throw Error(Status::invalid_input, "write_picture: size_pixels " +
                                           std::to_string(options.size_pixels) +
                                           " is outside [16, 16384]");
  }
  const DistortionMetrics metrics = evaluate_map(mesh3d, uv, uv_faces);
  PictureContent content;
  content.size = options.size_pixels;
  content.frame = detail::picture_frame(options.size_pixels);
  const detail::PictureFrame& frame = content.frame;
  content.title = options.title.empty() ? picture_headline(metrics) : options.title;
  content.color_bar = options.coloring == PictureColoring::conformal_distortion
                          ? detail::conformal_color_bar()
                          : detail::area_color_bar();
  content.flipped_label = "flipped triangles (" + std::to_string(metrics.flipped_triangles) + ")";
  fit_texts(content, font);

  // Fit the bounding box of the used UVs inside the layout box.
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
  const PixelBox& room = frame.layout;
  const Eigen::Vector2d extent = (high - low).cwiseMax(1e-300);
  const double scale = std::min(room.width() / extent.x(), room.height() / extent.y());
  const Eigen::Vector2d centre = 0.5 * (low + high);
  const auto to_pixels = [&](const Eigen::Vector2d& point) {
    return Eigen::Vector2d(room.left + 0.5 * room.width() + scale * (point.x() - centre.x()),
                           room.top + 0.5 * room.height() - scale * (point.y() - centre.y()));
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

// The outline widths: triangle edges, the flipped outline (twice as wide), the legend's lines.
double edge_width(const PictureContent& content) { return std::max(0.2, content.size / 4000.0); }
double legend_line_width(const PictureContent& content) {
  return std::max(1.0, content.frame.label_size / 12.0);
}

// ---------------------------------------------------------------------------------------------
// SVG

constexpr Eigen::Index kSvgEdgeLimit = 200000;  // Above this many faces edges would hide the fill.

std::string svg_box(const PixelBox& box, const std::string& style) {
  return "<rect x=\"" + fixed_number(box.left, 2) + "\" y=\"" + fixed_number(box.top, 2) +
         "\" width=\"" + fixed_number(box.width(), 2) + "\" height=\"" +
         fixed_number(box.height(), 2) + "\" " + style + "/>\n";
}

std::string svg_legend(const PictureContent& content) {
  const detail::PictureFrame& frame = content.frame;
  const detail::ColorBar& bar = content.color_bar;
  const std::string line_width = fixed_number(legend_line_width(content), 2);
  const std::string ink = detail::hex_color(detail::kLegendColor);
  std::string svg = "<defs><linearGradient id=\"color-bar\" x1=\"0\" y1=\"0\" x2=\"1\" y2=\"0\">";
  for (const auto& [offset, color] : bar.stops) {
    svg += "<stop offset=\"" + fixed_number(offset, 3) + "\" stop-color=\"" +
           detail::hex_color(color) + "\"/>";
  }
  svg += "</linearGradient></defs>\n";
  svg += detail::svg_text(frame.color_bar.left, frame.caption_baseline, content.caption_size,
                          detail::TextAnchor::start, detail::kLegendColor, bar.caption);
  svg += svg_box(frame.color_bar, "fill=\"url(#color-bar)\" stroke=\"" + ink +
                                      "\" stroke-width=\"" + line_width + "\"");
  for (const detail::ColorBarTick& tick : bar.ticks) {
    const double x = frame.color_bar.left + tick.position * frame.color_bar.width();
    svg += "<line x1=\"" + fixed_number(x, 2) + "\" y1=\"" +
           fixed_number(frame.color_bar.bottom, 2) + "\" x2=\"" + fixed_number(x, 2) + "\" y2=\"" +
           fixed_number(frame.color_bar.bottom + frame.tick_length, 2) + "\" stroke=\"" + ink +
           "\" stroke-width=\"" + line_width + "\"/>\n";
    svg += detail::svg_text(x, frame.tick_label_baseline, content.tick_label_size,
                            detail::TextAnchor::middle, detail::kLegendColor, tick.label);
  }
  svg += svg_box(frame.flipped_swatch,
                 "fill=\"" + detail::hex_color(detail::kFlippedFill) + "\" stroke=\"" +
                     detail::hex_color(detail::kFlippedOutline) + "\" stroke-width=\"" +
                     fixed_number(2.0 * legend_line_width(content), 2) + "\"");
  svg += detail::svg_text(frame.flipped_label_x, frame.flipped_label_baseline,
                          content.flipped_label_size, detail::TextAnchor::start,
                          detail::kLegendColor, content.flipped_label);
  return svg;
}

std::string render_svg(const PictureContent& content) {
  const std::string size = std::to_string(content.size);
  std::string svg;
  svg.reserve(4000 + content.triangles.size() * 120);
  svg += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + size + "\" height=\"" + size +
         "\" viewBox=\"0 0 " + size + " " + size + "\">\n";
  svg += "<rect width=\"" + size + "\" height=\"" + size + "\" fill=\"" +
         detail::hex_color(detail::kBackground) + "\"/>\n";
  svg += detail::svg_text(content.frame.margin, content.frame.title_baseline, content.title_size,
                          detail::TextAnchor::start, detail::kLegendColor, content.title);
  const bool edges =
      content.draw_edges && static_cast<Eigen::Index>(content.triangles.size()) <= kSvgEdgeLimit;
  const std::string edge_style =
      edges ? " stroke=\"" + detail::hex_color(detail::kEdgeColor) + "\" stroke-width=\"" +
                  fixed_number(edge_width(content), 2) + "\""
            : std::string(" stroke=\"none\"");
  const std::string flipped_style = " stroke=\"" + detail::hex_color(detail::kFlippedOutline) +
                                    "\" stroke-width=\"" +
                                    fixed_number(2.0 * edge_width(content), 2) + "\"";
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
  svg += svg_legend(content);
  return svg + "</svg>\n";
}

// ---------------------------------------------------------------------------------------------
// PNG

// Below this mean triangle area (in pixels) edges would cover the colours; they are left out.
constexpr double kPngEdgeMinimumArea = 40.0;

double pixel_area(const DrawnTriangle& triangle) {
  const Eigen::Vector2d e1 = triangle.corners[1] - triangle.corners[0];
  const Eigen::Vector2d e2 = triangle.corners[2] - triangle.corners[0];
  return 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
}

// A box outline `width` pixels wide, drawn inside the box.

void draw_legend_png(detail::RgbImage& image, const PictureContent& content,
                     const detail::TextRasterizer& font) {
  const detail::PictureFrame& frame = content.frame;
  const detail::ColorBar& bar = content.color_bar;
  const double line = legend_line_width(content);
  detail::ColorBarPlacement placement;
  placement.box = frame.color_bar;
  placement.caption_baseline = frame.caption_baseline;
  placement.caption_size = content.caption_size;
  placement.tick_length = frame.tick_length;
  placement.tick_label_baseline = frame.tick_label_baseline;
  placement.tick_label_size = content.tick_label_size;
  placement.line_width = line;
  detail::draw_color_bar(image, bar, placement, font, detail::kLegendColor);
  image.fill_box(frame.flipped_swatch, detail::kFlippedFill);
  image.outline_box(frame.flipped_swatch, 2.0 * line, detail::kFlippedOutline);
  image.draw_text(font.rasterize(content.flipped_label, content.flipped_label_size),
                  frame.flipped_label_x, frame.flipped_label_baseline, detail::kLegendColor);
}

std::string render_png(const PictureContent& content, const detail::TextRasterizer& font) {
  detail::RgbImage image(content.size, content.size, detail::kBackground);
  image.draw_text(font.rasterize(content.title, content.title_size), content.frame.margin,
                  content.frame.title_baseline, detail::kLegendColor);
  double drawn_area = 0.0;
  for (const DrawnTriangle& triangle : content.triangles) {
    image.fill_triangle(triangle.corners, triangle.fill);
    drawn_area += pixel_area(triangle);
  }
  const bool edges =
      content.draw_edges && !content.triangles.empty() &&
      drawn_area / static_cast<double>(content.triangles.size()) >= kPngEdgeMinimumArea;
  for (const DrawnTriangle& triangle : content.triangles) {
    if (!edges && !triangle.flipped) continue;
    const Rgb color = triangle.flipped ? detail::kFlippedOutline : detail::kEdgeColor;
    for (int corner = 0; corner < 3; ++corner) {
      image.draw_line(triangle.corners[corner], triangle.corners[(corner + 1) % 3], color);
    }
  }
  draw_legend_png(image, content, font);
  return image.encode_png();
}

}  // namespace

std::string picture_headline(const DistortionMetrics& metrics) {
  return std::to_string(metrics.flipped_triangles) + " flipped, conformal " +
         fixed_number(metrics.conformal_distortion_mean, 2) + ", area " +
         fixed_number(metrics.area_distortion_mean, 2);
}

void write_picture(const fs::path& path, const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                   const Eigen::MatrixX3i& uv_faces, const PictureOptions& options) {
  const PictureFormat format = detail::picture_format(path, "write_picture");  // Before any work.
  const detail::TextRasterizer font;
  const PictureContent content = lay_out(mesh3d, uv, uv_faces, options, font);
  detail::write_file_atomically(path, format == PictureFormat::svg ? render_svg(content)
                                                                  : render_png(content, font));
}

}  // namespace harmonia
