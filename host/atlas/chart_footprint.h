#pragma once
// Internal: a chart as the packer sees it at one scale: the texels its triangles touch, in each of
// the four quarter turns. Turning the raster is exact (the texel grid is unchanged by a quarter
// turn), so one rasterization serves all four.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "atlas/texel_bitmap.h"

namespace harmonia::detail {

//! Where the chart's lowest corner sits inside its first texel, in texels: just past the texel's
//! corner, by far more than raster_tolerance, so that a chart whose width is a whole number of
//! texels does not touch one texel more on each side.
inline constexpr double chart_lead_in = 1.0 / 1024.0;

//! A run of set texels in one row of a raster, at most 64 long (a longer run is cut into pieces),
//! so that the packer tests where it fits 64 places at a time.
struct TexelRun {
  int row = 0;
  int first = 0;   //!< Its first column.
  int length = 0;  //!< 1..64.
};

//! How many rows a tall run spans: a chart fits only where each run of `tall_run_rows` rows of
//! texels, set in all of them, finds texels free in all of them; the packer's index of such runs
//! passes over the many gaps between placed charts that are too low for it.
inline constexpr int tall_run_rows = 4;

struct ChartFootprint {
  //! turned[k]: the conservative raster turned by k quarter turns counter-clockwise. turned[0]
  //! holds corner p of the chart at texel position scale * p + (chart_lead_in, chart_lead_in).
  std::array<TexelBitmap, 4> turned;
  //! lowest_texel[k][x]: the lowest set row of column x of turned[k] (its height if none is set).
  std::array<std::vector<int>, 4> lowest_texel;
  //! runs[k]: the runs of turned[k], longest first (ties bottom to top, left to right).
  std::array<std::vector<TexelRun>, 4> runs;
  //! tall_runs[k]: for each band of tall_run_rows consecutive rows of turned[k] (from the bottom
  //! up, and the top band), the longest run of columns set in all of its rows (`row` the lowest),
  //! at most 64 long; longest first. None for a raster lower than a band.
  std::array<std::vector<TexelRun>, 4> tall_runs;
};

//! The footprint of a chart at `scale` texels per unit. `corners`: 3 rows per triangle, turned to
//! the chart's tightest box and moved so that the box's lowest corner is the origin.
[[nodiscard]] ChartFootprint chart_footprint(const Eigen::MatrixX2d& corners, double scale);

//! Where texel position `position` of turned[0] goes in turned[quarter_turns] (exact: a quarter
//! turn of a width x height raster sends (u, v) to (height - v, u)).
[[nodiscard]] Eigen::Vector2d turned_position(const Eigen::Vector2d& position, int quarter_turns, int width,
                                              int height);

}  // namespace harmonia::detail
