#pragma once
// A PNG read back for the picture tests (stb_image, compiled once in decoded_png.cpp).

#include <array>
#include <cstddef>
#include <utility>
#include <filesystem>
#include <vector>

#include "io/color_map.h"

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

//! The picture's pixels as RGB; empty (width 0) when it cannot be read.
[[nodiscard]] DecodedImage decode_png(const std::filesystem::path& path);

}  // namespace harmonia::testing
