#pragma once
// Internal: a black-and-white image of texels, one bit each, stored as rows of 64-bit words so that
// the packer tests and stamps 64 texels at a time. Texel (x, y) is bit x % 64 of word x / 64 of
// row y; x grows to the right and y upwards, as in the atlas.

#include <cstdint>
#include <vector>

namespace harmonia::detail {

class TexelBitmap {
 public:
  static constexpr int bits_per_word = 64;

  TexelBitmap() = default;
  TexelBitmap(int width, int height)
      : width_(width),
        height_(height),
        words_per_row_((width + bits_per_word - 1) / bits_per_word),
        words_(static_cast<std::size_t>(words_per_row_) * static_cast<std::size_t>(height), 0) {}

  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  [[nodiscard]] int words_per_row() const { return words_per_row_; }

  [[nodiscard]] const std::uint64_t* row(int y) const {
    return words_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(words_per_row_);
  }
  [[nodiscard]] std::uint64_t* row(int y) {
    return words_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(words_per_row_);
  }

  [[nodiscard]] bool test(int x, int y) const {
    return (row(y)[x / bits_per_word] >> (x % bits_per_word)) & 1u;
  }
  void set(int x, int y) { row(y)[x / bits_per_word] |= std::uint64_t{1} << (x % bits_per_word); }
  //! Sets texels [x_begin, x_end) of row y.
  void set_span(int x_begin, int x_end, int y);

  //! The number of texels set.
  [[nodiscard]] long long count() const;

  //! This image turned a quarter turn counter-clockwise: texel (x, y) goes to (height - 1 - y, x).
  [[nodiscard]] TexelBitmap quarter_turned() const;

  //! Every texel within `radius` texels of a set texel along both axes (a square neighbourhood,
  //! the Chebyshev distance) set too; texels that would fall outside the image are dropped.
  void dilate(int radius);

 private:
  int width_ = 0;
  int height_ = 0;
  int words_per_row_ = 0;
  std::vector<std::uint64_t> words_;
};

}  // namespace harmonia::detail
