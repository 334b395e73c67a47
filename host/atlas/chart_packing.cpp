#include "atlas/chart_packing.h"

#include <algorithm>
#include <array>
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
#include "mesh/for_each_index.h"

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
  std::vector<int> pages;                     //!< The page of each chart.
  int page_count = 1;
  std::vector<Eigen::Vector2i> raster_sizes;  //!< Width and height of each chart's unturned raster.
  int used_height = 0;                        //!< Of a trial that fits.
  double placed_fraction = 0.0;  //!< Of a trial that does not fit: the share of the footprint placed.
};

int atlas_height(const PackingOptions& options) { return options.height > 0 ? options.height : options.resolution; }

//! "width x height".
std::string size_text(const PackingOptions& options) {
  return std::to_string(options.resolution) + " x " + std::to_string(atlas_height(options));
}

//! The largest density at which a chart whose tightest box has sides `extent` fits the atlas'
//! inside in one of its quarter turns (the lead-in on each side adds to its raster); infinite for
//! a chart of no extent.
double largest_scale_for(const Eigen::Vector2d& extent, const PackingOptions& options) {
  const int margin = atlas_edge_margin(options.padding);
  const double inside_width = options.resolution - 2 * margin - 2 * chart_lead_in;
  const double inside_height = atlas_height(options) - 2 * margin - 2 * chart_lead_in;
  const double long_inside = std::max(inside_width, inside_height), short_inside = std::min(inside_width, inside_height);
  const double long_side = extent.maxCoeff(), short_side = extent.minCoeff();
  double scale = std::numeric_limits<double>::infinity();
  if (long_side > 0.0) scale = long_inside / long_side;
  if (short_side > 0.0) scale = std::min(scale, short_inside / short_side);
  return scale;
}

Eigen::Matrix2d rotation(double angle) {
  const double cosine = std::cos(angle), sine = std::sin(angle);
  Eigen::Matrix2d turn;
  turn << cosine, -sine, sine, cosine;
  return turn;
}

