#include "atlas/chart_raster.h"

#include <algorithm>
#include <cmath>

namespace harmonia::detail {

namespace {

//! The corners in counter-clockwise order (a degenerate triangle keeps its order).
struct CounterClockwiseTriangle {
  Eigen::Vector2d corners[3];
  double twice_area = 0.0;

  CounterClockwiseTriangle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    twice_area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    corners[0] = a;
    corners[1] = twice_area < 0.0 ? c : b;
    corners[2] = twice_area < 0.0 ? b : c;
    twice_area = std::abs(twice_area);
  }
};

//! Texel rows [first, last] that the triangle's bounding box, grown by `margin`, meets in a
//! bitmap of `height` rows (first > last for none).
struct RowRange {
  int first = 0;
  int last = -1;
};

RowRange rows_within(const CounterClockwiseTriangle& triangle, double margin, int height) {
  const double low = std::min({triangle.corners[0].y(), triangle.corners[1].y(), triangle.corners[2].y()});
  const double high = std::max({triangle.corners[0].y(), triangle.corners[1].y(), triangle.corners[2].y()});
  RowRange range;
  range.first = std::max(0, static_cast<int>(std::floor(low - margin)));
  range.last = std::min(height - 1, static_cast<int>(std::floor(high + margin)));
  return range;
}

}  // namespace

void rasterize_triangle_conservatively(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                       const Eigen::Vector2d& c, TexelBitmap& bitmap) {
  const CounterClockwiseTriangle triangle(a, b, c);
  const Eigen::Vector2d* corners = triangle.corners;
  const double left = std::min({corners[0].x(), corners[1].x(), corners[2].x()});
  const double right = std::max({corners[0].x(), corners[1].x(), corners[2].x()});
  const int box_first_column = std::max(0, static_cast<int>(std::floor(left - raster_tolerance)));
  const int box_last_column =
      std::min(bitmap.width() - 1, static_cast<int>(std::floor(right + raster_tolerance)));
  const RowRange rows = rows_within(triangle, raster_tolerance, bitmap.height());
  // Separating axes (the texel square and the triangle are convex): the two axes of the square,
  // which the bounding box above settles, and the normal of each edge. A texel whose centre is
  // (cx, cy) meets the edge from `from` along `along`, grown by the tolerance, where
  //   along.x (cy - from.y) - along.y (cx - from.x) + slack >= 0,
  // the slack being half of |along.x| + |along.y| (the square's farthest corner along the
  // edge's normal) plus the tolerance times the edge's length. Per row, that bounds cx.
  struct Edge {
    double along_x, along_y, from_y, constant;  // constant: along.y from.x + slack
  };
  Edge edges[3];
  for (int edge = 0; edge < 3; ++edge) {
    const Eigen::Vector2d& from = corners[edge];
    const Eigen::Vector2d along = corners[(edge + 1) % 3] - from;
    const double slack = 0.5 * (std::abs(along.x()) + std::abs(along.y())) + raster_tolerance * along.norm();
    edges[edge] = Edge{along.x(), along.y(), from.y(), along.y() * from.x() + slack};
  }
  for (int y = rows.first; y <= rows.last; ++y) {
    const double centre_y = y + 0.5;
    double first_column = box_first_column, last_column = box_last_column;
    bool empty = false;
    for (const Edge& edge : edges) {
      const double constant = edge.along_x * (centre_y - edge.from_y) + edge.constant;
      if (edge.along_y > 0.0) {
        last_column = std::min(last_column, std::floor(constant / edge.along_y - 0.5));
      } else if (edge.along_y < 0.0) {
        first_column = std::max(first_column, std::ceil(constant / edge.along_y - 0.5));
      } else if (constant < 0.0) {
        empty = true;
      }
    }
    if (empty || first_column > last_column) continue;
    bitmap.set_span(static_cast<int>(first_column), static_cast<int>(last_column) + 1, y);
  }
}

void rasterize_triangle_centres(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const Eigen::Vector2d& c, TexelBitmap& bitmap) {
  const CounterClockwiseTriangle triangle(a, b, c);
  if (!(triangle.twice_area > 0.0)) return;
  const Eigen::Vector2d* corners = triangle.corners;
  const double left = std::min({corners[0].x(), corners[1].x(), corners[2].x()});
  const double right = std::max({corners[0].x(), corners[1].x(), corners[2].x()});
  const int box_first_column = std::max(0, static_cast<int>(std::floor(left - 0.5)));
  const int box_last_column = std::min(bitmap.width() - 1, static_cast<int>(std::floor(right - 0.5)) + 1);
  if (box_first_column > box_last_column) return;  // beside the bitmap
  const RowRange rows = rows_within(triangle, 0.5, bitmap.height());
  // The texel centre strictly left of all three edges, evaluated exactly as an evaluator would,
  // so that a centre on an edge counts for neither triangle of that edge.
  auto inside = [&](int x, double centre_y) {
    const double centre_x = x + 0.5;
    for (int edge = 0; edge < 3; ++edge) {
      const Eigen::Vector2d& from = corners[edge];
      const Eigen::Vector2d& to = corners[(edge + 1) % 3];
      if (!((to.x() - from.x()) * (centre_y - from.y()) - (to.y() - from.y()) * (centre_x - from.x()) > 0.0)) {
        return false;
      }
    }
    return true;
  };
  for (int y = rows.first; y <= rows.last; ++y) {
    const double centre_y = y + 0.5;
    // The span from the edges' crossings with the row, then its two ends settled by the exact
    // test (the division may round a centre on the wrong side of an edge).
    double first = box_first_column, last = box_last_column;
    for (int edge = 0; edge < 3; ++edge) {
      const Eigen::Vector2d& from = corners[edge];
      const Eigen::Vector2d along = corners[(edge + 1) % 3] - from;
      const double constant = along.x() * (centre_y - from.y()) + along.y() * from.x();
      if (along.y() > 0.0) last = std::min(last, std::floor(constant / along.y() - 0.5));
      if (along.y() < 0.0) first = std::max(first, std::ceil(constant / along.y() - 0.5));
    }
    int first_column = static_cast<int>(std::clamp<double>(first, box_first_column, box_last_column + 1));
    int last_column = static_cast<int>(std::clamp<double>(last, box_first_column - 1, box_last_column));
    while (first_column > box_first_column && inside(first_column - 1, centre_y)) --first_column;
    while (first_column <= last_column && !inside(first_column, centre_y)) ++first_column;
    while (last_column < box_last_column && inside(last_column + 1, centre_y)) ++last_column;
    while (last_column >= first_column && !inside(last_column, centre_y)) --last_column;
    if (first_column <= last_column) bitmap.set_span(first_column, last_column + 1, y);
  }
}

}  // namespace harmonia::detail
