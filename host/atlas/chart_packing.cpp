#include "atlas/chart_packing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <string>

#include "atlas/atlas_occupancy.h"
#include "atlas/chart_footprint.h"
#include "atlas/chart_raster.h"
#include "atlas/min_area_rectangle.h"
#include "harmonia/types.h"

namespace harmonia::detail {

namespace {

constexpr int smallest_resolution = 16;
constexpr int largest_resolution = 32768;
constexpr int largest_padding = 64;

//! A chart turned to its tightest box, the box's lowest corner moved to the origin.
struct PreparedChart {
  Eigen::MatrixX2d corners;
  double angle = 0.0;                               //!< The turn that lays the box along the axes.
  Eigen::Vector2d box_low = Eigen::Vector2d::Zero();  //!< The turned box's lowest corner, moved to 0.
  Eigen::Vector2d extent = Eigen::Vector2d::Zero();   //!< The box's sides.
  double area = 0.0;                                //!< The triangles' total area.
};

//! The charts placed at one density (positions in input order of the charts).
struct Trial {
  double scale = 0.0;
  bool fits = false;
  std::vector<AtlasPosition> positions;
  std::vector<Eigen::Vector2i> raster_sizes;  //!< Width and height of each chart's unturned raster.
  int used_height = 0;                        //!< Of a trial that fits.
  double placed_area_fraction = 0.0;          //!< Of a trial that does not: the charts' area placed.
};

Eigen::Matrix2d rotation(double angle) {
  const double cosine = std::cos(angle), sine = std::sin(angle);
  Eigen::Matrix2d turn;
  turn << cosine, -sine, sine, cosine;
  return turn;
}

void validate(const std::vector<Eigen::MatrixX2d>& charts, const PackingOptions& options) {
  if (options.resolution < smallest_resolution || options.resolution > largest_resolution) {
    throw Error(Status::invalid_input, "the atlas resolution must be in [" + std::to_string(smallest_resolution) +
                                           ", " + std::to_string(largest_resolution) + "], not " +
                                           std::to_string(options.resolution));
  }
  if (options.padding < 0 || options.padding > largest_padding) {
    throw Error(Status::invalid_input, "the atlas padding must be in [0, " + std::to_string(largest_padding) +
                                           "], not " + std::to_string(options.padding));
  }
  if (options.resolution - 2 * options.padding < 1) {
    throw Error(Status::invalid_input, "a padding of " + std::to_string(options.padding) + " leaves no texel inside a " +
                                           std::to_string(options.resolution) + " x " +
                                           std::to_string(options.resolution) + " atlas");
  }
  if (charts.empty()) throw Error(Status::invalid_input, "there is no chart to pack");
  for (std::size_t chart = 0; chart < charts.size(); ++chart) {
    const Eigen::MatrixX2d& corners = charts[chart];
    if (corners.rows() == 0 || corners.rows() % 3 != 0) {
      throw Error(Status::invalid_input, "chart " + std::to_string(chart) + " has " + std::to_string(corners.rows()) +
                                             " corner rows, not a positive multiple of 3 (3 per triangle)");
    }
    for (Eigen::Index row = 0; row < corners.rows(); ++row) {
      if (!corners.row(row).allFinite()) {
        throw Error(Status::invalid_input, "chart " + std::to_string(chart) + ", row " + std::to_string(row) +
                                               ": the corner is not finite");
      }
    }
  }
}

PreparedChart prepare(const Eigen::MatrixX2d& chart) {
  std::vector<Eigen::Vector2d> points(static_cast<std::size_t>(chart.rows()));
  for (Eigen::Index row = 0; row < chart.rows(); ++row) points[row] = chart.row(row).transpose();
  PreparedChart prepared;
  prepared.angle = min_area_rectangle(convex_hull(std::move(points))).angle;
  const Eigen::MatrixX2d turned = chart * rotation(prepared.angle).transpose();
  prepared.box_low = turned.colwise().minCoeff().transpose();
  prepared.corners = turned.rowwise() - prepared.box_low.transpose();
  prepared.extent = prepared.corners.colwise().maxCoeff().transpose();
  for (Eigen::Index row = 0; row < chart.rows(); row += 3) {
    const Eigen::Vector2d first = chart.row(row + 1) - chart.row(row);
    const Eigen::Vector2d second = chart.row(row + 2) - chart.row(row);
    prepared.area += 0.5 * std::abs(first.x() * second.y() - first.y() * second.x());
  }
  return prepared;
}

//! Largest first: by area, then by the longer and the shorter side of the box; ties in input order.
std::vector<int> packing_order(const std::vector<PreparedChart>& charts) {
  std::vector<int> order(charts.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int first, int second) {
    const PreparedChart& a = charts[first];
    const PreparedChart& b = charts[second];
    if (a.area != b.area) return a.area > b.area;
    const double a_long = a.extent.maxCoeff(), b_long = b.extent.maxCoeff();
    if (a_long != b_long) return a_long > b_long;
    return a.extent.minCoeff() > b.extent.minCoeff();
  });
  return order;
}

Trial pack_at(const std::vector<PreparedChart>& charts, const std::vector<int>& order, double scale,
              const PackingOptions& options, double total_area) {
  Trial trial;
  trial.scale = scale;
  trial.positions.resize(charts.size());
  trial.raster_sizes.resize(charts.size());
  AtlasOccupancy atlas(options.resolution, options.padding);
  double placed_area = 0.0;
  // The search for holes resumes where the one before ended while the charts keep about the same
  // size, and starts from the bottom again once they are this much smaller (in area): 10 %
  // keeps nearly all the coverage of a search from the bottom for every chart (1 to 2 % less)
  // at a small part of its time (a tenth at 10,000 charts).
  constexpr double smaller_by = 1.1;
  double area_at_restart = std::numeric_limits<double>::infinity();
  for (const int chart : order) {
    if (charts[chart].area * smaller_by < area_at_restart) {
      area_at_restart = charts[chart].area;
      atlas.restart_hole_search();
    }
    const ChartFootprint footprint = chart_footprint(charts[chart].corners, scale);
    const std::optional<AtlasPosition> position = atlas.find_position(footprint);
    if (!position) {
      trial.placed_area_fraction = total_area > 0.0 ? placed_area / total_area : 0.0;
      return trial;
    }
    atlas.place(footprint, *position);
    trial.positions[chart] = *position;
    trial.raster_sizes[chart] = Eigen::Vector2i(footprint.turned[0].width(), footprint.turned[0].height());
    placed_area += charts[chart].area;
  }
  trial.fits = true;
  trial.used_height = atlas.used_height();
  return trial;
}

//! A first density: the charts' footprints (each taken as a square of its area, one texel larger
//! for the conservative raster and `padding` larger for the gap) filling a share of the atlas
//! that packings of such footprints usually reach.
double first_guess(const std::vector<PreparedChart>& charts, const PackingOptions& options) {
  constexpr double usual_share = 0.8;
  const double border = 1.0 + options.padding;
  double area = 0.0, sides = 0.0;
  for (const PreparedChart& chart : charts) {
    area += chart.area;
    sides += std::sqrt(chart.area);
  }
  const double atlas_area = usual_share * static_cast<double>(options.resolution) * options.resolution;
  // area s^2 + 2 border sides s + charts border^2 = atlas_area, for s > 0.
  const double linear = 2.0 * border * sides;
  const double constant = static_cast<double>(charts.size()) * border * border - atlas_area;
  if (!(area > 0.0)) return linear > 0.0 ? -constant / linear : std::numeric_limits<double>::infinity();
  return (-linear + std::sqrt(linear * linear - 4.0 * area * constant)) / (2.0 * area);
}

ChartPacking result_of(const std::vector<Eigen::MatrixX2d>& input, const std::vector<PreparedChart>& charts,
                       const Trial& trial, const PackingOptions& options) {
  ChartPacking packing;
  packing.texels_per_unit = trial.scale;
  packing.placements.resize(charts.size());
  long long covered = 0;
  const Eigen::Vector2d lead_in(chart_lead_in, chart_lead_in);
  for (std::size_t chart = 0; chart < charts.size(); ++chart) {
    const AtlasPosition& position = trial.positions[chart];
    const Eigen::Vector2i& size = trial.raster_sizes[chart];
    // Corner p sits at turned_position(scale (R p - box_low) + lead-in) + position in the atlas;
    // turned_position is a quarter turn plus a shift, so the shift goes into the offset.
    ChartPlacement& placement = packing.placements[chart];
    constexpr double quarter_turn = std::numbers::pi / 2;
    placement.angle = std::remainder(charts[chart].angle + position.quarter_turns * quarter_turn, 2 * std::numbers::pi);
    placement.offset = turned_position(lead_in - trial.scale * charts[chart].box_low, position.quarter_turns,
                                       size.x(), size.y()) +
                       Eigen::Vector2d(position.x, position.y);
    // Coverage: the chart's texel centres inside its triangles, in its own box of the atlas.
    const bool on_side = position.quarter_turns % 2 != 0;
    TexelBitmap centres(on_side ? size.y() : size.x(), on_side ? size.x() : size.y());
    const Eigen::Matrix2d turn = trial.scale * rotation(placement.angle);
    const Eigen::Vector2d shift = placement.offset - Eigen::Vector2d(position.x, position.y);
    const Eigen::MatrixX2d& corners = input[chart];
    for (Eigen::Index row = 0; row < corners.rows(); row += 3) {
      rasterize_triangle_centres(turn * corners.row(row).transpose() + shift,
                                 turn * corners.row(row + 1).transpose() + shift,
                                 turn * corners.row(row + 2).transpose() + shift, centres);
    }
    covered += centres.count();
  }
  packing.coverage = static_cast<double>(covered) / (static_cast<double>(options.resolution) * options.resolution);
  return packing;
}

}  // namespace

