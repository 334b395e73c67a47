#include "atlas/chart_footprint.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "atlas/chart_raster.h"

namespace harmonia::detail {

namespace {

std::vector<int> lowest_texel_per_column(const TexelBitmap& raster) {
  std::vector<int> lowest(static_cast<std::size_t>(raster.width()), raster.height());
  int unsettled = raster.width();
  for (int y = 0; y < raster.height() && unsettled > 0; ++y) {
    const std::uint64_t* words = raster.row(y);
    for (int word = 0; word < raster.words_per_row(); ++word) {
      for (std::uint64_t bits = words[word]; bits != 0; bits &= bits - 1) {
        const int x = word * TexelBitmap::bits_per_word + std::countr_zero(bits);
        if (lowest[x] == raster.height()) {
          lowest[x] = y;
          --unsettled;
        }
      }
    }
  }
  return lowest;
}

//! Calls visit(first, end) for each run [first, end) of set bits among the first `width` bits
//! of `words`, left to right.
template <typename Visit>
void for_each_run(const std::uint64_t* words, int width, Visit&& visit) {
  constexpr int bits_per_word = TexelBitmap::bits_per_word;
  for (int x = 0; x < width;) {
    const int word = x / bits_per_word, bit = x % bits_per_word;
    const std::uint64_t set = words[word] >> bit;
    if (set == 0) {
      x = (word + 1) * bits_per_word;
      continue;
    }
    const int first = x + std::countr_zero(set);
    if (first >= width) break;
    int end = first;
    while (end < width) {
      const int end_word = end / bits_per_word, end_bit = end % bits_per_word;
      const std::uint64_t clear = ~words[end_word] >> end_bit;
      if (clear != 0) {
        end = std::min(width, end + std::countr_zero(clear));
        break;
      }
      end = std::min(width, (end_word + 1) * bits_per_word);
    }
    visit(first, end);
    x = end;
  }
}

//! Sorts runs longest first, runs of one length kept in their order: a counting sort, as a run is
//! 1 to 64 texels long (a comparison sort of a large chart's thousands of runs, redone at every
//! trial density, took a tenth of the packing).
void sort_longest_first(std::vector<TexelRun>& runs) {
  constexpr int longest = TexelBitmap::bits_per_word;
  std::array<std::size_t, longest + 2> start{};  // start[64 - length + 1]: runs before that length
  for (const TexelRun& run : runs) ++start[static_cast<std::size_t>(longest - run.length + 1)];
  for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
  std::vector<TexelRun> sorted(runs.size());
  for (const TexelRun& run : runs) sorted[start[static_cast<std::size_t>(longest - run.length)]++] = run;
  runs = std::move(sorted);
}

//! The runs of set texels of a raster, cut into pieces of at most 64, longest first.
std::vector<TexelRun> runs_of(const TexelBitmap& raster) {
  std::vector<TexelRun> runs;
  constexpr int longest_piece = TexelBitmap::bits_per_word;
  for (int y = 0; y < raster.height(); ++y) {
    for_each_run(raster.row(y), raster.width(), [&](int first, int end) {
      for (int piece = first; piece < end; piece += longest_piece) {
        runs.push_back(TexelRun{y, piece, std::min(longest_piece, end - piece)});
      }
    });
  }
  sort_longest_first(runs);
  return runs;
}

//! Per band of tall_run_rows rows (tiling the raster from the bottom, the last band moved down to
//! end at the top row), the longest run of columns set in all of the band's rows, cut to 64;
//! longest first.
std::vector<TexelRun> tall_runs_of(const TexelBitmap& raster) {
  std::vector<TexelRun> tall_runs;
  std::vector<std::uint64_t> common(static_cast<std::size_t>(raster.words_per_row()));
  for (int band = 0; band * tall_run_rows < raster.height(); ++band) {
    const int y = std::min(band * tall_run_rows, raster.height() - tall_run_rows);
    if (y < 0) break;
    for (int word = 0; word < raster.words_per_row(); ++word) {
      common[word] = raster.row(y)[word];
      for (int above = 1; above < tall_run_rows; ++above) common[word] &= raster.row(y + above)[word];
    }
    TexelRun longest;
    for_each_run(common.data(), raster.width(), [&](int first, int end) {
      const int length = std::min(end - first, TexelBitmap::bits_per_word);
      if (length > longest.length) longest = TexelRun{y, first, length};
    });
    if (longest.length > 0) tall_runs.push_back(longest);
  }
  sort_longest_first(tall_runs);
  return tall_runs;
}

}  // namespace

ChartFootprint chart_footprint(const Eigen::MatrixX2d& corners, double scale) {
  const Eigen::Vector2d extent = corners.size() > 0 ? Eigen::Vector2d(corners.colwise().maxCoeff().transpose())
                                                    : Eigen::Vector2d::Zero();
  // The texels the box [lead-in, scale * extent + lead-in] touches, grown as the raster grows.
  auto texels_across = [&](double length) {
    return static_cast<int>(std::floor(scale * length + chart_lead_in + raster_tolerance)) + 1;
  };
  ChartFootprint footprint;
  TexelBitmap& raster = footprint.turned[0];
  raster = TexelBitmap(texels_across(extent.x()), texels_across(extent.y()));
  const Eigen::Vector2d lead_in(chart_lead_in, chart_lead_in);
  for (Eigen::Index row = 0; row + 2 < corners.rows(); row += 3) {
    rasterize_triangle_conservatively(scale * corners.row(row).transpose() + lead_in,
                                      scale * corners.row(row + 1).transpose() + lead_in,
                                      scale * corners.row(row + 2).transpose() + lead_in, raster);
  }
  for (int turns = 1; turns < 4; ++turns) footprint.turned[turns] = footprint.turned[turns - 1].quarter_turned();
  for (int turns = 0; turns < 4; ++turns) {
    footprint.lowest_texel[turns] = lowest_texel_per_column(footprint.turned[turns]);
    footprint.runs[turns] = runs_of(footprint.turned[turns]);
    footprint.tall_runs[turns] = tall_runs_of(footprint.turned[turns]);
  }
  return footprint;
}

Eigen::Vector2d turned_position(const Eigen::Vector2d& position, int quarter_turns, int width, int height) {
  Eigen::Vector2d turned = position;
  for (int turn = 0; turn < quarter_turns; ++turn) {
    turned = Eigen::Vector2d(height - turned.y(), turned.x());
    std::swap(width, height);
  }
  return turned;
}

}  // namespace harmonia::detail
