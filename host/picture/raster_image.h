#pragma once
// Internal: the RGB canvas the PNG pictures are drawn on, with the few primitives they need
// (filled triangles and boxes, one-pixel lines, antialiased wide polylines, text) and the PNG
// encoding (stb_image_write). Integer blending and fixed drawing orders: the same calls give the
// same bytes on every run.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "picture/color_map.h"
#include "picture/pixel_box.h"
#include "picture/text_rasterizer.h"

namespace harmonia::detail {

class RgbImage {
 public:
  RgbImage(int width, int height, const Rgb& background);

  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  [[nodiscard]] Rgb at(int x, int y) const;

  // Pixels outside the image are ignored by every drawing call.
  void set(int x, int y, const Rgb& color);
  // Mixes `color` into a pixel by `coverage` (0: unchanged, 255: replaced), rounded.
  void blend(int x, int y, const Rgb& color, int coverage);

  // The pixels whose centres lie in [left, right) x [top, bottom).
  void fill_box(const PixelBox& box, const Rgb& color);
  // The pixels whose centres lie inside the triangle (edges included), whatever its winding; a
  // triangle without area is drawn as its outline so that it stays visible.
  void fill_triangle(const std::array<Eigen::Vector2d, 3>& corners, const Rgb& color);
  // A one-pixel line, at least one sample per pixel along the longer axis.
  void draw_line(const Eigen::Vector2d& from, const Eigen::Vector2d& to, const Rgb& color);
  // A polyline `line_width` pixels wide with round joins and ends, antialiased, drawn only inside
  // `clip`. Where its own segments overlap it is drawn once (no darker joints).
  void stroke_polyline(const std::vector<Eigen::Vector2d>& points, double line_width,
                       const Rgb& color, const PixelBox& clip);
  // The border of `box`, `line_width` pixels wide, inside the box.
  void outline_box(const PixelBox& box, double line_width, const Rgb& color);
  // Text whose pen starts at (pen_x, baseline_y), both rounded to whole pixels.
  void draw_text(const TextCoverage& text, double pen_x, double baseline_y, const Rgb& color);

  // The image as PNG bytes; throws Error(io_error) if the encoder fails.
  [[nodiscard]] std::string encode_png() const;

 private:
  int width_;
  int height_;
  std::vector<std::uint8_t> pixels_;
};

}  // namespace harmonia::detail
