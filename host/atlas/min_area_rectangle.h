#pragma once
// Internal: the tightest box around a chart. The box of least area around a convex polygon has a
// side on one of the polygon's edges (Freeman and Shapira 1975), so rotating calipers find it in
// one turn around the convex hull (Toussaint 1983).

#include <vector>

#include <Eigen/Core>

namespace harmonia::detail {

//! The convex hull of `points`, counter-clockwise from the lowest-leftmost point, without repeated
//! or collinear points (Andrew's monotone chain). One point for a single point, two for a segment.
[[nodiscard]] std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> points);

struct OrientedRectangle {
  //! Turning the points by `angle` (radians, counter-clockwise) makes the rectangle axis aligned;
  //! in (-pi/4, pi/4], the smallest turn that does (the other three differ by quarter turns).
  double angle = 0.0;
  double width = 0.0;   //!< Its extent along x once turned.
  double height = 0.0;  //!< Its extent along y once turned.
};

//! The rectangle of least area around a convex hull (as convex_hull returns it). Of rectangles of
//! equal area (a square, a regular polygon), the one found first from the hull's first edge.
[[nodiscard]] OrientedRectangle min_area_rectangle(const std::vector<Eigen::Vector2d>& hull);

}  // namespace harmonia::detail
