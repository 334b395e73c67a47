#include "atlas/long_chart_cut.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "atlas/chart_mesh.h"
#include "atlas/chart_packing.h"
#include "atlas/min_area_rectangle.h"

namespace harmonia::detail {

namespace {

// The share of the atlas' inside that compact charts would fill: what packings of corpus charts
// reach (0.67-0.75 measured), so the density the charts' area allows is about
// sqrt(share) inside / sqrt(area).
constexpr double kCompactFill = 0.7;

// A chart's extent along its long axis (the longer side of its tightest box) and the chart faces
// at either end of it (by their centroids; ties to the lower face).
struct LongAxis {
  double length = 0.0;
  int first_face = 0, last_face = 0;
};

LongAxis long_axis(const FinishedChart& chart) {
  const Eigen::MatrixX2d& uv = chart.layout.uv;
  std::vector<Eigen::Vector2d> points(static_cast<std::size_t>(uv.rows()));
  for (Eigen::Index v = 0; v < uv.rows(); ++v) points[static_cast<std::size_t>(v)] = uv.row(v).transpose();
  const OrientedRectangle box = min_area_rectangle(convex_hull(std::move(points)));
  // Turned by box.angle the box is axis aligned; its longer side is along x or y.
  const Eigen::Vector2d along = box.width >= box.height ? Eigen::Vector2d(std::cos(box.angle), -std::sin(box.angle))
                                                        : Eigen::Vector2d(std::sin(box.angle), std::cos(box.angle));
  LongAxis axis;
  axis.length = std::max(box.width, box.height);
  const Eigen::MatrixX3i& faces = chart.mesh.mesh.faces;
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const double position = (uv.row(faces(f, 0)) + uv.row(faces(f, 1)) + uv.row(faces(f, 2))).dot(along.transpose());
    if (position < lowest) {
      lowest = position;
      axis.first_face = static_cast<int>(f);
    }
    if (position > highest) {
      highest = position;
      axis.last_face = static_cast<int>(f);
    }
  }
  return axis;
}

}  // namespace

std::optional<std::vector<FinishedChart>> long_charts_split(const Mesh& surface, const FaceGeometry& geometry,
                                                          double max_stretch, int width, int height, int padding,
                                                          const std::vector<FinishedChart>& whole) {
  double area = 0.0;
  for (const FinishedChart& chart : whole)
    for (const int face : chart.mesh.surface_face) area += geometry.area[static_cast<std::size_t>(face)];
  if (!(area > 0.0)) return std::nullopt;
  const int margin = atlas_edge_margin(padding);
  const double inside_width = width - 2 * margin, inside_height = height - 2 * margin;
  // Lengths in the layouts' units (3D lengths): the longest that fits the atlas' longer side at
  // the density the area allows (the charts filling kCompactFill of the inside).
  const double density = std::sqrt(kCompactFill * inside_width * inside_height / area);
  const double longest = std::max(inside_width, inside_height) / density;
  std::vector<FinishedChart> pending = whole, charts;
  bool split = false;
  while (!pending.empty()) {
    FinishedChart chart = std::move(pending.back());
    pending.pop_back();
    const LongAxis axis = chart.mesh.surface_face.size() > 1 ? long_axis(chart) : LongAxis{};
    if (!(axis.length > longest)) {
      charts.push_back(std::move(chart));
      continue;
    }
    const std::vector<int>& faces = chart.mesh.surface_face;
    std::vector<FinishedChart> pieces;
    for (std::vector<int>& half : split_between(geometry, faces, faces[static_cast<std::size_t>(axis.first_face)],
                                                        faces[static_cast<std::size_t>(axis.last_face)])) {
      ChartMesh piece = opened_chart(surface, geometry, half);
      if (!is_disk(piece)) break;
      std::optional<FlattenedChart> layout =
          restricted_layout(chart.mesh, chart.layout.uv, piece, chart.layout.method, max_stretch).chart;
      if (!layout) break;
      pieces.push_back(FinishedChart{std::move(piece), std::move(*layout)});
    }
    if (pieces.size() != 2) {
      charts.push_back(std::move(chart));
      continue;
    }
    for (FinishedChart& piece : pieces) pending.push_back(std::move(piece));
    split = true;
  }
  if (!split) return std::nullopt;
  std::sort(charts.begin(), charts.end(), [](const FinishedChart& a, const FinishedChart& b) {
    return a.mesh.surface_face.front() < b.mesh.surface_face.front();
  });
  return charts;
}

bool cut_worth_its_charts(std::size_t whole_charts, double whole_coverage, std::size_t cut_charts,
                          double cut_coverage) {
  if (!(whole_coverage > 0.0) || whole_charts == 0) return cut_coverage > whole_coverage;
  const double coverage_gain = cut_coverage / whole_coverage - 1.0;
  const double chart_gain = static_cast<double>(cut_charts) / static_cast<double>(whole_charts) - 1.0;
  return coverage_gain > 0.0 && coverage_gain >= kCoverageGainPerChartGain * chart_gain;
}

}  // namespace harmonia::detail
