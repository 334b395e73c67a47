#pragma once
// A PNG read back for the picture tests (stb_image, compiled once in decoded_png.cpp).

#include <array>
#include <cstddef>
#include <utility>
#include <filesystem>
#include <vector>

#include "picture/color_map.h"

namespace harmonia::testing {

struct DecodedImage {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  // width * height * 3, row by row from the top
  [[nodiscard]] detail::Rgb at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

//! One pixel in from each corner of the picture, (x, y): where only background should be.
[[nodiscard]] inline std::array<std::pair<int, int>, 4> corner_pixels(const DecodedImage& image) {
  return {{{1, 1}, {image.width - 2, 1}, {1, image.height - 2}, {image.width - 2, image.height - 2}}};
}

//! Whether a pixel shows the pictures' background.
[[nodiscard]] inline bool is_background(const detail::Rgb& color) { return color == detail::kBackground; }

//! Side-by-side pictures (deform, transfer): the pixels of one half (0 left, 1 right), in the band
//! above the captions and the legend, that satisfy `test`.
template <typename Test>
[[nodiscard]] int count_in_view(const DecodedImage& image, int half, const Test& test) {
  const int half_width = image.width / 2;
  int count = 0;
  for (int y = 0; y < image.height * 85 / 100; ++y)
    for (int x = half * half_width; x < (half + 1) * half_width; ++x) count += test(image.at(x, y)) ? 1 : 0;
  return count;
}

//! Side-by-side pictures: the pixels of that band where the right half differs from the left.
[[nodiscard]] inline int differences_between_halves(const DecodedImage& image) {
  const int half_width = image.width / 2;
  int count = 0;
  for (int y = 0; y < image.height * 85 / 100; ++y)
    for (int x = 0; x < half_width; ++x) count += image.at(x, y) == image.at(x + half_width, y) ? 0 : 1;
  return count;
}

//! The picture's pixels as RGB; empty (width 0) when it cannot be read.
[[nodiscard]] DecodedImage decode_png(const std::filesystem::path& path);

}  // namespace harmonia::testing
