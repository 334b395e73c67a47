// The PNG canvas: every primitive decides pixel by pixel from the pixel's centre, in a fixed order,
// with integer blending, so that a picture is the same bytes on every run.
#include "picture/raster_image.h"

#include <algorithm>
#include <cmath>

#include <stb_image_write.h>

#include "harmonia/types.h"

namespace harmonia::detail {

RgbImage::RgbImage(int width, int height, const Rgb& background)
    : width_(width), height_(height), pixels_(static_cast<std::size_t>(width) * height * 3) {
  for (std::size_t at = 0; at < pixels_.size(); at += 3) {
    pixels_[at] = background.red;
    pixels_[at + 1] = background.green;
    pixels_[at + 2] = background.blue;
  }
}

Rgb RgbImage::at(int x, int y) const {
  const std::size_t at = (static_cast<std::size_t>(y) * width_ + x) * 3;
  return {pixels_[at], pixels_[at + 1], pixels_[at + 2]};
}

void RgbImage::set(int x, int y, const Rgb& color) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  const std::size_t at = (static_cast<std::size_t>(y) * width_ + x) * 3;
  pixels_[at] = color.red;
  pixels_[at + 1] = color.green;
  pixels_[at + 2] = color.blue;
}

void RgbImage::blend(int x, int y, const Rgb& color, int coverage) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_ || coverage <= 0) return;
  if (coverage >= 255) return set(x, y, color);
  const std::size_t at = (static_cast<std::size_t>(y) * width_ + x) * 3;
  const auto mix = [coverage](std::uint8_t under, std::uint8_t over) {
    return static_cast<std::uint8_t>((under * (255 - coverage) + over * coverage + 127) / 255);
  };
  pixels_[at] = mix(pixels_[at], color.red);
  pixels_[at + 1] = mix(pixels_[at + 1], color.green);
  pixels_[at + 2] = mix(pixels_[at + 2], color.blue);
}

