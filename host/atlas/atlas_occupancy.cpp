#include "atlas/atlas_occupancy.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <numeric>

namespace harmonia::detail {

namespace {

constexpr int bits_per_word = TexelBitmap::bits_per_word;

//! ORs `source` (source_words words) shifted `shift` texels to the right (left where negative)
//! into `target` (target_words words); bits past either end of the target are dropped.
void or_shifted(const std::uint64_t* source, int source_words, int shift, std::uint64_t* target,
                int target_words) {
  if (shift < 0) {
    // Leftwards (a grown raster reaching past the atlas' left edge): the texels that land before
    // column 0 drop out.
    const int first_word = -shift / bits_per_word, bit = -shift % bits_per_word;
    for (int at = 0; at + first_word < source_words && at < target_words; ++at) {
      std::uint64_t bits = source[at + first_word] >> bit;
      if (bit != 0 && at + first_word + 1 < source_words) bits |= source[at + first_word + 1] << (bits_per_word - bit);
      target[at] |= bits;
    }
    return;
  }
  const int first_word = shift / bits_per_word, bit = shift % bits_per_word;
  for (int word = 0; word < source_words; ++word) {
    const std::uint64_t bits = source[word];
    if (bits == 0) continue;
    const int at = first_word + word;
    if (at < target_words) target[at] |= bits << bit;
    if (bit != 0 && at + 1 < target_words) target[at + 1] |= bits >> (bits_per_word - bit);
  }
}

//! The chart's raster grown by `padding` texels on every side (its size grows by 2 * padding).
TexelBitmap grown_raster(const TexelBitmap& raster, int padding) {
  TexelBitmap grown(raster.width() + 2 * padding, raster.height() + 2 * padding);
  for (int y = 0; y < raster.height(); ++y) {
    or_shifted(raster.row(y), raster.words_per_row(), padding, grown.row(y + padding), grown.words_per_row());
  }
  grown.dilate(padding);
  return grown;
}

//! 64 texels of `row` (of `words` words) from texel `offset` on, set where the texel is clear;
//! texels past the row count as taken.
std::uint64_t clear_texels_at(const std::uint64_t* row, int words, int offset) {
  const int word = offset / bits_per_word, bit = offset % bits_per_word;
  const std::uint64_t low = word < words ? ~row[word] : 0;
  if (bit == 0) return low;
  const std::uint64_t high = word + 1 < words ? ~row[word + 1] : 0;
  return (low >> bit) | (high << (bits_per_word - bit));
}

//! Bit i: texels [offset + i, offset + i + length) of `row` are all clear (length 1..64).
std::uint64_t clear_run_starts(const std::uint64_t* row, int words, int offset, int length) {
  // A 128-texel window holds every texel the 64 starts need; doubling, bit i of `low` comes to
  // say that texels [i, i + covered) of the window are clear.
  std::uint64_t low = clear_texels_at(row, words, offset);
  if (low == 0) return 0;
  std::uint64_t high = length > 1 ? clear_texels_at(row, words, offset + bits_per_word) : 0;
  for (int covered = 1; covered < length;) {
    const int step = std::min(covered, length - covered);  // at most 32
    low &= (low >> step) | (high << (bits_per_word - step));
    high &= high >> step;
    covered += step;
  }
  return low;
}

//! Per word k in [first_word, last_word] of `row`, the longest run of clear texels among the row's
//! first `width` that starts in word k (0 if none does), into longest[k].
void longest_clear_runs_by_word(const std::uint64_t* row, int width, int first_word, int last_word,
                                std::uint16_t* longest) {
  std::fill(longest + first_word, longest + last_word + 1, std::uint16_t{0});
  const int starts_end = std::min(width, (last_word + 1) * bits_per_word);
  for (int x = first_word * bits_per_word; x < starts_end;) {
    // The next clear texel, then the end of its run (which may lie past the words asked for).
    const int word = x / bits_per_word, bit = x % bits_per_word;
    const std::uint64_t clear = ~row[word] >> bit;
    if (clear == 0) {
      x = (word + 1) * bits_per_word;
      continue;
    }
    const int start = x + std::countr_zero(clear);
    if (start >= starts_end) break;
    int end = start;
    while (end < width) {
      const int end_word = end / bits_per_word, end_bit = end % bits_per_word;
      const std::uint64_t taken = row[end_word] >> end_bit;
      if (taken != 0) {
        end = std::min(width, end + std::countr_zero(taken));
        break;
      }
      end = std::min(width, (end_word + 1) * bits_per_word);
    }
    // The longest run starting in word k starts at the run's start or at the word's first texel.
    for (int k = start / bits_per_word; k <= last_word && k * bits_per_word < end; ++k) {
      const int from = std::max(start, k * bits_per_word);
      longest[k] = std::max<std::uint16_t>(longest[k], static_cast<std::uint16_t>(end - from));
    }
    x = end;
  }
}

//! The first texel of the run of clear texels of `row` that contains `column`; column + 1 if
//! that texel is taken.
int clear_run_start(const std::uint64_t* row, int column) {
  int word = column / bits_per_word;
  const int bit = column % bits_per_word;
  const std::uint64_t up_to_column =
      bit == bits_per_word - 1 ? ~std::uint64_t{0} : (std::uint64_t{1} << (bit + 1)) - 1;
  std::uint64_t taken = row[word] & up_to_column;
  while (taken == 0) {
    if (word == 0) return 0;
    taken = row[--word];
  }
  return word * bits_per_word + (bits_per_word - 1 - std::countl_zero(taken)) + 1;
}

//! Charts wider than this many texels have their heights on the horizon bounded by a sliding
//! maximum (which costs one pass over the atlas' width per quarter turn; narrower charts have few
//! columns to measure anyway).
constexpr int kWideChart = 16;

//! maximum[x - first] = the largest of values[x .. x + width - 1], for x in [first, last] (a
//! queue of the candidates for the maximum, each value entering and leaving it once).
void sliding_maximum(const std::vector<int>& values, int first, int last, int width, std::vector<int>& maximum) {
  maximum.resize(static_cast<std::size_t>(std::max(0, last - first + 1)));
  std::vector<int> candidates;  // indices of decreasing values; a deque as a vector and a head
  std::size_t head = 0;
  for (int x = first; x < last + width; ++x) {
    while (candidates.size() > head && values[static_cast<std::size_t>(candidates.back())] <= values[static_cast<std::size_t>(x)])
      candidates.pop_back();
    candidates.push_back(x);
    const int start = x - width + 1;
    if (start < first) continue;
    while (candidates[head] < start) ++head;
    maximum[static_cast<std::size_t>(start - first)] = values[static_cast<std::size_t>(candidates[head])];
  }
}

}  // namespace

FreeRunIndex::FreeRunIndex(int rows, int stripes)
    : rows_(rows),
      leaves_(static_cast<int>(std::bit_ceil(static_cast<unsigned>(std::max(1, rows))))),
      nodes_(static_cast<std::size_t>(stripes) * 2 * leaves_, 0) {}

void FreeRunIndex::set(int row, int stripe, int length) {
  std::uint16_t* nodes = nodes_.data() + offset(stripe);
  int node = row + leaves_;
  nodes[node] = static_cast<std::uint16_t>(length);
  for (node /= 2; node >= 1; node /= 2) nodes[node] = std::max(nodes[2 * node], nodes[2 * node + 1]);
}

void FreeRunIndex::rebuild() {
  const int stripes = static_cast<int>(nodes_.size() / (2 * static_cast<std::size_t>(leaves_)));
  for (int stripe = 0; stripe < stripes; ++stripe) {
    std::uint16_t* nodes = nodes_.data() + offset(stripe);
    for (int node = leaves_ - 1; node >= 1; --node) nodes[node] = std::max(nodes[2 * node], nodes[2 * node + 1]);
  }
}

int FreeRunIndex::first_row_with(int stripe, int from, int length) const {
  if (from >= rows_) return rows_;
  const std::uint16_t* nodes = nodes_.data() + offset(stripe);
  int node = std::max(from, 0) + leaves_;
  // Up and to the right until a subtree holds a run long enough, then down to its first row.
  while (nodes[node] < length) {
    while (node & 1) node /= 2;  // a right child: its parent's range has nothing further right
    if (node == 0) return rows_;
    ++node;
  }
  while (node < leaves_) node = nodes[2 * node] >= length ? 2 * node : 2 * node + 1;
  return std::min(node - leaves_, rows_);
}

AtlasOccupancy::AtlasOccupancy(int width, int height, int padding, int margin)
    : width_(width),
      height_(height),
      padding_(padding),
      margin_(margin),
      // One spare word per row, so that a shifted test may read one word past a raster's end.
      taken_(width + bits_per_word, height),
      horizon_(static_cast<std::size_t>(width), margin),
      free_runs_(height, taken_.words_per_row()),
      tall_free_runs_(height, taken_.words_per_row()),
      row_runs_(static_cast<std::size_t>(taken_.words_per_row()), 0),
      common_row_(static_cast<std::size_t>(taken_.words_per_row()), 0) {
  // The frame: `margin` texels along each edge.
  for (int y = 0; y < height; ++y) {
    if (y < margin || y >= height - margin) {
      taken_.set_span(0, width, y);
    } else if (margin > 0) {
      taken_.set_span(0, margin, y);
      taken_.set_span(width - margin, width, y);
    }
  }
  // Every row of the inside is alike: one clear run between the side frames.
  for (int y = 0; y < height; ++y) {
    longest_clear_runs_by_word(taken_.row(y), width, 0, taken_.words_per_row() - 1, row_runs_.data());
    for (int stripe = 0; stripe < taken_.words_per_row(); ++stripe) {
      free_runs_.set_only(y, stripe, row_runs_[stripe]);
      // Tall runs: the same in every row with tall_run_rows rows of the inside from it up.
      const bool tall_inside = y >= margin && y + tall_run_rows <= height - margin;
      tall_free_runs_.set_only(y, stripe, tall_inside ? row_runs_[stripe] : 0);
    }
  }
  free_runs_.rebuild();
  tall_free_runs_.rebuild();
}

void AtlasOccupancy::index_free_runs(int first_row, int last_row, int first_column, int last_column) {
  const int words = taken_.words_per_row();
  // The runs that changed start in the words from the one where the clear run reaching the first
  // changed column begins to the one of the last changed column; a tree is updated only where
  // a run did change.
  auto index_row = [&](FreeRunIndex& index, int y, const std::uint64_t* taken) {
    const int from = first_column > 0 ? clear_run_start(taken, first_column - 1) : 0;
    const int first_word = std::min(from, first_column) / bits_per_word;
    const int last_word = last_column / bits_per_word;
    longest_clear_runs_by_word(taken, width_, first_word, last_word, row_runs_.data());
    for (int stripe = first_word; stripe <= last_word; ++stripe) {
      if (index.longest(y, stripe) != row_runs_[stripe]) index.set(y, stripe, row_runs_[stripe]);
    }
  };
  for (int y = first_row; y <= last_row; ++y) index_row(free_runs_, y, taken_.row(y));
  // A tall run from row y up covers rows y .. y + tall_run_rows - 1 (rows past the top count as
  // taken), so the rows just below the change see it too.
  for (int y = std::max(0, first_row - tall_run_rows + 1); y <= last_row; ++y) {
    if (y + tall_run_rows > height_) {
      std::fill(common_row_.begin(), common_row_.end(), ~std::uint64_t{0});
    } else {
      for (int word = 0; word < words; ++word) {
        std::uint64_t taken = 0;
        for (int above = 0; above < tall_run_rows; ++above) taken |= taken_.row(y + above)[word];
        common_row_[word] = taken;
      }
    }
    index_row(tall_free_runs_, y, common_row_.data());
  }
}

std::optional<AtlasPosition> AtlasOccupancy::find_position(const ChartFootprint& chart) {
  // The lowest place from the search's start up, in the holes or anywhere above, unless a place
  // on the horizon is as low: then the lowest place on the horizon, the one wasting the least
  // area among equals. A place on the horizon fits, so the bitmap search needs to look only
  // below the lowest one: nothing lower there leaves it the winner, and the lowest place at all
  // then lies on its row.
  const int inner_top = height_ - margin_;  // the first row of the top frame
  const std::optional<AtlasPosition> on_horizon =
      position_on_horizon(chart, std::numeric_limits<int>::max());
  if (on_horizon && search_start_row_ < on_horizon->y) {
    const std::optional<AtlasPosition> lower = lowest_position(chart, search_start_row_, on_horizon->y);
    // Every row from the start up to the lowest place was searched: a chart of about the same
    // size will not fit there either.
    search_start_row_ = lower ? lower->y : on_horizon->y;
    return lower ? lower : on_horizon;
  }
  // From a start at or above the horizon's lowest place, that place wins; the search only moves
  // the start on.
  const std::optional<AtlasPosition> lowest = lowest_position(chart, search_start_row_, inner_top);
  if (lowest) search_start_row_ = lowest->y;
  return on_horizon ? on_horizon : lowest;
}

std::optional<AtlasPosition> AtlasOccupancy::position_on_horizon(const ChartFootprint& chart, int highest) const {
  const int inner_right = width_ - margin_, inner_top = height_ - margin_;  // where the far frames start
  highest = std::min(highest, inner_top);
  // Resting no higher than `highest`, a chart has its texels of row r over columns whose horizon
  // is at most highest + r: row r of `too_high` marks the other columns, and each run of the
  // chart's rows below masked_rows rules out, 64 places at a time, the places that put it over
  // one of them. Only the places left are measured column by column.
  constexpr int masked_rows = 2;
  TexelBitmap too_high(width_ + bits_per_word, masked_rows);
  for (int row = 0; row < masked_rows; ++row) {
    std::uint64_t* words = too_high.row(row);
    for (int word = 0; word * bits_per_word < width_; ++word) {
      const int* heights = horizon_.data() + word * bits_per_word;
      const int count = std::min(bits_per_word, width_ - word * bits_per_word);
      std::uint64_t bits = 0;
      for (int bit = 0; bit < count; ++bit) bits |= std::uint64_t{heights[bit] > highest + row} << bit;
      words[word] = bits;
    }
  }
  // The horizon's prefix sums: the area between the horizon and a chart resting on it, summed
  // over the chart's columns, is then its width times its height minus two sums.
  std::vector<long long> horizon_before(static_cast<std::size_t>(width_) + 1, 0);
  for (int x = 0; x < width_; ++x) horizon_before[static_cast<std::size_t>(x) + 1] = horizon_before[static_cast<std::size_t>(x)] + horizon_[static_cast<std::size_t>(x)];
  std::vector<TexelRun> low_runs;  // the runs of the chart's rows below masked_rows
  std::vector<int> highest_under;
  std::optional<AtlasPosition> best;
  long long best_waste = std::numeric_limits<long long>::max();
  int best_y = highest;
  std::vector<int> columns;
  for (int turns = 0; turns < 4; ++turns) {
    const TexelBitmap& raster = chart.turned[turns];
    const std::vector<int>& lowest = chart.lowest_texel[turns];
    const int width = raster.width(), height = raster.height();
    if (margin_ + width > inner_right || margin_ + height > inner_top) continue;
    // The chart's lowest columns first: they decide its height on a flat horizon, so a place
    // higher than the best so far is given up after a column or two.
    columns.resize(static_cast<std::size_t>(width));
    std::iota(columns.begin(), columns.end(), 0);
    std::stable_sort(columns.begin(), columns.end(), [&](int a, int b) { return lowest[a] < lowest[b]; });
    const long long lowest_sum = std::accumulate(lowest.begin(), lowest.begin() + width, 0LL);
    low_runs.clear();
    for (const TexelRun& run : chart.runs[turns]) {
      if (run.row < masked_rows) low_runs.push_back(run);
    }
    const int first_x = margin_, last_x = inner_right - width;
    // For a wide chart, the highest horizon under each place (a sliding maximum): once the
    // columns left to measure rest their lowest texel no lower than that maximum minus the
    // height found so far, none of them can raise it (on a flat horizon, after one column).
    const bool wide = width > kWideChart;
    if (wide) sliding_maximum(horizon_, first_x, last_x, width, highest_under);
    for (int word = first_x / bits_per_word; word <= last_x / bits_per_word; ++word) {
      std::uint64_t places = ~std::uint64_t{0};
      if (word == first_x / bits_per_word) places &= ~std::uint64_t{0} << (first_x % bits_per_word);
      if (word == last_x / bits_per_word && last_x % bits_per_word != bits_per_word - 1) {
        places &= (std::uint64_t{1} << (last_x % bits_per_word + 1)) - 1;
      }
      for (const TexelRun& run : low_runs) {
        places &= clear_run_starts(too_high.row(run.row), too_high.words_per_row(), word * bits_per_word + run.first,
                                   run.length);
        if (places == 0) break;
      }
      for (; places != 0; places &= places - 1) {
        const int x = word * bits_per_word + std::countr_zero(places);
        int y = 0;
        const int highest = wide ? highest_under[static_cast<std::size_t>(x - first_x)] : 0;
        for (int i = 0; i < width; ++i) {
          const int column = columns[static_cast<std::size_t>(i)];
          y = std::max(y, horizon_[x + column] - lowest[column]);
          if (y > best_y) break;
          if (wide && i + 1 < width && highest - lowest[columns[static_cast<std::size_t>(i) + 1]] <= y) break;
        }
        if (y > best_y || y + height > inner_top) continue;
        // The area between the horizon and the chart's lowest texels.
        const long long waste = static_cast<long long>(width) * y + lowest_sum -
                                (horizon_before[static_cast<std::size_t>(x + width)] - horizon_before[static_cast<std::size_t>(x)]);
        if (!best || y < best_y || waste < best_waste) {
          best_waste = waste;
          best_y = y;
          best = AtlasPosition{x, y, turns};
        }
      }
    }
  }
  return best;
}

std::optional<AtlasPosition> AtlasOccupancy::lowest_position(const ChartFootprint& chart, int first_row,
                                                             int below_row) const {
  const int inner_right = width_ - margin_, inner_top = height_ - margin_;
  const int words = taken_.words_per_row();
  // What a place needs, as free runs in the indexes: the chart's tall runs (the most selective,
  // the longest leads the search) and each run of its rows.
  struct Need {
    const FreeRunIndex* index;
    TexelRun run;
  };
  std::vector<Need> needs;
  std::vector<const TexelRun*> blocking, narrowing;  // see below
  std::optional<AtlasPosition> best;
  for (int turns = 0; turns < 4; ++turns) {
    const TexelBitmap& raster = chart.turned[turns];
    const int width = raster.width(), height = raster.height();
    if (margin_ + width > inner_right || margin_ + height > inner_top) continue;
    needs.clear();
    for (const TexelRun& run : chart.tall_runs[turns]) needs.push_back(Need{&tall_free_runs_, run});
    for (const TexelRun& run : chart.runs[turns]) needs.push_back(Need{&free_runs_, run});
    const int first_x = margin_, last_x = inner_right - width;
    // The 64 places whose column 0 lies in word `word`, one word at a time, left to right; each
    // search stops at the lowest place found so far.
    for (int word = first_x / bits_per_word; word <= last_x / bits_per_word; ++word) {
      std::uint64_t places = ~std::uint64_t{0};
      if (word == first_x / bits_per_word) places &= ~std::uint64_t{0} << (first_x % bits_per_word);
      if (word == last_x / bits_per_word && last_x % bits_per_word != bits_per_word - 1) {
        places &= (std::uint64_t{1} << (last_x % bits_per_word + 1)) - 1;
      }
      // The starts of a run's 64 places lie in one stripe of an index, or in two where the run
      // does not begin at a word boundary.
      auto free_in = [&](const Need& need, int y) {
        const int stripe = (word * bits_per_word + need.run.first) / bits_per_word;
        const int row = y + need.run.row;
        return need.index->longest(row, stripe) >= need.run.length ||
               (need.run.first % bits_per_word != 0 && need.index->longest(row, stripe + 1) >= need.run.length);
      };
      // The next row from `from` on where `need` may be met (a failing need sends the search
      // straight there: a leapfrog join of the needs).
      auto next_row_for = [&](const Need& need, int from) {
        const int stripe = (word * bits_per_word + need.run.first) / bits_per_word;
        int row = need.index->first_row_with(stripe, from + need.run.row, need.run.length);
        if (need.run.first % bits_per_word != 0) {
          row = std::min(row, need.index->first_row_with(stripe + 1, from + need.run.row, need.run.length));
        }
        return row - need.run.row;
      };
      const int ceiling = best ? best->y : below_row;
      // The runs that, in the last exact test, each ruled out some of the places that the runs
      // before them left, until none was left: the rows where they alone still rule out all 64
      // places go by at a few words each. Where the indexes pass every need, a place is most often
      // missed only by the texels, and the next row by the same few runs.
      blocking.clear();
      const auto blocked = [&](int y) {
        std::uint64_t left = places;
        for (const TexelRun* run : blocking) {
          left &= clear_run_starts(taken_.row(y + run->row), words, word * bits_per_word + run->first, run->length);
          if (left == 0) return true;
        }
        return false;
      };
      for (int y = next_row_for(needs.front(), first_row); y < ceiling && y + height <= inner_top;) {
        if (!blocking.empty() && blocked(y)) {
          ++y;
          continue;
        }
        // Every need against its index first (cheap), then every run against the texels (exact).
        const Need* failing = nullptr;
        for (const Need& need : needs) {
          if (!free_in(need, y)) {
            failing = &need;
            break;
          }
        }
        if (failing) {
          y = std::max(y + 1, next_row_for(*failing, y));
          continue;
        }
        std::uint64_t fitting = places;
        narrowing.clear();
        for (const TexelRun& run : chart.runs[turns]) {
          const std::uint64_t left =
              fitting & clear_run_starts(taken_.row(y + run.row), words, word * bits_per_word + run.first, run.length);
          if (left == fitting) continue;
          narrowing.push_back(&run);
          fitting = left;
          if (fitting == 0) break;
        }
        if (fitting == 0) blocking.swap(narrowing);
        if (fitting != 0) {
          best = AtlasPosition{word * bits_per_word + std::countr_zero(fitting), y, turns};
          break;
        }
        y = next_row_for(needs.front(), y + 1);
      }
    }
  }
  return best;
}

void AtlasOccupancy::place(const ChartFootprint& chart, const AtlasPosition& position) {
  const TexelBitmap& raster = chart.turned[position.quarter_turns];
  const TexelBitmap grown = grown_raster(raster, padding_);
  const int left = position.x - padding_, bottom = position.y - padding_;
  for (int row = 0; row < grown.height(); ++row) {
    const int y = bottom + row;
    if (y < 0 || y >= height_) continue;
    std::uint64_t* taken = taken_.row(y);
    or_shifted(grown.row(row), grown.words_per_row(), left, taken, taken_.words_per_row());
    // The padding may reach past the right edge (the frame is narrower than it): those texels
    // are not the atlas'.
    if (left + grown.width() > width_) {
      const int word = width_ / bits_per_word, bit = width_ % bits_per_word;
      taken[word] &= bit == 0 ? 0 : (std::uint64_t{1} << bit) - 1;
      for (int beyond = word + 1; beyond < taken_.words_per_row(); ++beyond) taken[beyond] = 0;
    }
  }
  index_free_runs(std::max(0, bottom), std::min(height_ - 1, bottom + grown.height() - 1), std::max(0, left),
                  std::min(width_ - 1, left + grown.width() - 1));
  // The horizon rises to the top of the grown raster in each of its columns.
  std::vector<bool> settled(static_cast<std::size_t>(grown.width()), false);
  int unsettled = grown.width();
  for (int row = grown.height() - 1; row >= 0 && unsettled > 0; --row) {
    const std::uint64_t* words = grown.row(row);
    for (int word = 0; word < grown.words_per_row(); ++word) {
      for (std::uint64_t bits = words[word]; bits != 0; bits &= bits - 1) {
        const int column = word * bits_per_word + std::countr_zero(bits);
        if (settled[column]) continue;
        settled[column] = true;
        --unsettled;
        const int x = left + column;
        if (x >= 0 && x < width_) horizon_[x] = std::max(horizon_[x], std::min(height_, bottom + row + 1));
      }
    }
  }
  used_height_ = std::max(used_height_, position.y + raster.height());
}

}  // namespace harmonia::detail
