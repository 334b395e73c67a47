#include "atlas/texel_bitmap.h"

#include <algorithm>
#include <bit>

namespace harmonia::detail {

namespace {

//! The bits of the last word of a row that are texels (the rest must stay clear).
std::uint64_t last_word_mask(int width) {
  const int used_bits = width % TexelBitmap::bits_per_word;
  return used_bits == 0 ? ~std::uint64_t{0} : (std::uint64_t{1} << used_bits) - 1;
}

//! One step of horizontal growth: every set texel also sets its left and right neighbours.
void grow_row_by_one(std::uint64_t* words, int word_count) {
  std::uint64_t carry_from_left = 0;  // the top bit of the word before, moving right
  for (int word = 0; word < word_count; ++word) {
    const std::uint64_t original = words[word];
    const std::uint64_t from_right = word + 1 < word_count ? words[word + 1] << 63 : 0;
    words[word] = original | (original << 1) | carry_from_left | (original >> 1) | from_right;
    carry_from_left = original >> 63;
  }
}

}  // namespace

void TexelBitmap::set_span(int x_begin, int x_end, int y) {
  std::uint64_t* words = row(y);
  for (int x = x_begin; x < x_end;) {
    const int word = x / bits_per_word, bit = x % bits_per_word;
    const int bits = std::min(bits_per_word - bit, x_end - x);
    const std::uint64_t run = bits == bits_per_word ? ~std::uint64_t{0} : ((std::uint64_t{1} << bits) - 1);
    words[word] |= run << bit;
    x += bits;
  }
}

long long TexelBitmap::count() const {
  long long total = 0;
  for (const std::uint64_t word : words_) total += std::popcount(word);
  return total;
}

TexelBitmap TexelBitmap::quarter_turned() const {
  TexelBitmap turned(height_, width_);
  for (int y = 0; y < height_; ++y) {
    const std::uint64_t* words = row(y);
    for (int word = 0; word < words_per_row_; ++word) {
      for (std::uint64_t bits = words[word]; bits != 0; bits &= bits - 1) {
        const int x = word * bits_per_word + std::countr_zero(bits);
        turned.set(height_ - 1 - y, x);
      }
    }
  }
  return turned;
}

void TexelBitmap::dilate(int radius) {
  if (radius <= 0 || height_ == 0) return;
  // The square neighbourhood is separable: grow every row sideways, then every column up and
  // down, one texel per step (radius is small: the atlas' padding).
  const std::uint64_t mask = last_word_mask(width_);
  for (int y = 0; y < height_; ++y) {
    std::uint64_t* words = row(y);
    for (int step = 0; step < radius; ++step) grow_row_by_one(words, words_per_row_);
    words[words_per_row_ - 1] &= mask;
  }
  std::vector<std::uint64_t> grown(words_.size());
  for (int step = 0; step < radius; ++step) {
    for (int y = 0; y < height_; ++y) {
      const std::uint64_t* below = y > 0 ? row(y - 1) : nullptr;
      const std::uint64_t* above = y + 1 < height_ ? row(y + 1) : nullptr;
      const std::uint64_t* here = row(y);
      std::uint64_t* out = grown.data() + static_cast<std::size_t>(y) * words_per_row_;
      for (int word = 0; word < words_per_row_; ++word) {
        out[word] = here[word] | (below ? below[word] : 0) | (above ? above[word] : 0);
      }
    }
    words_.swap(grown);
  }
}

}  // namespace harmonia::detail
