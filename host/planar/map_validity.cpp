// Validity of a UV layout: flipped or degenerate triangles, and crossings of its boundary.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "harmonia/metrics.h"
#include "harmonia/types.h"
#include "mesh/power_of_two_scale.h"
#include "planar/boundary_crossings.h"
#include "planar/exact_orientation.h"
#include "planar/uv_layout_checks.h"

namespace harmonia {
namespace detail {

void check_uv_faces(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces,
                    const char* caller) {
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) {
    for (int corner = 0; corner < 3; ++corner) {
      const int index = uv_faces(f, corner);
      if (index < 0 || index >= uv.rows()) {
        throw Error(Status::invalid_input,
                    std::string(caller) + ": uv_faces row " + std::to_string(f) + " corner " +
                        std::to_string(corner) + " refers to uv row " + std::to_string(index) +
                        ", but uv has " + std::to_string(uv.rows()) + " rows");
      }
    }
  }
}

std::vector<double> signed_uv_areas(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces) {
  std::vector<double> areas(static_cast<std::size_t>(uv_faces.rows()));
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) {
    const Eigen::Vector2d a = uv.row(uv_faces(f, 0));
    const Eigen::Vector2d b = uv.row(uv_faces(f, 1));
    const Eigen::Vector2d c = uv.row(uv_faces(f, 2));
    const Eigen::Vector2d ab = b - a, ac = c - a;
    areas[static_cast<std::size_t>(f)] = 0.5 * (ab.x() * ac.y() - ab.y() * ac.x());
  }
  return areas;
}

TriangleState classify_uv_triangle(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces,
                                   Eigen::Index face, double signed_area) {
  if (!std::isfinite(signed_area)) return TriangleState::degenerate;
  const Eigen::Vector2d a = uv.row(uv_faces(face, 0));
  const Eigen::Vector2d b = uv.row(uv_faces(face, 1));
  const Eigen::Vector2d c = uv.row(uv_faces(face, 2));
  // The exact orientation decides the sign. A triangle also counts as zero-area when its area is
  // within what rounding its corners could change: moving a corner by d changes the area by at
  // most d times half the opposite edge, and a coordinate of size m is only known to eps m. A
  // triangle far from the origin thus needs a larger area than one near it, but a tiny triangle
  // whose shape the coordinates do resolve (a map that shrinks a protrusion by 1e-10 in length)
  // is a valid triangle.
  const int sign = orientation_sign(a, b, c);
  const double magnitude = std::max({a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(),
                                     c.cwiseAbs().maxCoeff()});
  const double perimeter = (b - a).norm() + (c - b).norm() + (a - c).norm();
  const double resolution =
      kAreaResolutionFactor * std::numeric_limits<double>::epsilon() * magnitude * perimeter;
  if (sign == 0 || std::abs(signed_area) <= resolution) return TriangleState::degenerate;
  return sign > 0 ? TriangleState::positive : TriangleState::flipped;
}

double total_finite_area(const std::vector<double>& signed_areas) {
  double total = 0.0;
  for (const double area : signed_areas) {
    if (std::isfinite(area)) total += std::abs(area);
  }
  return total;
}

}  // namespace detail

namespace {

FlipCount count_flips_in_safe_range(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces) {
  detail::check_uv_faces(uv, uv_faces, "count_flips");
  const std::vector<double> areas = detail::signed_uv_areas(uv, uv_faces);
  const double total = detail::total_finite_area(areas);
  FlipCount count;
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) {
    const double area = areas[static_cast<std::size_t>(f)];
    switch (detail::classify_uv_triangle(uv, uv_faces, f, area)) {
      case detail::TriangleState::positive:
        if (area <= detail::kZeroAreaFraction * total) ++count.tiny;
        break;
      case detail::TriangleState::flipped:
        ++count.flipped;
        break;
      case detail::TriangleState::degenerate:
        ++count.zero_area;
        break;
    }
  }
  return count;
}

}  // namespace

FlipCount count_flips(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces) {
  // The counts do not change when the layout is scaled by a power of two (exact), and at unit
  // size its areas neither overflow nor underflow (mesh/power_of_two_scale.h).
  return count_flips_in_safe_range(detail::scaled_into_safe_range(uv), uv_faces);
}