ChartPacking pack_charts(const std::vector<Eigen::MatrixX2d>& charts, const PackingOptions& options) {
  validate(charts, options);
  // Even charts of a single texel, `padding` apart, fill the atlas' inside at most this many.
  const long long inside = options.resolution - 2 * options.padding;
  const long long per_side = (inside + options.padding) / (1 + options.padding);
  if (static_cast<long long>(charts.size()) > per_side * per_side) {
    throw Error(Status::invalid_input, std::to_string(charts.size()) + " charts cannot fit in a " +
                                           std::to_string(options.resolution) + " x " +
                                           std::to_string(options.resolution) + " atlas with padding " +
                                           std::to_string(options.padding) + " at any density");
  }
  std::vector<PreparedChart> prepared;
  prepared.reserve(charts.size());
  double total_area = 0.0, longest_side = 0.0;
  for (const Eigen::MatrixX2d& chart : charts) {
    prepared.push_back(prepare(chart));
    total_area += prepared.back().area;
    longest_side = std::max(longest_side, prepared.back().extent.maxCoeff());
  }
  const std::vector<int> order = packing_order(prepared);

  // No chart's raster can be wider than the atlas' inside (the lead-in and the raster's tolerance
  // add to its width).
  const double largest_scale =
      longest_side > 0.0 ? (static_cast<double>(inside) - 2 * chart_lead_in) / longest_side : 1.0;
  // Give up on a density this far below the largest: charts of no extent pack at any density, and
  // charts that fit at none were refused above; this only guards the loop.
  const double smallest_scale = largest_scale * 1e-12;
  constexpr int most_trials = 64;

  std::optional<Trial> best;                             // the densest trial that fits
  double failed_scale = std::numeric_limits<double>::infinity();  // the least dense that does not
  double scale = std::min(first_guess(prepared, options), largest_scale);
  if (!(scale > 0.0)) scale = largest_scale;
  int trials = 0;
  // Trials in a row that fitted, or that did not, before the densest fit is bracketed: each step
  // away is twice the last (in log scale), so that a poor first guess costs few trials.
  int fits_in_a_row = 0, misses_in_a_row = 0;
  auto galloping_step = [](int in_a_row) { return std::pow(1.0 + density_tolerance, std::ldexp(1.0, in_a_row - 1)); };
  while (trials < most_trials && scale >= smallest_scale) {
    Trial trial = pack_at(prepared, order, scale, options, total_area);
    ++trials;
    double predicted = scale;
    if (trial.fits) {
      ++fits_in_a_row;
      misses_in_a_row = 0;
      // The packing fills the atlas' width, so its height grows as the charts' area: as scale^2.
      const double used = std::max(1, trial.used_height - options.padding);
      predicted = scale * std::sqrt(static_cast<double>(inside) / used);
      best = std::move(trial);
      if (scale >= largest_scale || longest_side == 0.0) break;
    } else {
      ++misses_in_a_row;
      fits_in_a_row = 0;
      failed_scale = scale;
      predicted = scale * std::sqrt(trial.placed_area_fraction);
    }
    const double fitted_scale = best ? best->scale : 0.0;
    if (best && failed_scale <= fitted_scale * (1.0 + density_tolerance)) break;
    if (!best) {
      scale = std::min(predicted, scale / galloping_step(misses_in_a_row));
    } else if (failed_scale == std::numeric_limits<double>::infinity()) {
      scale = std::min(std::max(predicted, scale * galloping_step(fits_in_a_row)), largest_scale);
    } else {
      // Bracketed: the prediction where it falls well inside the bracket, else its middle.
      const double low = std::log(fitted_scale), high = std::log(failed_scale);
      const double margin = 0.1 * (high - low);
      const double guess = std::log(predicted);
      scale = guess > low + margin && guess < high - margin ? predicted : std::exp(0.5 * (low + high));
    }
  }
  if (!best) {
    throw Error(Status::invalid_input, "the charts do not fit in a " + std::to_string(options.resolution) + " x " +
                                           std::to_string(options.resolution) + " atlas at any density tried");
  }
  ChartPacking packing = result_of(charts, prepared, *best, options);
  packing.trials = trials;
  return packing;
}

}  // namespace harmonia::detail
