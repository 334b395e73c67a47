// A colour bar drawn into a PNG picture (color_bar_drawing.h).

#include "picture/color_bar_drawing.h"

#include <algorithm>
#include <cmath>

namespace harmonia::detail {

void draw_color_bar(RgbImage& image, const ColorBar& bar, const ColorBarPlacement& placement,
                    const TextRasterizer& font, const Rgb& ink) {
  const PixelBox& box = placement.box;
  image.draw_text(font.rasterize(bar.caption, placement.caption_size), box.left,
                  placement.caption_baseline, ink);
  for (int x = static_cast<int>(std::floor(box.left)); x < static_cast<int>(std::ceil(box.right));
       ++x) {
    const double position = std::clamp((x + 0.5 - box.left) / box.width(), 0.0, 1.0);
    image.fill_box(
        {std::max<double>(x, box.left), box.top, std::min<double>(x + 1, box.right), box.bottom},
        bar.color_at(position));
  }
  image.outline_box(box, placement.line_width, ink);
  const double line = placement.line_width;
  for (const ColorBarTick& tick : bar.ticks) {
    const double x = box.left + tick.position * box.width();
    image.fill_box({x - 0.5 * line, box.bottom, x + 0.5 * line, box.bottom + placement.tick_length},
                   ink);
    image.draw_text(font.rasterize(tick.label, placement.tick_label_size),
                    x - 0.5 * font.width(tick.label, placement.tick_label_size),
                    placement.tick_label_baseline, ink);
  }
}

}  // namespace harmonia::detail