namespace {

struct BoundaryEdge {
  int from = 0;
  int to = 0;
};

// Undirected edges of uv_faces used by exactly one face, in increasing (min, max) order. Each edge
// is packed into one 64-bit key (min index high, max index low) so that sorting is a plain sort of
// integers.
std::vector<BoundaryEdge> uv_boundary_edges(const Eigen::MatrixX3i& uv_faces) {
  std::vector<std::uint64_t> keys;
  keys.reserve(static_cast<std::size_t>(uv_faces.rows()) * 3);
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) {
    for (int corner = 0; corner < 3; ++corner) {
      const auto a = static_cast<std::uint32_t>(uv_faces(f, corner));
      const auto b = static_cast<std::uint32_t>(uv_faces(f, (corner + 1) % 3));
      keys.push_back(static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b));
    }
  }
  std::sort(keys.begin(), keys.end());
  std::vector<BoundaryEdge> boundary;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    if (j - i == 1) {
      boundary.push_back(
          {static_cast<int>(keys[i] >> 32), static_cast<int>(keys[i] & 0xffffffffu)});
    }
    i = j;
  }
  return boundary;
}

// p lies on the closed segment [a, b], given that a, b, p are exactly collinear.
bool within_collinear_segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                              const Eigen::Vector2d& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

// The closed segments [p1, p2] and [q1, q2] have a point in common (crossing, touching or
// overlapping), decided with exact orientation signs.
bool segments_intersect(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                        const Eigen::Vector2d& q1, const Eigen::Vector2d& q2) {
  const int side_q1 = detail::orientation_sign(p1, p2, q1);
  const int side_q2 = detail::orientation_sign(p1, p2, q2);
  const int side_p1 = detail::orientation_sign(q1, q2, p1);
  const int side_p2 = detail::orientation_sign(q1, q2, p2);
  if (side_q1 * side_q2 < 0 && side_p1 * side_p2 < 0) return true;  // A proper crossing.
  // Otherwise they meet only if an endpoint of one lies on the other.
  return (side_q1 == 0 && within_collinear_segment(p1, p2, q1)) ||
         (side_q2 == 0 && within_collinear_segment(p1, p2, q2)) ||
         (side_p1 == 0 && within_collinear_segment(q1, q2, p1)) ||
         (side_p2 == 0 && within_collinear_segment(q1, q2, p2));
}

// A uniform grid over the bounding box of the boundary; each edge is entered in every cell that
// its bounding box covers (a conservative superset of the cells it passes through).
class EdgeGrid {
 public:
  // `padding`: how far beyond its bounding box each edge is entered (the clearance of a contact
  // search), so that edges nearer than that share a cell.
  EdgeGrid(const Eigen::MatrixX2d& uv, const std::vector<BoundaryEdge>& edges,
           const std::vector<int>& usable_edges, double padding = 0.0)
      : padding_(padding) {
    Eigen::Vector2d low = Eigen::Vector2d::Constant(INFINITY);
    Eigen::Vector2d high = Eigen::Vector2d::Constant(-INFINITY);
    for (const int e : usable_edges) {
      for (const int v : {edges[e].from, edges[e].to}) {
        low = low.cwiseMin(uv.row(v).transpose());
        high = high.cwiseMax(uv.row(v).transpose());
      }
    }
    low_ = low;
    // About one cell per edge, shaped like the bounding box.
    const Eigen::Vector2d extent = (high - low).cwiseMax(1e-300);
    const double cells = std::max<double>(1.0, static_cast<double>(usable_edges.size()));
    const double cell_size = std::sqrt(extent.x() * extent.y() / cells);
    for (int axis = 0; axis < 2; ++axis) {
      const double count = cell_size > 0.0 ? std::ceil(extent[axis] / cell_size) : 1.0;
      cells_[axis] = static_cast<int>(std::clamp(count, 1.0, 4096.0));
      scale_[axis] = cells_[axis] / extent[axis];
    }
    ranges_.resize(edges.size());
    // Two passes (count, then fill) give every cell its edges in increasing edge order.
    std::vector<int> counts(static_cast<std::size_t>(cells_[0]) * cells_[1] + 1, 0);
    for (const int e : usable_edges) {
      ranges_[e] = cell_range(uv.row(edges[e].from), uv.row(edges[e].to));
      for_each_cell(ranges_[e], [&](int cell) { ++counts[cell + 1]; });
    }
    for (std::size_t i = 1; i < counts.size(); ++i) counts[i] += counts[i - 1];
    cell_start_ = counts;
    cell_edges_.resize(static_cast<std::size_t>(counts.back()));
    for (const int e : usable_edges) {
      for_each_cell(ranges_[e], [&](int cell) { cell_edges_[counts[cell]++] = e; });
    }
  }

