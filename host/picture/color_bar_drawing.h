#pragma once
// Internal: a colour bar drawn into a PNG picture (the layout pictures and the sphere pictures):
// its caption above it, the bar column by column (each column the colour at its centre), its
// outline, and a tick with its label below at each of the bar's ticks.

#include "picture/color_map.h"
#include "picture/pixel_box.h"
#include "picture/raster_image.h"
#include "picture/text_rasterizer.h"

namespace harmonia::detail {

//! Where a colour bar and its texts go, in pixels.
struct ColorBarPlacement {
  PixelBox box;
  double caption_baseline = 0.0;
  double caption_size = 0.0;
  double tick_length = 0.0;
  double tick_label_baseline = 0.0;
  double tick_label_size = 0.0;
  double line_width = 1.0;  //!< The outline and the ticks.
};

void draw_color_bar(RgbImage& image, const ColorBar& bar, const ColorBarPlacement& placement,
                    const TextRasterizer& font, const Rgb& ink);

}  // namespace harmonia::detail
