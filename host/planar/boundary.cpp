// Boundary placement for fixed-boundary maps: the boundary loop is laid out on a convex shape
// with spacing proportional to 3D arc length (so the boundary's own proportions survive), or to
// the geometric mean of each edge's length and its triangle's side (BoundarySpacing).
// Input is assumed validated by the caller (the mappers report bad `given` data as a status).

#include "harmonia/boundary.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include <Eigen/Geometry>

#include "mesh/power_of_two_scale.h"

namespace harmonia {
namespace {

// Cumulative 3D arc length at each loop vertex (0 at loop[0]) and the total perimeter.
struct ArcLength {
  std::vector<double> at_vertex;
  double total = 0.0;
};

// The area of the face that holds each loop edge loop[k] -> loop[k + 1] (the mesh lies to the
// loop's left, so the edge is a half-edge of that face); 0 where no face holds it.
std::vector<double> loop_edge_triangle_areas(const Mesh& mesh, const std::vector<int>& loop) {
  std::unordered_map<int, std::size_t> position;
  for (std::size_t k = 0; k < loop.size(); ++k) position.emplace(loop[k], k);
  std::vector<double> areas(loop.size(), 0.0);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const auto found = position.find(mesh.faces(f, c));
      if (found == position.end()) continue;
      const std::size_t k = found->second;
      if (loop[(k + 1) % loop.size()] != mesh.faces(f, (c + 1) % 3)) continue;
      const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
      const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
      const Eigen::Vector3d d = mesh.vertices.row(mesh.faces(f, 2));
      areas[k] = 0.5 * (b - a).cross(d - a).norm();
    }
  }
  return areas;
}

// The cumulative share of each loop vertex under `spacing` (arc length, or the geometric mean of
// each edge's length and its triangle's side) and the total.
ArcLength arc_length(const Mesh& mesh, const std::vector<int>& loop, BoundarySpacing spacing) {
  ArcLength arc;
  const std::size_t n = loop.size();
  arc.at_vertex.resize(n, 0.0);
  const std::vector<double> areas = spacing == BoundarySpacing::edge_and_triangle_size
                                        ? loop_edge_triangle_areas(mesh, loop)
                                        : std::vector<double>();
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) arc.at_vertex[k] = arc.total;
    const double length = (mesh.vertices.row(loop[(k + 1) % n]) - mesh.vertices.row(loop[k])).norm();
    arc.total += areas.empty() ? length : std::sqrt(length * std::sqrt(areas[k]));
  }
  // A loop of coincident points has no length: fall back to equal spacing.
  if (!(arc.total > 0.0)) {
    for (std::size_t k = 0; k < n; ++k) arc.at_vertex[k] = static_cast<double>(k);
    arc.total = static_cast<double>(n);
  }
  return arc;
}

BoundaryPlacement place_on_circle(const Mesh& mesh, const std::vector<int>& loop,
                                  BoundarySpacing spacing) {
  const ArcLength arc = arc_length(mesh, loop, spacing);
  BoundaryPlacement placement;
  placement.vertices.resize(static_cast<Eigen::Index>(loop.size()));
  placement.uv.resize(static_cast<Eigen::Index>(loop.size()), 2);
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const double angle = 2.0 * std::numbers::pi * arc.at_vertex[k] / arc.total;
    const auto row = static_cast<Eigen::Index>(k);
    placement.vertices[row] = loop[k];
    placement.uv.row(row) << std::cos(angle), std::sin(angle);
  }
  return placement;
}

// The four corners of [-1,1]^2, counter-clockwise.
const std::array<Eigen::Vector2d, 4> square_corners = {
    Eigen::Vector2d(-1.0, -1.0), Eigen::Vector2d(1.0, -1.0), Eigen::Vector2d(1.0, 1.0),
    Eigen::Vector2d(-1.0, 1.0)};

BoundaryPlacement place_on_square(const Mesh& mesh, const std::vector<int>& loop,
                                  BoundarySpacing spacing) {
  const ArcLength arc = arc_length(mesh, loop, spacing);
  const int n = static_cast<int>(loop.size());
  BoundaryPlacement placement;
  placement.vertices.resize(n);
  placement.uv.resize(n, 2);
  for (int k = 0; k < n; ++k) placement.vertices[k] = loop[static_cast<std::size_t>(k)];
  if (n < 4) {
    // Too few vertices for four corners (validation normally rejects this): use corners in order.
    for (int k = 0; k < n; ++k) placement.uv.row(k) = square_corners[static_cast<std::size_t>(k)];
    return placement;
  }
  // Corner c sits at the loop vertex nearest to arc length c/4 of the perimeter, kept strictly
  // increasing so each side gets at least one edge.
  std::array<int, 5> corner = {0, 0, 0, 0, n};
  for (int c = 1; c < 4; ++c) {
    const double target = arc.total * c / 4.0;
    int best = corner[c - 1] + 1;
    for (int k = best; k <= n - (4 - c); ++k) {
      if (std::abs(arc.at_vertex[k] - target) < std::abs(arc.at_vertex[best] - target)) best = k;
    }
    corner[c] = best;
  }
  // Along each side, positions proportional to arc length between its two corners.
  for (int side = 0; side < 4; ++side) {
    const int first = corner[side], last = corner[side + 1];
    const double start = arc.at_vertex[first];
    const double end = last < n ? arc.at_vertex[last] : arc.total;
    const Eigen::Vector2d from = square_corners[side], to = square_corners[(side + 1) % 4];
    for (int k = first; k < last; ++k) {
      const double t = end > start ? (arc.at_vertex[k] - start) / (end - start)
                                   : static_cast<double>(k - first) / (last - first);
      placement.uv.row(k) = (1.0 - t) * from + t * to;
    }
  }
  return placement;
}

}  // namespace

BoundaryPlacement place_boundary(const Mesh& mesh, const std::vector<int>& loop,
                                 const BoundaryOptions& options) {
  // Only ratios of arc lengths matter: measured on the copy of unit size, whose perimeter neither
  // overflows (a model in units of 1e300) nor underflows, with the same ratios bit for bit.
  switch (options.shape) {
    case BoundaryShape::circle:
      return place_on_circle(detail::unit_scaled(mesh).mesh, loop, options.spacing);
    case BoundaryShape::square:
      return place_on_square(detail::unit_scaled(mesh).mesh, loop, options.spacing);
    case BoundaryShape::given:
      return BoundaryPlacement{options.given_vertices, options.given_uv};
  }
  return {};
}

}  // namespace harmonia
