#include "atlas/texel_bitmap.h"

#include <algorithm>
#include <array>
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

//! Transposes a 64 x 64 bit matrix in place (bit j of word i goes to bit i of word j) by swapping
//! ever smaller off-diagonal blocks (Warren, Hacker's Delight, section 7-3).
void transpose(std::array<std::uint64_t, TexelBitmap::bits_per_word>& rows) {
  constexpr std::array<std::uint64_t, 6> low_halves = {0x00000000FFFFFFFFull, 0x0000FFFF0000FFFFull,
                                                       0x00FF00FF00FF00FFull, 0x0F0F0F0F0F0F0F0Full,
                                                       0x3333333333333333ull, 0x5555555555555555ull};
  int level = 0;
  for (int width = 32; width >= 1; width /= 2, ++level) {
    const std::uint64_t mask = low_halves[static_cast<std::size_t>(level)];
    for (int i = 0; i < TexelBitmap::bits_per_word; ++i) {
      if ((i & width) != 0) continue;
      std::uint64_t& upper = rows[static_cast<std::size_t>(i)];
      std::uint64_t& lower = rows[static_cast<std::size_t>(i + width)];
      const std::uint64_t swapped = ((upper >> width) ^ lower) & mask;
      upper ^= swapped << width;
      lower ^= swapped;
    }
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
  // 64 x 64 blocks at a time: a block of 64 rows (bottom row last) and one word of columns,
  // transposed, holds in word j the column 64 w + j from its top row up to its bottom row, which
  // is row 64 w + j of the turned image from column height - 64 - 64 g on.
  TexelBitmap turned(height_, width_);
  std::array<std::uint64_t, bits_per_word> block{};
  for (int first_row = 0; first_row < height_; first_row += bits_per_word) {
    const int first_column = height_ - bits_per_word - first_row;  // of the turned rows; may be < 0
    for (int word = 0; word < words_per_row_; ++word) {
      bool empty = true;
      for (int i = 0; i < bits_per_word; ++i) {
        const int y = first_row + bits_per_word - 1 - i;
        block[static_cast<std::size_t>(i)] = y < height_ ? row(y)[word] : 0;
        empty = empty && block[static_cast<std::size_t>(i)] == 0;
      }
      if (empty) continue;
      transpose(block);
      for (int j = 0; j < bits_per_word && word * bits_per_word + j < width_; ++j) {
        const std::uint64_t bits = block[static_cast<std::size_t>(j)];
        if (bits == 0) continue;
        std::uint64_t* target = turned.row(word * bits_per_word + j);
        if (first_column < 0) {
          target[0] |= bits >> -first_column;
          continue;
        }
        const int target_word = first_column / bits_per_word, bit = first_column % bits_per_word;
        target[target_word] |= bits << bit;
        if (bit != 0 && target_word + 1 < turned.words_per_row_) target[target_word + 1] |= bits >> (bits_per_word - bit);
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
