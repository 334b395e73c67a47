#pragma once
// Internal: where things go in a layout picture of size x size pixels, the same for SVG and PNG:
// the title line on top, the UV layout in the middle, and below it the legend (the colour bar with
// its caption and tick labels, and the swatch of flipped triangles). Text sizes follow the picture
// (about 1/64 of its side, at least 11 pixels) as long as the bands stay within 36 % of it; smaller
// pictures get smaller text.

#include "picture/pixel_box.h"

namespace harmonia::detail {

struct PictureFrame {
  double margin = 0.0;
  double title_size = 0.0;  // Font sizes, pixels per em.
  double label_size = 0.0;
  double title_baseline = 0.0;
  PixelBox layout;  // The UV layout is fitted inside (aspect ratio kept).
  PixelBox color_bar;
  double caption_baseline = 0.0;  // The colour bar's caption, above the bar from its left end.
  double tick_length = 0.0;       // Tick marks hang below the bar, their labels below them.
  double tick_label_baseline = 0.0;
  PixelBox flipped_swatch;  // Right of the colour bar; its label right of the swatch.
  double flipped_label_x = 0.0;
  double flipped_label_baseline = 0.0;
};

// Throws nothing; size is checked by the caller (16..16384).
[[nodiscard]] PictureFrame picture_frame(int size);

}  // namespace harmonia::detail
