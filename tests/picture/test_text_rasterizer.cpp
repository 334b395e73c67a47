// The text of the PNG pictures: UTF-8 decoding, advance widths that scale with the font size,
// glyph coverage of the embedded DejaVu Sans where the font's metrics put it, the quarter turn of
// y-axis labels, and the same pixels on every call.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "picture/text_rasterizer.h"

namespace harmonia {
namespace {

using detail::TextCoverage;
using detail::TextRasterizer;

TEST(Utf8, DecodesGreekAndMathSignsAndReplacesMalformedBytes) {
  EXPECT_EQ(detail::decode_utf8("a\xcf\x83\xe2\x89\xa5"),
            (std::vector<char32_t>{U'a', U'\u03c3', U'\u2265'}));
  // A stray continuation byte, an invalid lead byte, and a sequence cut short at the end.
  EXPECT_EQ(detail::decode_utf8("\x89x\xffy\xe2\x89"),
            (std::vector<char32_t>{0xFFFD, U'x', 0xFFFD, U'y', 0xFFFD, 0xFFFD}));
}

// Rows and columns with any coverage.
struct InkBox {
  int top = -1, bottom = -1, left = -1, right = -1;
};
InkBox ink_box(const TextCoverage& text) {
  InkBox box;
  for (int y = 0; y < text.height; ++y) {
    for (int x = 0; x < text.width; ++x) {
      if (text.at(x, y) == 0) continue;
      if (box.top < 0) box.top = y;
      box.bottom = y;
      box.left = box.left < 0 ? x : std::min(box.left, x);
      box.right = std::max(box.right, x);
    }
  }
  return box;
}

TEST(TextRasterizer, WidthScalesExactlyWithTheFontSize) {
  const TextRasterizer font;
  const double small = font.width("harmonia 1.91", 10.0);
  EXPECT_GT(small, 0.0);
  // Doubling the size doubles stb_truetype's (float) scale exactly, and with it every advance.
  EXPECT_EQ(font.width("harmonia 1.91", 20.0), 2.0 * small);
  EXPECT_EQ(font.width("", 20.0), 0.0);
}

TEST(TextRasterizer, CapitalsReachTheFontsCapHeightAboveTheBaseline) {
  const TextRasterizer font;
  const TextCoverage text = font.rasterize("HH", 100.0);
  const InkBox box = ink_box(text);
  ASSERT_GE(box.top, 0);
  // DejaVu Sans: capitals stand on the baseline and are 1493/2048 em tall; a partly covered row
  // at either end may add one row each.
  EXPECT_NEAR(text.baseline - box.top, 1493.0 / 2048.0 * 100.0, 1.5);
  EXPECT_NEAR(box.bottom + 1, text.baseline, 1.0);
  // The ink starts right of the pen (H's left side bearing) and ends within the advance.
  EXPECT_GE(box.left, text.origin_x);
  EXPECT_LE(box.right - text.origin_x, font.width("HH", 100.0));
}

TEST(TextRasterizer, SpacesHaveNoInkAndTheSamePixelsComeEveryTime) {
  const TextRasterizer font;
  const TextCoverage spaces = font.rasterize("   ", 30.0);
  EXPECT_TRUE(std::all_of(spaces.values.begin(), spaces.values.end(),
                          [](std::uint8_t value) { return value == 0; }));
  const TextCoverage first = font.rasterize("conformal σ1/σ2 ≥4", 17.3);
  const TextCoverage second = TextRasterizer().rasterize("conformal σ1/σ2 ≥4", 17.3);
  EXPECT_GT(std::count_if(first.values.begin(), first.values.end(),
                          [](std::uint8_t value) { return value > 0; }),
            100);
  EXPECT_EQ(first.values, second.values);
  EXPECT_EQ(first.width, second.width);
  EXPECT_EQ(first.baseline, second.baseline);
}

TEST(TextRasterizer, QuarterTurnReadsUpwardsWithThePenAtTheBottom) {
  const TextRasterizer font;
  const TextCoverage text = font.rasterize("L1", 24.0);
  const TextCoverage turned = text.turned_counterclockwise();
  ASSERT_EQ(turned.width, text.height);
  ASSERT_EQ(turned.height, text.width);
  for (int y = 0; y < text.height; ++y) {
    for (int x = 0; x < text.width; ++x) {
      ASSERT_EQ(turned.at(y, text.width - 1 - x), text.at(x, y)) << x << "," << y;
    }
  }
  // The baseline becomes a column, the pen's start the row at the bottom end of the text.
  EXPECT_EQ(turned.origin_x, text.baseline);
  EXPECT_EQ(turned.baseline, text.width - 1 - text.origin_x);
  // The text runs upwards from there: all its ink lies on or above the pen's row.
  const InkBox box = ink_box(turned);
  EXPECT_LE(box.bottom, turned.baseline);
}

}  // namespace
}  // namespace harmonia
