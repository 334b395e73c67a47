// Text lines rasterized with stb_truetype from the embedded DejaVu Sans: glyphs placed at
// fractional pen positions (stb_truetype's subpixel shift), kerned, and merged into one coverage
// bitmap by taking the larger coverage where neighbouring glyphs overlap.
#include "picture/text_rasterizer.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <stb_truetype.h>

#include "harmonia/types.h"
#include "picture/embedded_font.h"

namespace harmonia::detail {

std::vector<char32_t> decode_utf8(std::string_view text) {
  constexpr char32_t kReplacement = 0xFFFD;
  std::vector<char32_t> code_points;
  code_points.reserve(text.size());
  std::size_t at = 0;
  while (at < text.size()) {
    const auto lead = static_cast<unsigned char>(text[at]);
    int continuation = 0;
    char32_t value = 0;
    if (lead < 0x80) {
      value = lead;
    } else if ((lead & 0xE0) == 0xC0) {
      continuation = 1, value = lead & 0x1F;
    } else if ((lead & 0xF0) == 0xE0) {
      continuation = 2, value = lead & 0x0F;
    } else if ((lead & 0xF8) == 0xF0) {
      continuation = 3, value = lead & 0x07;
    } else {
      code_points.push_back(kReplacement);
      ++at;
      continue;
    }
    bool well_formed = at + continuation < text.size();
    for (int i = 1; well_formed && i <= continuation; ++i) {
      const auto next = static_cast<unsigned char>(text[at + i]);
      well_formed = (next & 0xC0) == 0x80;
      value = (value << 6) | (next & 0x3F);
    }
    if (!well_formed) {
      code_points.push_back(kReplacement);
      ++at;
      continue;
    }
    code_points.push_back(value);
    at += continuation + 1;
  }
  return code_points;
}

TextCoverage TextCoverage::turned_counterclockwise() const {
  // Pixel (x, y) goes to (y, width - 1 - x): the text's left end comes to the bottom.
  TextCoverage turned;
  turned.width = height;
  turned.height = width;
  turned.values.assign(values.size(), 0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      turned.values[static_cast<std::size_t>(width - 1 - x) * turned.width + y] = at(x, y);
    }
  }
  turned.origin_x = baseline;
  turned.baseline = width - 1 - origin_x;
  return turned;
}

TextRasterizer::TextRasterizer() : font_(std::make_unique<stbtt_fontinfo>()) {
  const int offset = stbtt_GetFontOffsetForIndex(dejavu_sans_ttf, 0);
  if (offset < 0 || stbtt_InitFont(font_.get(), dejavu_sans_ttf, offset) == 0) {
    throw Error(Status::io_error, "the embedded font (DejaVu Sans, " +
                                      std::to_string(dejavu_sans_ttf_size) +
                                      " bytes) cannot be parsed: the library was built wrongly");
  }
}

TextRasterizer::~TextRasterizer() = default;

namespace {

// One glyph as placed on the line: its index and the pen position (in pixels) it starts at.
struct PlacedGlyph {
  int glyph = 0;
  double pen_x = 0.0;
};

struct GlyphLine {
  std::vector<PlacedGlyph> glyphs;
  double advance = 0.0;  // Pixels from the first pen position to the last.
};

GlyphLine place_glyphs(const stbtt_fontinfo& font, std::string_view text, float scale) {
  GlyphLine line;
  int previous = -1;
  for (const char32_t code_point : decode_utf8(text)) {
    const int glyph = stbtt_FindGlyphIndex(&font, static_cast<int>(code_point));
    if (previous >= 0) line.advance += scale * stbtt_GetGlyphKernAdvance(&font, previous, glyph);
    line.glyphs.push_back({glyph, line.advance});
    int advance_width = 0, left_side_bearing = 0;
    stbtt_GetGlyphHMetrics(&font, glyph, &advance_width, &left_side_bearing);
    line.advance += scale * advance_width;
    previous = glyph;
  }
  return line;
}

}  // namespace

double TextRasterizer::width(std::string_view text, double font_size) const {
  const float scale = stbtt_ScaleForMappingEmToPixels(font_.get(), static_cast<float>(font_size));
  return place_glyphs(*font_, text, scale).advance;
}

TextCoverage TextRasterizer::rasterize(std::string_view text, double font_size) const {
  const float scale = stbtt_ScaleForMappingEmToPixels(font_.get(), static_cast<float>(font_size));
  const GlyphLine line = place_glyphs(*font_, text, scale);

  // Each glyph's pixel box relative to the pen origin (whole pixels, y down), and their union.
  struct GlyphBox {
    int x0, y0, x1, y1;
    float shift_x;
  };
  std::vector<GlyphBox> boxes;
  int left = 0, top = 0, right = 1, bottom = 1;
  for (const PlacedGlyph& placed : line.glyphs) {
    const double whole = std::floor(placed.pen_x);
    GlyphBox box{};
    box.shift_x = static_cast<float>(placed.pen_x - whole);
    stbtt_GetGlyphBitmapBoxSubpixel(font_.get(), placed.glyph, scale, scale, box.shift_x, 0.0f,
                                    &box.x0, &box.y0, &box.x1, &box.y1);
    box.x0 += static_cast<int>(whole);
    box.x1 += static_cast<int>(whole);
    boxes.push_back(box);
    if (box.x1 <= box.x0 || box.y1 <= box.y0) continue;  // A space: nothing to draw.
    left = std::min(left, box.x0);
    right = std::max(right, box.x1);
    top = std::min(top, box.y0);
    bottom = std::max(bottom, box.y1);
  }

  TextCoverage coverage;
  coverage.width = right - left;
  coverage.height = bottom - top;
  coverage.origin_x = -left;
  coverage.baseline = -top;
  coverage.values.assign(static_cast<std::size_t>(coverage.width) * coverage.height, 0);
  std::vector<std::uint8_t> glyph_pixels;
  for (std::size_t i = 0; i < line.glyphs.size(); ++i) {
    const GlyphBox& box = boxes[i];
    const int glyph_width = box.x1 - box.x0, glyph_height = box.y1 - box.y0;
    if (glyph_width <= 0 || glyph_height <= 0) continue;
    glyph_pixels.assign(static_cast<std::size_t>(glyph_width) * glyph_height, 0);
    stbtt_MakeGlyphBitmapSubpixel(font_.get(), glyph_pixels.data(), glyph_width, glyph_height,
                                  glyph_width, scale, scale, box.shift_x, 0.0f,
                                  line.glyphs[i].glyph);
    for (int y = 0; y < glyph_height; ++y) {
      for (int x = 0; x < glyph_width; ++x) {
        std::uint8_t& target =
            coverage.values[static_cast<std::size_t>(box.y0 - top + y) * coverage.width +
                            (box.x0 - left + x)];
        target = std::max(target, glyph_pixels[static_cast<std::size_t>(y) * glyph_width + x]);
      }
    }
  }
  return coverage;
}

double fitted_size(const TextRasterizer& font, const std::string& text, double preferred,
                   double room) {
  const double width = font.width(text, preferred);
  return width > room && width > 0.0 ? preferred * room / width : preferred;
}

}  // namespace harmonia::detail
