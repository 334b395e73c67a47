#pragma once
// Internal: the texels of an atlas taken so far, and the search for where the next chart goes.
//
// The atlas holds every placed chart's raster grown by the padding, and a frame `margin` texels
// wide along its edges; a chart fits where its own (not grown) raster meets none of it, so two
// charts end up at least `padding` texels apart and every chart at least `margin` texels from the
// atlas' edge (chart_packing.h: atlas_edge_margin).
//
// A chart goes to the lowest place where it fits, in the best of its four quarter turns (a
// bottom-left fill; charts come largest first, so small ones fill the gaps between big ones):
//  - an exact bitmap search finds the lowest, then leftmost, place: 64 places at a time, skipping
//    straight to the rows where the chart's runs of texels find free runs long enough in the 64
//    columns they would cover (FreeRunIndex, one row high and tall_run_rows high). It starts where
//    the search before it ended (a chart of about the same size does not fit lower; xatlas'
//    brute-force packer resumes the same way), until restart_search();
//  - among the places no higher that rest on the atlas' horizon (per column, the top of what it
//    holds: the "Tetris" packing of Lévy et al. 2002, least squares conformal maps, section 5),
//    the lowest wins, ties going to the one that wastes the least area between the horizon and
//    the chart, so that the charts nestle into one another.
//
// Memory: the taken texels (1 bit each) and two indexes (1/16 byte per texel each): about 0.25
// byte per texel, 4 MiB at 4096 x 4096, 270 MiB at 32768 x 32768.

#include <cstdint>
#include <optional>
#include <vector>

#include "atlas/chart_footprint.h"
#include "atlas/texel_bitmap.h"

namespace harmonia::detail {

struct AtlasPosition {
  int x = 0;              //!< Texel column of the raster's column 0.
  int y = 0;              //!< Texel row of the raster's row 0.
  int quarter_turns = 0;  //!< Which of the footprint's turns.
};

//! For each stripe of 64 columns (one word of a bitmap row) and each row, the longest run of free
//! texels that starts in the stripe; and, per stripe, a segment tree of their maxima over rows, to
//! find the next row where a run of some length starts, in O(log rows).
class FreeRunIndex {
 public:
  FreeRunIndex(int rows, int stripes);
  [[nodiscard]] int longest(int row, int stripe) const { return nodes_[offset(stripe) + leaves_ + row]; }
  void set(int row, int stripe, int length);
  //! Sets a row's value without updating the maxima: for filling a whole index, then rebuild().
  void set_only(int row, int stripe, int length) {
    nodes_[offset(stripe) + leaves_ + row] = static_cast<std::uint16_t>(length);
  }
  //! The maxima from the values, in one pass.
  void rebuild();
  //! The first row >= `from` where a run of at least `length` starts in the stripe; `rows` if none.
  [[nodiscard]] int first_row_with(int stripe, int from, int length) const;

 private:
  [[nodiscard]] std::size_t offset(int stripe) const { return static_cast<std::size_t>(stripe) * 2 * leaves_; }

  int rows_;
  int leaves_;  //!< A power of two >= rows.
  //! Per stripe, 2 * leaves_ nodes: node 1 the root, node n's children 2n and 2n + 1, leaves from
  //! leaves_ on. Runs are at most 32768 + 64 texels long.
  std::vector<std::uint16_t> nodes_;
};

class AtlasOccupancy {
 public:
  //! An empty atlas of width x height texels with its frame of `margin` texels, whose charts
  //! keep `padding` texels apart.
  AtlasOccupancy(int width, int height, int padding, int margin);

  //! Where the chart goes, or nothing where it fits nowhere.
  [[nodiscard]] std::optional<AtlasPosition> find_position(const ChartFootprint& chart);

  //! The bitmap search resumes where the last one ended (a chart of about the same size will not
  //! fit lower); this starts the next from the bottom again, for charts markedly smaller.
  void restart_search() { search_start_row_ = margin_; }

  //! Takes the chart's raster, grown by the padding, at `position`.
  void place(const ChartFootprint& chart, const AtlasPosition& position);

  //! The highest row any chart reaches, plus one (the frame below included).
  [[nodiscard]] int used_height() const { return used_height_; }

 private:
  //! The lowest place resting on the horizon no higher than row `highest`, the one wasting the
  //! least area under it among equals.
  [[nodiscard]] std::optional<AtlasPosition> position_on_horizon(const ChartFootprint& chart, int highest) const;
  //! The lowest, then leftmost, place from row `first_row` up to below row `below_row` where the
  //! chart fits (its row 0 there), by the bitmap.
  [[nodiscard]] std::optional<AtlasPosition> lowest_position(const ChartFootprint& chart, int first_row,
                                                             int below_row) const;
  //! Brings the indexes of free runs up to date after the texels of rows [first_row, last_row]
  //! and columns [first_column, last_column] changed.
  void index_free_runs(int first_row, int last_row, int first_column, int last_column);

  int width_;
  int height_;
  int padding_;
  int margin_;  //!< The frame's width.
  TexelBitmap taken_;
  //! Per column, the row above the highest texel taken (the horizon).
  std::vector<int> horizon_;
  FreeRunIndex free_runs_;       //!< Runs free in one row.
  FreeRunIndex tall_free_runs_;  //!< Runs free in tall_run_rows rows, from the row indexed up.
  std::vector<std::uint16_t> row_runs_;   //!< Scratch: one row's longest runs per stripe.
  std::vector<std::uint64_t> common_row_;  //!< Scratch: texels free in several rows.
  int used_height_ = 0;
  int search_start_row_ = 0;  //!< The row the next bitmap search starts from.
};

}  // namespace harmonia::detail
