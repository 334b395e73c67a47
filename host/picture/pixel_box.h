#pragma once
// Internal: an axis-aligned box in picture pixels (x right, y down), as the picture and plot
// layouts hand them to the SVG and PNG renderers.

namespace harmonia::detail {

struct PixelBox {
  double left = 0.0;
  double top = 0.0;
  double right = 0.0;
  double bottom = 0.0;

  [[nodiscard]] double width() const { return right - left; }
  [[nodiscard]] double height() const { return bottom - top; }
};

}  // namespace harmonia::detail
