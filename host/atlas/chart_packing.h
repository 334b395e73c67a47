#pragma once
// Internal: packing flattened charts into one square texture atlas at one texel density.
//
// Every chart keeps its shape: it is only turned (by any angle), scaled by the one density common
// to all charts, and moved. Each chart is first turned to its tightest bounding box (the box of
// least area, min_area_rectangle.h). Then, at a trial density, every chart is rasterized
// conservatively (chart_raster.h, chart_footprint.h) and the charts, largest first, are placed one
// by one in one of four quarter turns, bottom-left first: resting on the atlas' horizon, or lower,
// in a hole between charts placed before (atlas_occupancy.h). The density is the largest tried at
// which every chart fits, searched two densities at a time (side by side on two threads; the same
// trials on one): a pair around a first guess from the charts' total area, pairs further up or
// down from how full the trials came out while all fit or none does (steps doubling), then the
// points that cut the bracket in thirds, to within density_tolerance. Last, the charts widest box
// first (xatlas' order: a ring or an arc before the charts that fill its inside) are tried a pair
// at a time above the density found, and kept where they fit denser.

#include <vector>

#include <Eigen/Core>

namespace harmonia::detail {

struct PackingOptions {
  //! The atlas is resolution (wide) x height texels, each 16..32768; height 0: a square.
  int resolution = 1024;
  int height = 0;
  //! Empty texels between two charts (0..64), across the atlas' edges too: a chart keeps
  //! atlas_edge_margin(padding) texels from each edge (see there).
  int padding = 2;
  //! Threads for the trials: two densities tried side by side, each trial's charts rasterized on
  //! the threads left (the placement of one trial runs on one thread); the packing is the same
  //! for any count. Memory: one atlas occupancy (atlas_occupancy.h) per trial running.
  int threads = 1;
  //! 0: the densest packing that fits (searched). Greater: exactly this density, in texels per
  //! unit of the charts' lengths, or a refusal when the charts do not fit at it.
  double fixed_scale = 0.0;
  //! At a fixed_scale, the charts that find no room on the pages opened so far open another
  //! (an atlas of several squares, each resolution x resolution), up to this many; 0: as many
  //! as they need. A searched density packs one page.
  int max_pages = 1;
  //! Charts keep their orientation up to quarter turns (a layout whose texture content must stay
  //! upright or axis-aligned) instead of being turned to their tightest box first.
  bool quarter_turns_only = false;
};

//! The empty texels between a chart and each edge of the atlas: half the padding, rounded up. A
//! texture sampled with wrapping (glTF's default sampler) continues across the edge into the
//! opposite one, so two charts facing each other across it are then the two margins apart, at
//! least `padding` like any two charts. A full padding on each side would keep twice that: 0.4 %
//! of a 1024-texel atlas with padding 2, for nothing.
[[nodiscard]] constexpr int atlas_edge_margin(int padding) { return (padding + 1) / 2; }

struct ChartPlacement {
  double angle = 0.0;                                //!< Radians, counter-clockwise, applied first.
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();  //!< Texels, added after turning and scaling.
  int page = 0;                                      //!< Which square of the atlas it is on.
};

struct ChartPacking {
  double texels_per_unit = 0.0;            //!< The one scale of every chart.
  std::vector<ChartPlacement> placements;  //!< One per chart, in input order.
  //! Texel centres strictly inside some chart's triangle / (pages resolution^2): the atlas'
  //! coverage; and the same per page.
  double coverage = 0.0;
  int pages = 1;
  std::vector<double> page_coverage;
  //! How many densities were tried (each one a rasterization and a packing of every chart).
  int trials = 0;
};

//! The densest packing found: every chart in the atlas at a density within density_tolerance of
//! a denser one at which the packer failed to fit them all (or at the largest density that lets
//! the largest chart fit).
//!
//! charts[c]: 3 rows per triangle (its corners, counter-clockwise), in units of 3D length. A corner
//! p of chart c lands at texel position texels_per_unit * R(angle_c) * p + offset_c, x right and
//! y up, inside [margin, resolution - margin]^2 with margin = atlas_edge_margin(padding). The
//! conservative rasterization of a chart (every texel its closed triangles touch) grown by
//! `padding` texels (a square neighbourhood) shares no texel with another chart's conservative
//! rasterization: there are at least `padding` empty texels between two charts, in every
//! direction, also across the atlas' edges where the texture wraps.
//!
//! At a fixed_scale with max_pages other than 1, the charts go largest first to the first page
//! where they fit, or open the next (its charts placed as on the first).
//!
//! Deterministic, and independent of the charts' order except among charts of equal size and box,
//! which go in input order. Throws Error(Status::invalid_input) for a resolution or padding out of
//! range, no chart, a chart with no triangle or a row count not a multiple of 3, a corner that is
//! not finite (naming the chart and row), or charts too many to fit at any density.
[[nodiscard]] ChartPacking pack_charts(const std::vector<Eigen::MatrixX2d>& charts, const PackingOptions& options);

//! Whether `chart` (as pack_charts takes it), turned to its tightest box, fits inside one page
//! at options.fixed_scale (then pack_charts does not refuse it for its size).
[[nodiscard]] bool fits_one_page(const Eigen::MatrixX2d& chart, const PackingOptions& options);

//! The search for the density stops once a density at which every chart fits and a denser one at
//! which they do not are this close, relatively (the coverage is then within about twice that).
inline constexpr double density_tolerance = 0.01;

}  // namespace harmonia::detail
