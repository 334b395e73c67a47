// The bands of a layout picture, in multiples of the label size so that they scale together.
#include "picture/picture_frame.h"

#include <algorithm>

namespace harmonia::detail {

namespace {

// Heights in label sizes (DejaVu Sans: capitals reach 0.73 em above the baseline, descenders
// 0.24 em below it).
constexpr double kTitleToLabel = 1.25;  // Title size over label size.
constexpr double kTitleBand = 1.45;     // In title sizes: the title line and the gap below it.
constexpr double kLegendGap = 0.6;      // Between the layout and the caption.
constexpr double kCaptionLine = 1.3;    // Caption, with the gap to the bar.
constexpr double kBarHeight = 1.1;
constexpr double kTickLength = 0.35;
constexpr double kTickLabelLine = 1.25;
constexpr double kBandsInLabels = kTitleToLabel * kTitleBand + kLegendGap + kCaptionLine +
                                  kBarHeight + kTickLength + kTickLabelLine;
constexpr double kMostBandShare = 0.36;  // Of the picture's height, the rest is the layout's.

}  // namespace

PictureFrame picture_frame(int size) {
  const double side = size;
  PictureFrame frame;
  frame.margin = 0.025 * side;
  const double preferred_label = std::max(side / 64.0, 11.0);
  const double room_for_bands = kMostBandShare * side - 2.0 * frame.margin;
  const double label = std::min(preferred_label, room_for_bands / kBandsInLabels);
  frame.label_size = label;
  frame.title_size = kTitleToLabel * label;
  frame.title_baseline = frame.margin + 0.95 * frame.title_size;

  const double legend_height =
      (kLegendGap + kCaptionLine + kBarHeight + kTickLength + kTickLabelLine) * label;
  frame.layout = {frame.margin, frame.margin + kTitleBand * frame.title_size, side - frame.margin,
                  side - frame.margin - legend_height};

  // The bar leaves room at its ends for half a tick label ("≤1/4").
  const double bar_left = frame.margin + 1.2 * label;
  const double bar_top = frame.layout.bottom + (kLegendGap + kCaptionLine) * label;
  frame.color_bar = {bar_left, bar_top, bar_left + 0.42 * (side - 2.0 * frame.margin),
                     bar_top + kBarHeight * label};
  frame.caption_baseline = bar_top - 0.4 * label;
  frame.tick_length = kTickLength * label;
  frame.tick_label_baseline = frame.color_bar.bottom + frame.tick_length + 0.95 * label;

  const double swatch_left = frame.color_bar.right + 2.5 * label;
  frame.flipped_swatch = {swatch_left, bar_top, swatch_left + kBarHeight * label,
                          frame.color_bar.bottom};
  frame.flipped_label_x = frame.flipped_swatch.right + 0.5 * label;
  frame.flipped_label_baseline = bar_top + 0.5 * kBarHeight * label + 0.36 * label;
  return frame;
}

}  // namespace harmonia::detail
