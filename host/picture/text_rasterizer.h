#pragma once
// Internal: text for the PNG pictures, drawn with the embedded DejaVu Sans (picture/embedded_font.h)
// through stb_truetype. Sizes are in pixels per em, as an SVG font-size is, so that a PNG and an
// SVG of the same picture set their text alike; the SVG writers also measure with width() to fit
// a line into the room it has. Everything here is a pure function of its arguments: the same text
// gives the same pixels on every run.

#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

// stb_truetype's parsed font (its header stays inside the library, beside its implementation).
struct stbtt_fontinfo;

namespace harmonia::detail {

// Coverage of a line of text: 0 (none) to 255 (full) per pixel, row by row. The pen starts at
// column origin_x on row baseline (both may lie inside the bitmap: glyphs reach left of the pen
// and below the baseline).
struct TextCoverage {
  int width = 0;
  int height = 0;
  int origin_x = 0;
  int baseline = 0;
  std::vector<std::uint8_t> values;

  [[nodiscard]] std::uint8_t at(int x, int y) const {
    return values[static_cast<std::size_t>(y) * width + x];
  }
  // The same text turned a quarter counter-clockwise (reading upwards, as a y axis label): the
  // pen origin moves with it, its baseline becoming a column and its start a row.
  [[nodiscard]] TextCoverage turned_counterclockwise() const;
};

class TextRasterizer {
 public:
  // Parses the embedded font; throws Error(io_error) if it cannot (only a broken build could).
  TextRasterizer();
  ~TextRasterizer();
  TextRasterizer(const TextRasterizer&) = delete;
  TextRasterizer& operator=(const TextRasterizer&) = delete;

  // Advance width in pixels of UTF-8 `text` at `font_size` pixels per em, kerning included.
  [[nodiscard]] double width(std::string_view text, double font_size) const;
  // The coverage of UTF-8 `text`; bytes that are not UTF-8 are drawn as U+FFFD.
  [[nodiscard]] TextCoverage rasterize(std::string_view text, double font_size) const;

 private:
  std::unique_ptr<stbtt_fontinfo> font_;
};

// The code points of UTF-8 text; a malformed sequence becomes U+FFFD.
[[nodiscard]] std::vector<char32_t> decode_utf8(std::string_view text);

//! The font size at which `text` fits into `room` pixels: `preferred` if it fits already.
[[nodiscard]] double fitted_size(const TextRasterizer& font, const std::string& text,
                                 double preferred, double room);

}  // namespace harmonia::detail
