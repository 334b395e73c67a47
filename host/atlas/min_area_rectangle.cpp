#include "atlas/min_area_rectangle.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace harmonia::detail {

namespace {

double cross(const Eigen::Vector2d& origin, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - origin.x()) * (b.y() - origin.y()) - (a.y() - origin.y()) * (b.x() - origin.x());
}

bool lexicographically_less(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
}

//! Drops the points strictly inside the quadrilateral of the four extreme points (Akl and
//! Toussaint 1978): they cannot be on the hull, and in a chart of many triangles they are nearly
//! all of its corners, so the sort that follows has far less to do.
void drop_points_inside_extremes(std::vector<Eigen::Vector2d>& points) {
  if (points.size() < 8) return;
  Eigen::Vector2d left = points[0], right = points[0], bottom = points[0], top = points[0];
  for (const Eigen::Vector2d& point : points) {
    if (point.x() < left.x()) left = point;
    if (point.x() > right.x()) right = point;
    if (point.y() < bottom.y()) bottom = point;
    if (point.y() > top.y()) top = point;
  }
  // Counter-clockwise: bottom, right, top, left. A point strictly left of all four edges is inside.
  const Eigen::Vector2d corners[4] = {bottom, right, top, left};
  std::erase_if(points, [&](const Eigen::Vector2d& point) {
    for (int edge = 0; edge < 4; ++edge) {
      if (!(cross(corners[edge], corners[(edge + 1) % 4], point) > 0.0)) return false;
    }
    return true;
  });
}

double angle_in_quarter_turn(double angle) {
  // Into (-pi/4, pi/4]: the rectangle is the same after any quarter turn.
  constexpr double quarter_turn = std::numbers::pi / 2;
  double reduced = std::remainder(angle, quarter_turn);
  if (reduced <= -quarter_turn / 2) reduced += quarter_turn;
  return reduced;
}

//! The rectangle with sides `length` along `direction` and `depth` across it, as the reduced turn
//! that makes it axis aligned and its extents once turned.
OrientedRectangle rectangle_along(const Eigen::Vector2d& direction, double length, double depth) {
  const double turn = -std::atan2(direction.y(), direction.x());  // lays the direction along +x
  OrientedRectangle rectangle;
  rectangle.angle = angle_in_quarter_turn(turn);
  // The reduction changed the turn by whole quarter turns; an odd number swaps the sides.
  const long quarter_turns = std::lround((rectangle.angle - turn) / (std::numbers::pi / 2));
  const bool swapped = quarter_turns % 2 != 0;
  rectangle.width = swapped ? depth : length;
  rectangle.height = swapped ? length : depth;
  return rectangle;
}

}  // namespace

std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> points) {
  drop_points_inside_extremes(points);
  std::sort(points.begin(), points.end(), lexicographically_less);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  // Lower hull left to right, then upper hull right to left; a turn that is not strictly to the
  // left drops the middle point (collinear points included).
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t size = 0;
  for (const Eigen::Vector2d& point : points) {
    while (size >= 2 && cross(hull[size - 2], hull[size - 1], point) <= 0.0) --size;
    hull[size++] = point;
  }
  const std::size_t lower_size = size + 1;
  for (std::size_t index = points.size() - 1; index-- > 0;) {
    while (size >= lower_size && cross(hull[size - 2], hull[size - 1], points[index]) <= 0.0) --size;
    hull[size++] = points[index];
  }
  hull.resize(size - 1);  // the last point repeats the first
  return hull;
}

OrientedRectangle min_area_rectangle(const std::vector<Eigen::Vector2d>& hull) {
  OrientedRectangle best;
  const int count = static_cast<int>(hull.size());
  if (count < 2) return best;  // no point, or a single point: nothing to turn
  if (count == 2) return rectangle_along(hull[1] - hull[0], (hull[1] - hull[0]).norm(), 0.0);
  auto next = [count](int index) { return index + 1 == count ? 0 : index + 1; };
  // Calipers: for the direction of edge i, the hull points farthest along it (ahead), against it
  // (behind) and away from it (across). Each only moves forward as i goes round.
  int ahead = 0, behind = 0, across = 0;
  double best_area = -1.0;
  for (int edge = 0; edge < count; ++edge) {
    const Eigen::Vector2d direction = (hull[next(edge)] - hull[edge]).normalized();
    const Eigen::Vector2d normal(-direction.y(), direction.x());  // into the hull
    auto along = [&](int index) { return direction.dot(hull[index]); };
    auto away = [&](int index) { return normal.dot(hull[index]); };
    if (edge == 0) {
      for (int index = 1; index < count; ++index) {
        if (along(index) > along(ahead)) ahead = index;
        if (along(index) < along(behind)) behind = index;
        if (away(index) > away(across)) across = index;
      }
    } else {
      while (along(next(ahead)) > along(ahead)) ahead = next(ahead);
      while (along(next(behind)) < along(behind)) behind = next(behind);
      while (away(next(across)) > away(across)) across = next(across);
    }
    const double length = along(ahead) - along(behind);
    const double depth = away(across) - away(edge);
    const double area = length * depth;
    if (best_area < 0.0 || area < best_area) {
      best_area = area;
      best = rectangle_along(direction, length, depth);
    }
  }
  return best;
}

}  // namespace harmonia::detail