  struct CellRange {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  };

  [[nodiscard]] int cell_count() const { return cells_[0] * cells_[1]; }
  [[nodiscard]] const CellRange& range(int edge) const { return ranges_[edge]; }
  [[nodiscard]] int cell_x(int cell) const { return cell % cells_[0]; }
  [[nodiscard]] int cell_y(int cell) const { return cell / cells_[0]; }
  //! Edges entered in `cell`, as [begin, end) into cell_edges().
  [[nodiscard]] int begin(int cell) const { return cell_start_[cell]; }
  [[nodiscard]] int end(int cell) const { return cell_start_[cell + 1]; }
  [[nodiscard]] int edge_at(int slot) const { return cell_edges_[slot]; }

 private:
  // The mapping x -> floor((x - low) * scale) is monotone in floating point, so two segments whose
  // bounding boxes overlap get overlapping cell ranges.
  int cell_of(double value, int axis) const {
    const double cell = std::floor((value - low_[axis]) * scale_[axis]);
    return static_cast<int>(std::clamp(cell, 0.0, static_cast<double>(cells_[axis] - 1)));
  }

  CellRange cell_range(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
    return {cell_of(std::min(a.x(), b.x()) - padding_, 0), cell_of(std::min(a.y(), b.y()) - padding_, 1),
            cell_of(std::max(a.x(), b.x()) + padding_, 0), cell_of(std::max(a.y(), b.y()) + padding_, 1)};
  }

  template <typename Visit>
  void for_each_cell(const CellRange& range, Visit visit) const {
    for (int y = range.y0; y <= range.y1; ++y) {
      for (int x = range.x0; x <= range.x1; ++x) visit(y * cells_[0] + x);
    }
  }

  double padding_ = 0.0;
  Eigen::Vector2d low_;
  int cells_[2] = {1, 1};
  double scale_[2] = {1.0, 1.0};
  std::vector<CellRange> ranges_;
  std::vector<int> cell_start_;
  std::vector<int> cell_edges_;
};

// Calls visit(p, q) for each pair of non-adjacent edges among `edges` that share a point, found
// through the grid (cell by cell, each pair in the lowest cell both edges enter), until visit
// returns false.
// The distance between the closed segments [p1, p2] and [q1, q2] when they do not meet: the
// least of the distances from each endpoint to the other segment.
double segment_distance(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                        const Eigen::Vector2d& q1, const Eigen::Vector2d& q2) {
  const auto point_to_segment = [](const Eigen::Vector2d& x, const Eigen::Vector2d& a,
                                   const Eigen::Vector2d& b) {
    const Eigen::Vector2d along = b - a;
    const double length_squared = along.squaredNorm();
    const double t = length_squared > 0.0 ? std::clamp((x - a).dot(along) / length_squared, 0.0, 1.0) : 0.0;
    return (x - (a + t * along)).norm();
  };
  return std::min({point_to_segment(p1, q1, q2), point_to_segment(p2, q1, q2),
                   point_to_segment(q1, p1, p2), point_to_segment(q2, p1, p2)});
}

// Calls visit(p, q) for each pair of non-adjacent edges among `edges` that share a point or, with
// a positive `clearance`, come nearer than it, found through the grid (cell by cell, each pair in
// the lowest cell both edges enter), until visit returns false.
template <typename Visit>
void for_each_edge_crossing(const Eigen::MatrixX2d& uv, const std::vector<BoundaryEdge>& edges,
                            const Visit& visit, double clearance = 0.0) {
  // Edges with a non-finite endpoint cannot be placed; they are left out (count_flips reports
  // their triangles as degenerate).
  std::vector<int> usable_edges;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (uv.row(edges[e].from).allFinite() && uv.row(edges[e].to).allFinite()) {
      usable_edges.push_back(static_cast<int>(e));
    }
  }
  if (usable_edges.size() < 2) return;

  const EdgeGrid grid(uv, edges, usable_edges, clearance);
  for (int cell = 0; cell < grid.cell_count(); ++cell) {
    const int x = grid.cell_x(cell), y = grid.cell_y(cell);
    for (int i = grid.begin(cell); i < grid.end(cell); ++i) {
      const int first = grid.edge_at(i);
      const BoundaryEdge& p = edges[first];
      for (int j = i + 1; j < grid.end(cell); ++j) {
        const int second = grid.edge_at(j);
        const BoundaryEdge& q = edges[second];
        // A pair that shares several cells is examined only in the lowest cell they share.
        const auto& range_p = grid.range(first);
        const auto& range_q = grid.range(second);
        if (x != std::max(range_p.x0, range_q.x0) || y != std::max(range_p.y0, range_q.y0))
          continue;
        if (p.from == q.from || p.from == q.to || p.to == q.from || p.to == q.to) continue;
        const bool meet =
            segments_intersect(uv.row(p.from), uv.row(p.to), uv.row(q.from), uv.row(q.to)) ||
            (clearance > 0.0 &&
             segment_distance(uv.row(p.from), uv.row(p.to), uv.row(q.from), uv.row(q.to)) <= clearance);
        if (meet && !visit(p, q)) return;
      }
    }
  }
}