namespace {

// The whole-pixel range [first, last] of pixels whose centres may lie in [low, high], clipped to
// [0, size - 1]; empty (first > last) when there is none.
struct PixelRange {
  int first = 0;
  int last = -1;
};

PixelRange pixel_range(double low, double high, int size) {
  if (!(high >= low) || size <= 0) return {};
  const double first = std::max(std::floor(low), 0.0);
  const double last = std::min(std::ceil(high), static_cast<double>(size - 1));
  if (first > last) return {};
  return {static_cast<int>(first), static_cast<int>(last)};
}

// Twice the signed area of (a, b, p): which side of the line a -> b the point p lies on.
double edge_function(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b) {
  const Eigen::Vector2d along = b - a;
  const double length_squared = along.squaredNorm();
  const double t =
      length_squared > 0.0 ? std::clamp((p - a).dot(along) / length_squared, 0.0, 1.0) : 0.0;
  return (p - (a + t * along)).norm();
}

void append_bytes(void* context, void* data, int size) {
  auto* bytes = static_cast<std::string*>(context);
  bytes->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

}  // namespace

void RgbImage::fill_box(const PixelBox& box, const Rgb& color) {
  const PixelRange columns = pixel_range(box.left - 0.5, box.right - 0.5, width_);
  const PixelRange rows = pixel_range(box.top - 0.5, box.bottom - 0.5, height_);
  for (int y = rows.first; y <= rows.last; ++y) {
    for (int x = columns.first; x <= columns.last; ++x) {
      const double cx = x + 0.5, cy = y + 0.5;
      if (cx >= box.left && cx < box.right && cy >= box.top && cy < box.bottom) set(x, y, color);
    }
  }
}

void RgbImage::fill_triangle(const std::array<Eigen::Vector2d, 3>& corners, const Rgb& color) {
  const Eigen::Vector2d& a = corners[0];
  Eigen::Vector2d b = corners[1], c = corners[2];
  const double twice_area = edge_function(a, b, c);
  if (twice_area == 0.0) {  // A sliver with no interior: still show it as its outline.
    draw_line(a, b, color);
    draw_line(b, c, color);
    return;
  }
  if (twice_area < 0.0) std::swap(b, c);
  const PixelRange columns =
      pixel_range(std::min({a.x(), b.x(), c.x()}) - 0.5, std::max({a.x(), b.x(), c.x()}), width_);
  const PixelRange rows =
      pixel_range(std::min({a.y(), b.y(), c.y()}) - 0.5, std::max({a.y(), b.y(), c.y()}), height_);
  for (int y = rows.first; y <= rows.last; ++y) {
    for (int x = columns.first; x <= columns.last; ++x) {
      const Eigen::Vector2d centre(x + 0.5, y + 0.5);
      if (edge_function(a, b, centre) >= 0.0 && edge_function(b, c, centre) >= 0.0 &&
          edge_function(c, a, centre) >= 0.0) {
        set(x, y, color);
      }
    }
  }
}

void RgbImage::draw_line(const Eigen::Vector2d& from, const Eigen::Vector2d& to, const Rgb& color) {
  const Eigen::Vector2d delta = to - from;
  const int steps =
      static_cast<int>(std::ceil(std::max(std::abs(delta.x()), std::abs(delta.y())))) + 1;
  for (int step = 0; step <= steps; ++step) {
    const Eigen::Vector2d point = from + delta * (static_cast<double>(step) / steps);
    set(static_cast<int>(std::floor(point.x())), static_cast<int>(std::floor(point.y())), color);
  }
}

void RgbImage::stroke_polyline(const std::vector<Eigen::Vector2d>& points, double line_width,
                               const Rgb& color, const PixelBox& clip) {
  if (points.empty()) return;
  // The largest coverage any segment gives each pixel of the clip box, then one blend per pixel.
  const PixelRange clip_columns = pixel_range(clip.left, clip.right - 1.0, width_);
  const PixelRange clip_rows = pixel_range(clip.top, clip.bottom - 1.0, height_);
  if (clip_columns.first > clip_columns.last || clip_rows.first > clip_rows.last) return;
  const int box_width = clip_columns.last - clip_columns.first + 1;
  const int box_height = clip_rows.last - clip_rows.first + 1;
  std::vector<double> coverage(static_cast<std::size_t>(box_width) * box_height, 0.0);
  const double half = 0.5 * line_width;
  const double reach = half + 1.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d& a = points[i];
    const Eigen::Vector2d& b = points[i + 1 < points.size() ? i + 1 : i];
    const PixelRange columns =
        pixel_range(std::min(a.x(), b.x()) - reach, std::max(a.x(), b.x()) + reach, width_);
    const PixelRange rows =
        pixel_range(std::min(a.y(), b.y()) - reach, std::max(a.y(), b.y()) + reach, height_);
    for (int y = std::max(rows.first, clip_rows.first); y <= std::min(rows.last, clip_rows.last);
         ++y) {
      for (int x = std::max(columns.first, clip_columns.first);
           x <= std::min(columns.last, clip_columns.last); ++x) {
        const double distance = distance_to_segment(Eigen::Vector2d(x + 0.5, y + 0.5), a, b);
        const double value = std::clamp(half + 0.5 - distance, 0.0, 1.0);
        double& cell = coverage[static_cast<std::size_t>(y - clip_rows.first) * box_width +
                                (x - clip_columns.first)];
        cell = std::max(cell, value);
      }
    }
  }
  for (int y = 0; y < box_height; ++y) {
    for (int x = 0; x < box_width; ++x) {
      const double value = coverage[static_cast<std::size_t>(y) * box_width + x];
      blend(clip_columns.first + x, clip_rows.first + y, color,
            static_cast<int>(std::lround(255.0 * value)));
    }
  }
}

void RgbImage::draw_text(const TextCoverage& text, double pen_x, double baseline_y,
                         const Rgb& color) {
  const int left = static_cast<int>(std::lround(pen_x)) - text.origin_x;
  const int top = static_cast<int>(std::lround(baseline_y)) - text.baseline;
  for (int y = 0; y < text.height; ++y) {
    for (int x = 0; x < text.width; ++x) blend(left + x, top + y, color, text.at(x, y));
  }
}

std::string RgbImage::encode_png() const {
  std::string bytes;
  if (stbi_write_png_to_func(append_bytes, &bytes, width_, height_, 3, pixels_.data(),
                             width_ * 3) == 0) {
    throw Error(Status::io_error, "the PNG encoder failed");
  }
  return bytes;
}

void RgbImage::outline_box(const PixelBox& box, double line_width, const Rgb& color) {
  fill_box({box.left, box.top, box.right, box.top + line_width}, color);
  fill_box({box.left, box.bottom - line_width, box.right, box.bottom}, color);
  fill_box({box.left, box.top, box.left + line_width, box.bottom}, color);
  fill_box({box.right - line_width, box.top, box.right, box.bottom}, color);
}

}  // namespace harmonia::detail