void validate(const std::vector<Eigen::MatrixX2d>& charts, const PackingOptions& options) {
  for (const int side : {options.resolution, atlas_height(options)}) {
    if (side < smallest_resolution || side > largest_resolution) {
      throw Error(Status::invalid_input, "the atlas resolution (each side) must be in [" + std::to_string(smallest_resolution) +
                                             ", " + std::to_string(largest_resolution) + "], not " + size_text(options));
    }
  }
  if (options.padding < 0 || options.padding > largest_padding) {
    throw Error(Status::invalid_input, "the atlas padding must be in [0, " + std::to_string(largest_padding) +
                                           "], not " + std::to_string(options.padding));
  }
  if (std::min(options.resolution, atlas_height(options)) - 2 * atlas_edge_margin(options.padding) < 1) {
    throw Error(Status::invalid_input, "a padding of " + std::to_string(options.padding) +
                                           " leaves no texel inside a " + size_text(options) + " atlas");
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

PreparedChart prepare(const Eigen::MatrixX2d& chart, bool quarter_turns_only) {
  PreparedChart prepared;
  if (!quarter_turns_only) {
    std::vector<Eigen::Vector2d> points(static_cast<std::size_t>(chart.rows()));
    for (Eigen::Index row = 0; row < chart.rows(); ++row) points[row] = chart.row(row).transpose();
    prepared.angle = min_area_rectangle(convex_hull(std::move(points))).angle;
  }
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

//! Widest box first: by the box's half-perimeter (xatlas' order), then by area; ties in input
//! order. A chart with a large box for its area (a ring, an arc) goes before the charts that can
//! fill its inside.
std::vector<int> packing_order_by_box(const std::vector<PreparedChart>& charts) {
  std::vector<int> order(charts.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int first, int second) {
    const PreparedChart& a = charts[first];
    const PreparedChart& b = charts[second];
    const double a_half = a.extent.sum(), b_half = b.extent.sum();
    if (a_half != b_half) return a_half > b_half;
    return a.area > b.area;
  });
  return order;
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

//! The texels the charts take at a density, as a model: each chart a square of its area, one
//! texel wider for the edge of its conservative raster and `padding` wider for the gap,
//!   footprint(s) = sum (s sqrt(area) + 1 + padding)^2 = area s^2 + 2 sides s + borders.
//! The packer fills the atlas with such footprints to some share, which each trial measures; the
//! next density is the one whose footprint fills the atlas at that share. The model sees that
//! padding and raster edges do not grow with the density.
struct FootprintModel {
  double border = 1.0;   //!< 1 + padding
  double area = 0.0;     //!< sum of the charts' areas
  double sides = 0.0;    //!< border sum sqrt(area)
  double borders = 0.0;  //!< charts border^2

  explicit FootprintModel(int padding) : border(1.0 + padding) {}
  void add(double chart_area) {
    area += chart_area;
    sides += border * std::sqrt(chart_area);
    borders += border * border;
  }
  [[nodiscard]] double at(double scale) const { return (area * scale + 2.0 * sides) * scale + borders; }
  //! The density whose footprint is `texels`: the positive root; infinite if the charts have no
  //! area nor extent, 0 if even their borders take more.
  [[nodiscard]] double scale_for(double texels) const {
    const double constant = borders - texels;
    if (constant >= 0.0) return 0.0;
    if (!(area > 0.0)) return sides > 0.0 ? -constant / (2.0 * sides) : std::numeric_limits<double>::infinity();
    return (-sides + std::sqrt(sides * sides - area * constant)) / area;
  }
};

Trial pack_at(const std::vector<PreparedChart>& charts, const std::vector<int>& order, double scale,
              const PackingOptions& options, const FootprintModel& model) {
  Trial trial;
  trial.scale = scale;
  trial.positions.resize(charts.size());
  trial.pages.assign(charts.size(), 0);
  trial.raster_sizes.resize(charts.size());
  // With several threads, the footprints first (each chart's alone on a thread), then placed one
  // by one; on one thread each just before it is placed, so that a trial that fails makes none
  // for the charts it never reaches.
  std::vector<ChartFootprint> footprints(charts.size());
  const bool footprints_first = options.threads > 1;
  if (footprints_first) {
    for_each_index(order.size(), options.threads,
                   [&](std::size_t k) { footprints[k] = chart_footprint(charts[order[k]].corners, scale); });
  }
  // The pages: one, and more at a fixed density when asked (each chart to the first with room).
  std::vector<AtlasOccupancy> pages;
  const int margin = atlas_edge_margin(options.padding);
  pages.emplace_back(options.resolution, atlas_height(options), options.padding, margin);
  const bool more_pages = options.fixed_scale > 0.0 && options.max_pages != 1;
  // Per page, the boxes of the charts that found no room on it (those that hold no other): a
  // chart whose box holds one of them is not searched for there. Exact for rectangles, and what
  // keeps a packing of many pages from searching every full page for every chart.
  std::vector<std::vector<std::pair<int, int>>> missed_boxes(1);
  FootprintModel placed(options.padding);  // the footprint placed so far
  // The search for holes resumes where the one before ended while the charts keep about the same
  // size and shape, and starts from the bottom again once one is this much smaller in area, or
  // narrower along either side of its box than the chart that last started it: 10 % keeps most of
  // the coverage of a search from the bottom for every chart (1 to 3 points less on the closed
  // corpus) at a fifth of its time at 10,000 charts. The sides matter where a long chart follows
  // wide ones, or any chart follows one with a hole (a plate around a window): the area rule
  // alone left the holes empty (idler_riser.STL coverage 0.53, 0.64 with the sides).
  constexpr double smaller_by = 1.1;
  double area_at_restart = std::numeric_limits<double>::infinity();
  std::pair<int, int> sides_at_restart{std::numeric_limits<int>::max(), std::numeric_limits<int>::max()};
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int chart = order[k];
    if (!footprints_first) footprints[k] = chart_footprint(charts[chart].corners, scale);
    const ChartFootprint& footprint = footprints[k];
    const int width = footprint.turned[0].width(), height = footprint.turned[0].height();
    const std::pair<int, int> box{std::min(width, height), std::max(width, height)};  // its sides
    if (charts[chart].area * smaller_by < area_at_restart || box.first * smaller_by < sides_at_restart.first ||
        box.second * smaller_by < sides_at_restart.second) {
      area_at_restart = charts[chart].area;
      sides_at_restart = box;
      for (AtlasOccupancy& page : pages) page.restart_search();
    }
    std::optional<AtlasPosition> position;
    std::size_t page = 0;
    for (; page < pages.size(); ++page) {
      std::vector<std::pair<int, int>>& missed = missed_boxes[page];
      if (std::any_of(missed.begin(), missed.end(), [&](const std::pair<int, int>& smaller) {
            return box.first >= smaller.first && box.second >= smaller.second;
          }))
        continue;
      if ((position = pages[page].find_position(footprint))) break;
      // Keep the boxes that missed least: this one, and those it does not hold.
      std::erase_if(missed, [&](const std::pair<int, int>& other) {
        return other.first >= box.first && other.second >= box.second;
      });
      missed.push_back(box);
    }
    if (position) {
      // found on an open page
    } else if (more_pages && (options.max_pages <= 0 || static_cast<int>(pages.size()) < options.max_pages)) {
      pages.emplace_back(options.resolution, atlas_height(options), options.padding, margin);
      missed_boxes.emplace_back();
      page = pages.size() - 1;
      position = pages.back().find_position(footprint);  // an empty page: fails only for a chart too wide
    }
    if (!position) {
      trial.placed_fraction = placed.at(scale) / model.at(scale);
      return trial;
    }
    pages[page].place(footprint, *position);
    trial.positions[chart] = *position;
    trial.pages[chart] = static_cast<int>(page);
    trial.raster_sizes[chart] = Eigen::Vector2i(footprint.turned[0].width(), footprint.turned[0].height());
    placed.add(charts[chart].area);
  }
  trial.fits = true;
  trial.used_height = pages.front().used_height();
  trial.page_count = static_cast<int>(pages.size());
  return trial;
}

ChartPacking result_of(const std::vector<Eigen::MatrixX2d>& input, const std::vector<PreparedChart>& charts,
                       const Trial& trial, const PackingOptions& options) {
  ChartPacking packing;
  packing.texels_per_unit = trial.scale;
  packing.placements.resize(charts.size());
  packing.pages = trial.page_count;
  std::vector<long long> covered(static_cast<std::size_t>(trial.page_count), 0);
  const Eigen::Vector2d lead_in(chart_lead_in, chart_lead_in);
  for (std::size_t chart = 0; chart < charts.size(); ++chart) {
    const AtlasPosition& position = trial.positions[chart];
    const Eigen::Vector2i& size = trial.raster_sizes[chart];
    // Corner p sits at turned_position(scale (R p - box_low) + lead-in) + position in the atlas;
    // turned_position is a quarter turn plus a shift, so the shift goes into the offset.
    ChartPlacement& placement = packing.placements[chart];
    placement.page = trial.pages[chart];
    constexpr double quarter_turn = std::numbers::pi / 2;
    placement.angle =
        std::remainder(charts[chart].angle + position.quarter_turns * quarter_turn, 2 * std::numbers::pi);
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
    covered[static_cast<std::size_t>(placement.page)] += centres.count();
  }
  const double page_texels = static_cast<double>(options.resolution) * atlas_height(options);
  long long total = 0;
  for (const long long count : covered) {
    packing.page_coverage.push_back(static_cast<double>(count) / page_texels);
    total += count;
  }
  packing.coverage = static_cast<double>(total) / (page_texels * trial.page_count);
  return packing;
}

}  // namespace

bool fits_one_page(const Eigen::MatrixX2d& chart, const PackingOptions& options) {
  return options.fixed_scale <= largest_scale_for(prepare(chart, options.quarter_turns_only).extent, options);
}

ChartPacking pack_charts(const std::vector<Eigen::MatrixX2d>& charts, const PackingOptions& options) {
  validate(charts, options);
  // Even charts of a single texel, `padding` apart, fill the atlas' inside at most this many.
  const int margin = atlas_edge_margin(options.padding);
  const long long inside_width = options.resolution - 2 * margin;
  const long long inside_height = atlas_height(options) - 2 * margin;
  const long long per_row = (inside_width + options.padding) / (1 + options.padding);
  const long long per_column = (inside_height + options.padding) / (1 + options.padding);
  const bool pages_open = options.fixed_scale > 0.0 && options.max_pages != 1;
  const long long most_charts = per_row * per_column * (pages_open && options.max_pages > 0 ? options.max_pages : 1);
  if (!(pages_open && options.max_pages <= 0) && static_cast<long long>(charts.size()) > most_charts) {
    throw Error(Status::invalid_input, std::to_string(charts.size()) + " charts cannot fit in a " +
                                           size_text(options) + " atlas with padding " +
                                           std::to_string(options.padding) + " at any density");
  }
  std::vector<PreparedChart> prepared;
  prepared.reserve(charts.size());
  double longest_side = 0.0;
  // The largest density at which every chart fits the atlas' inside in one of its quarter turns.
  double largest_scale = std::numeric_limits<double>::infinity();
  std::size_t limiting_chart = 0;
  for (const Eigen::MatrixX2d& chart : charts) {
    prepared.push_back(prepare(chart, options.quarter_turns_only));
    longest_side = std::max(longest_side, prepared.back().extent.maxCoeff());
    const double scale = largest_scale_for(prepared.back().extent, options);
    if (scale < largest_scale) {
      largest_scale = scale;
      limiting_chart = prepared.size() - 1;
    }
  }
  if (!std::isfinite(largest_scale)) largest_scale = 1.0;  // charts of no extent pack at any density
  const std::vector<int> order = packing_order(prepared);
  FootprintModel model(options.padding);
  for (const int chart : order) model.add(prepared[chart].area);  // the same sums in any input order

  if (options.fixed_scale > 0.0) {
    // One trial at the density asked for: the charts fit there, or the atlas is too small.
    if (options.fixed_scale > largest_scale) {
      const Eigen::Vector2d box = options.fixed_scale * prepared[limiting_chart].extent;
      throw Error(Status::invalid_input,
                  "at the density asked for chart " + std::to_string(limiting_chart) + " is " +
                      std::to_string(static_cast<long long>(std::ceil(box.maxCoeff()))) + " x " +
                      std::to_string(static_cast<long long>(std::ceil(box.minCoeff()))) + " texels, more than the " +
                      std::to_string(inside_width) + " x " + std::to_string(inside_height) + " inside a " +
                      size_text(options) + " atlas");
    }
    const Trial trial = pack_at(prepared, order, options.fixed_scale, options, model);
    if (!trial.fits) {
      const std::string where = options.max_pages == 1 ? "a " : std::to_string(options.max_pages) + " pages of ";
      throw Error(Status::invalid_input,
                  "at the density asked for the charts do not fit in " + where + size_text(options) +
                      " texels (" + std::to_string(static_cast<int>(100.0 * trial.placed_fraction)) +
                      " % of them placed)");
    }
    ChartPacking packing = result_of(charts, prepared, trial, options);
    packing.trials = 1;
    return packing;
  }

  // No chart's raster can be wider than the atlas' inside (largest_scale above).
  // Give up on a density this far below the largest: charts of no extent pack at any density, and
  // charts that fit at none were refused above; this only guards the loop.
  const double smallest_scale = largest_scale * 1e-12;
  constexpr int most_trials = 64;

  // The densities are tried two at a time, side by side on two threads (one after the other on
  // one: the same trials, so the same packing, for any thread count): a pair around the first
  // guess, then pairs further up or down while every trial fits or none does, then, once a
  // fitting density and a denser failing one bracket the answer, the two points that cut the
  // bracket in thirds (in log scale), until it is within density_tolerance.
  std::optional<Trial> best;     // the densest trial that fits
  std::vector<Trial> failures;   // the trials that did not (their scale and placed share)
  // The first pair: footprints filling 80 % of the inside, about what packings of these
  // footprints reach (65 to 90 % measured, from xatlas' charts of corpus meshes to random
  // blobs), and 70 %.
  constexpr double usual_share = 0.8, lower_share = 0.7;
  const double inside_area = static_cast<double>(inside_width) * static_cast<double>(inside_height);
  const auto first_guess = [&](double share) {
    const double guess = std::min(model.scale_for(share * inside_area), largest_scale);
    return guess > 0.0 ? guess : largest_scale;
  };
  std::array<double, 2> pair{first_guess(lower_share), first_guess(usual_share)};
  if (longest_side == 0.0) pair = {largest_scale, largest_scale};  // every density packs the same
  int trials = 0;
  int pairs_beyond = 0;  // pairs in a row that all fit, or all failed, before a bracket
  const int pair_threads = std::min(2, std::max(1, options.threads));
  PackingOptions trial_options = options;
  trial_options.threads = std::max(1, options.threads / pair_threads);
  while (trials < most_trials) {
    const bool single = pair[0] >= pair[1];
    std::array<Trial, 2> tried;
    for_each_index(single ? 1 : 2, pair_threads, [&](std::size_t k) {
      tried[k] = pack_at(prepared, order, pair[k], trial_options, model);
    });
    trials += single ? 1 : 2;
    for (int k = 0; k < (single ? 1 : 2); ++k) {
      if (!tried[k].fits) {
        failures.push_back(std::move(tried[k]));
      } else if (!best || tried[k].scale > best->scale) {
        best = std::move(tried[k]);
      }
    }
    if (longest_side == 0.0) break;
    // The least dense failure above the best fit.
    const Trial* failed = nullptr;
    for (const Trial& failure : failures)
      if ((!best || failure.scale > best->scale) && (!failed || failure.scale < failed->scale)) failed = &failure;
    if (best && failed && failed->scale <= best->scale * (1.0 + density_tolerance)) break;
    if (best && !failed && best->scale >= largest_scale) break;
    if (best && failed) {
      const double low = std::log(best->scale), high = std::log(failed->scale);
      pair = {std::exp(low + (high - low) / 3.0), std::exp(low + 2.0 * (high - low) / 3.0)};
      continue;
    }
    // Beyond the pairs so far: a step at least the last pair's spread, doubling from the third
    // such pair on (charts that are mostly padding make a first guess far off).
    ++pairs_beyond;
    const double spread = std::max(pair[1] / pair[0], 1.0 + density_tolerance) *
                          std::ldexp(1.0, std::max(0, pairs_beyond - 2));
    if (!best) {
      // Below the least dense failure: where what it placed would fill the atlas, at most halved.
      const Trial& lowest = *std::min_element(failures.begin(), failures.end(),
                                              [](const Trial& a, const Trial& b) { return a.scale < b.scale; });
      const double predicted = std::max(model.scale_for(model.at(lowest.scale) * lowest.placed_fraction), lowest.scale / 2);
      const double high = std::min(predicted, lowest.scale / spread);
      if (!(high >= smallest_scale)) break;
      pair = {high / spread, high};
    } else {
      // Above the best fit: it fills the atlas' width and `used` of its rows, the same share of the
      // whole; a step at least the spread.
      const double used = std::max(1, best->used_height - margin);
      const double predicted = model.scale_for(model.at(best->scale) * static_cast<double>(inside_height) / used);
      const double low = std::min(std::max(predicted, best->scale * spread), largest_scale);
      pair = {low, std::min(low * spread, largest_scale)};
    }
  }
  if (!best) {
    throw Error(Status::invalid_input, "the charts do not fit in a " + size_text(options) +
                                           " atlas at any density tried");
  }
  // Largest first is the better order on most atlases, but not on all: where a ring or an arc
  // leaves its inside empty for want of charts placed after it, the widest box first fills it.
  // That order is tried above the density found, a pair at a time (2 % and 5 % denser, then on
  // while both fit), and kept where it fits denser.
  if (const std::vector<int> by_box = packing_order_by_box(prepared);
      by_box != order && longest_side > 0.0 && best->scale < largest_scale) {
    double step = 1.0 + 2.0 * density_tolerance;
    for (int round = 0; round < 4; ++round) {
      pair = {std::min(best->scale * step, largest_scale), std::min(best->scale * step * 1.03, largest_scale)};
      std::array<Trial, 2> tried;
      for_each_index(2, pair_threads, [&](std::size_t k) {
        tried[k] = pack_at(prepared, by_box, pair[k], trial_options, model);
      });
      trials += 2;
      bool both = true;
      for (Trial& trial : tried) {
        if (trial.fits && trial.scale > best->scale) best = std::move(trial);
        else if (!trial.fits) both = false;
      }
      if (!both || best->scale >= largest_scale) break;
      step = 1.03;
    }
  }
  ChartPacking packing = result_of(charts, prepared, *best, options);
  packing.trials = trials;
  return packing;
}

}  // namespace harmonia::detail