int count_edge_crossings(const Eigen::MatrixX2d& uv, const std::vector<BoundaryEdge>& edges) {
  int crossings = 0;
  for_each_edge_crossing(uv, edges, [&](const BoundaryEdge&, const BoundaryEdge&) {
    ++crossings;
    return true;
  });
  return crossings;
}

}  // namespace

int count_boundary_self_intersections(const Eigen::MatrixX2d& uv,
                                      const Eigen::MatrixX3i& uv_faces) {
  detail::check_uv_faces(uv, uv_faces, "count_boundary_self_intersections");
  // In the safe range (a power of two: the same crossings) the products of the tests cannot overflow.
  return count_edge_crossings(detail::scaled_into_safe_range(uv), uv_boundary_edges(uv_faces));
}

namespace detail {

int count_loop_self_intersections(const Eigen::MatrixX2d& uv, const std::vector<int>& loop) {
  std::vector<BoundaryEdge> edges;
  edges.reserve(loop.size());
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const int from = loop[k], to = loop[(k + 1) % loop.size()];
    if (from < 0 || from >= uv.rows())
      throw Error(Status::invalid_input, "count_loop_self_intersections: loop vertex " +
                                             std::to_string(from) + " is outside the " +
                                             std::to_string(uv.rows()) + " uv rows");
    edges.push_back({from, to});
  }
  return count_edge_crossings(scaled_into_safe_range(uv), edges);
}

std::optional<BoundaryCrossing> first_boundary_crossing(const Eigen::MatrixX2d& uv,
                                                        const Eigen::MatrixX3i& uv_faces) {
  return first_boundary_contact(uv, uv_faces, 0.0);
}

std::optional<BoundaryCrossing> first_boundary_contact(const Eigen::MatrixX2d& uv,
                                                       const Eigen::MatrixX3i& uv_faces,
                                                       double relative_clearance) {
  check_uv_faces(uv, uv_faces, "first_boundary_contact");
  const std::vector<BoundaryEdge> edges = uv_boundary_edges(uv_faces);
  const Eigen::MatrixX2d scaled = scaled_into_safe_range(uv);
  double clearance = 0.0;
  if (relative_clearance > 0.0 && !edges.empty()) {
    // Relative to the boundary's extent, and below a quarter of its shortest edge, so that two
    // edges joined by a short third one do not count as near each other for that reason alone.
    Eigen::AlignedBox2d box;
    double shortest = INFINITY;
    for (const BoundaryEdge& edge : edges) {
      if (!scaled.row(edge.from).allFinite() || !scaled.row(edge.to).allFinite()) continue;
      box.extend(scaled.row(edge.from).transpose());
      box.extend(scaled.row(edge.to).transpose());
      shortest = std::min(shortest, (scaled.row(edge.to) - scaled.row(edge.from)).norm());
    }
    if (!box.isEmpty()) clearance = std::min(relative_clearance * box.diagonal().norm(), 0.25 * shortest);
  }
  std::optional<BoundaryCrossing> found;
  for_each_edge_crossing(
      scaled, edges,
      [&](const BoundaryEdge& p, const BoundaryEdge& q) {
        found = BoundaryCrossing{{{p.from, p.to}}, {{q.from, q.to}}};
        return false;
      },
      clearance);
  return found;
}

}  // namespace detail

}  // namespace harmonia
