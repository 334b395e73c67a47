#pragma once
// Internal: the pieces of SVG markup that the pictures and plots share: numbers written the same
// way everywhere (no locale: std::to_chars), text escaped for XML, and text elements in the font
// the PNGs use (DejaVu Sans, with the usual fallbacks for a viewer without it).

#include <string>
#include <string_view>

#include "picture/color_map.h"

namespace harmonia::detail {

// `value` with exactly `decimals` digits after the point ("-0.00" is written "0.00").
[[nodiscard]] std::string fixed_number(double value, int decimals);

// `text` with &, <, >, " and ' replaced by their entities.
[[nodiscard]] std::string xml_escape(std::string_view text);

enum class TextAnchor { start, middle, end };

// One <text> element with its baseline at (x, y), turned by `rotate_degrees` about that point
// (negative: counter-clockwise, as an SVG rotate() reads).
[[nodiscard]] std::string svg_text(double x, double y, double font_size, TextAnchor anchor,
                                   const Rgb& color, std::string_view text,
                                   double rotate_degrees = 0.0);

}  // namespace harmonia::detail
