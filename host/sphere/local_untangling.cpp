// Untangling turned triangles of a spherical map vertex by vertex (local_untangling.h).

#include "sphere/local_untangling.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include <Eigen/Dense>

#include "sphere/sphere_orientation.h"
#include "sphere/tangential_relaxation.h"

namespace harmonia::detail {
namespace {

int orientation(const Eigen::MatrixX3d& points, const Eigen::MatrixX3i& faces, Eigen::Index f) {
  return sphere_orientation_sign(points.row(faces(f, 0)).transpose(),
                                 points.row(faces(f, 1)).transpose(),
                                 points.row(faces(f, 2)).transpose());
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// The part of the convex polygon left of the directed line from -> to (Sutherland-Hodgman).
std::vector<Eigen::Vector2d> clip_left_of(const std::vector<Eigen::Vector2d>& polygon,
                                          const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  std::vector<Eigen::Vector2d> clipped;
  const Eigen::Vector2d direction = to - from;
  const auto side = [&](const Eigen::Vector2d& p) { return cross(direction, p - from); };
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector2d& current = polygon[k];
    const Eigen::Vector2d& next = polygon[(k + 1) % polygon.size()];
    const double current_side = side(current), next_side = side(next);
    if (current_side > 0.0) clipped.push_back(current);
    if ((current_side > 0.0) != (next_side > 0.0)) {
      const double t = current_side / (current_side - next_side);
      clipped.push_back(current + t * (next - current));
    }
  }
  return clipped;
}

// Area centroid of a convex polygon (its vertices' mean when the area vanishes).
Eigen::Vector2d polygon_centroid(const std::vector<Eigen::Vector2d>& polygon, double& area) {
  area = 0.0;
  Eigen::Vector2d weighted = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector2d& a = polygon[k];
    const Eigen::Vector2d& b = polygon[(k + 1) % polygon.size()];
    const double twice = cross(a, b);
    area += 0.5 * twice;
    weighted += twice * (a + b) / 6.0;
  }
  if (area > 0.0) return weighted / area;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : polygon) mean += p;
  return polygon.empty() ? mean : Eigen::Vector2d(mean / static_cast<double>(polygon.size()));
}

// Signed distance of x from the line a -> b, positive on its left.
double distance_left_of(const std::array<Eigen::Vector2d, 2>& edge, const Eigen::Vector2d& x) {
  const Eigen::Vector2d direction = edge[1] - edge[0];
  return cross(direction, x - edge[0]) / direction.norm();
}

double worst_distance(const std::vector<std::array<Eigen::Vector2d, 2>>& edges,
                      const Eigen::Vector2d& x) {
  double worst = std::numeric_limits<double>::infinity();
  for (const auto& edge : edges) worst = std::min(worst, distance_left_of(edge, x));
  return worst;
}

// The point of the box |x|, |y| <= bound that maximizes the smallest distance left of the edges:
// a linear program in (x, y, t) with three variables, solved by trying every vertex (three active
// constraints) of its feasible set; the rings are small.
Eigen::Vector2d least_violating_point(const std::vector<std::array<Eigen::Vector2d, 2>>& edges,
                                      double bound) {
  // Constraints n . x + c >= t with |n| = 1.
  std::vector<Eigen::Vector2d> normal;
  std::vector<double> offset;
  for (const auto& edge : edges) {
    const Eigen::Vector2d direction = (edge[1] - edge[0]).normalized();
    normal.emplace_back(-direction.y(), direction.x());
    offset.push_back(-normal.back().dot(edge[0]));
  }
  for (const Eigen::Vector2d& side : {Eigen::Vector2d(1, 0), Eigen::Vector2d(-1, 0),
                                      Eigen::Vector2d(0, 1), Eigen::Vector2d(0, -1)}) {
    normal.push_back(side);
    offset.push_back(bound);
  }
  const std::size_t count = normal.size();
  Eigen::Vector2d best = Eigen::Vector2d::Zero();
  double best_margin = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < count; ++i)
    for (std::size_t j = i + 1; j < count; ++j)
      for (std::size_t k = j + 1; k < count; ++k) {
        Eigen::Matrix3d system;
        Eigen::Vector3d right;
        std::size_t row = 0;
        for (const std::size_t m : {i, j, k}) {
          system.row(static_cast<Eigen::Index>(row)) << normal[m].x(), normal[m].y(), -1.0;
          right[static_cast<Eigen::Index>(row)] = -offset[m];
          ++row;
        }
        const Eigen::FullPivLU<Eigen::Matrix3d> solver(system);
        if (!solver.isInvertible()) continue;
        const Eigen::Vector3d solution = solver.solve(right);
        const Eigen::Vector2d x = solution.head<2>();
        const double margin = solution[2];
        if (!std::isfinite(margin) || margin <= best_margin) continue;
        bool feasible = true;
        for (std::size_t m = 0; m < count && feasible; ++m)
          feasible = normal[m].dot(x) + offset[m] >= margin - 1e-12 * bound;
        if (!feasible) continue;
        best = x;
        best_margin = margin;
      }
  return best;
}

// Moves v into the kernel of its ring (see the file comment); false when the kernel is empty or
// the move would not leave every triangle around v facing outward.
bool move_into_kernel(const Eigen::MatrixX3i& faces, const std::vector<int>& around, int v,
                      Eigen::MatrixX3d& points) {
  const Eigen::Vector3d centre = points.row(v).transpose();
  const Eigen::Vector3d first_axis = centre.unitOrthogonal();
  const Eigen::Vector3d second_axis = centre.cross(first_axis);
  // The ring's edges a -> b, as each triangle (v, a, b) runs them, in the gnomonic chart at v.
  std::vector<std::array<Eigen::Vector2d, 2>> edges;
  double extent = 0.0;
  constexpr double kSmallestCosine = 0.1;  // the ring well inside v's hemisphere
  for (const int f : around) {
    int corner = 0;
    while (faces(f, corner) != v) ++corner;
    std::array<Eigen::Vector2d, 2> edge;
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d p = points.row(faces(f, (corner + 1 + k) % 3)).transpose();
      const double cosine = p.dot(centre);
      if (cosine < kSmallestCosine) return false;
      const Eigen::Vector3d projected = p / cosine;
      edge[static_cast<std::size_t>(k)] = Eigen::Vector2d(projected.dot(first_axis), projected.dot(second_axis));
      extent = std::max(extent, edge[static_cast<std::size_t>(k)].cwiseAbs().maxCoeff());
    }
    edges.push_back(edge);
  }
  if (!(extent > 0.0)) return false;
  std::vector<Eigen::Vector2d> kernel{{-2.0 * extent, -2.0 * extent}, {2.0 * extent, -2.0 * extent},
                                      {2.0 * extent, 2.0 * extent}, {-2.0 * extent, 2.0 * extent}};
  for (const auto& edge : edges) {
    kernel = clip_left_of(kernel, edge[0], edge[1]);
    if (kernel.size() < 3) break;
  }
  double area = 0.0;
  const Eigen::Vector2d centroid = kernel.size() >= 3 ? polygon_centroid(kernel, area)
                                                      : Eigen::Vector2d::Zero();
  // An empty kernel: the point farthest inside the worst of v's triangles, if that is better than
  // where v is (it is at the chart's origin), so that the neighbours can finish the work.
  const bool inside_kernel = area > 0.0;
  const Eigen::Vector2d target =
      inside_kernel ? centroid : least_violating_point(edges, 2.0 * extent);
  if (!inside_kernel && !(worst_distance(edges, target) > worst_distance(edges, Eigen::Vector2d::Zero())))
    return false;
  const auto turned_around = [&] {
    int count = 0;
    for (const int f : around) count += orientation(points, faces, f) <= 0 ? 1 : 0;
    return count;
  };
  const int turned_before = turned_around();
  const Eigen::Vector3d before = centre;
  points.row(v) = (centre + target.x() * first_axis + target.y() * second_axis).normalized().transpose();
  // Inside the kernel every triangle must face outward now (the exact test has the last word); the
  // least violating point may leave some turned, but not more than before.
  const int turned_after = turned_around();
  if (inside_kernel ? turned_after > 0 : turned_after > turned_before) {
    points.row(v) = before.transpose();
    return false;
  }
  return true;
}

// The farthest ring around the turned triangles whose vertices are moved to make room.
constexpr int kMostRings = 8;

}  // namespace

UntanglingOutcome untangle_on_sphere(const Mesh& mesh, int max_passes, Eigen::MatrixX3d& points) {
  UntanglingOutcome outcome;
  const auto vertex_count = static_cast<int>(points.rows());
  const Eigen::MatrixX3i& faces = mesh.faces;
  std::vector<std::vector<int>> around(static_cast<std::size_t>(vertex_count));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) around[static_cast<std::size_t>(faces(f, k))].push_back(static_cast<int>(f));
  const auto turned_vertices = [&] {
    std::vector<int> vertices;
    for (Eigen::Index f = 0; f < faces.rows(); ++f)
      if (orientation(points, faces, f) <= 0)
        for (int k = 0; k < 3; ++k) vertices.push_back(faces(f, k));
    return vertices;
  };
  const auto turned_count = [&] {
    int count = 0;
    for (Eigen::Index f = 0; f < faces.rows(); ++f) count += orientation(points, faces, f) <= 0 ? 1 : 0;
    return count;
  };
  outcome.turned_before = turned_count();
  if (outcome.turned_before == 0) return outcome;
  const Eigen::MatrixX3d input = points;
  // Visit in the order of the 3D positions, so that the result does not depend on the numbering.
  const auto before_in_space = [&](int a, int b) {
    for (int axis = 0; axis < 3; ++axis)
      if (mesh.vertices(a, axis) != mesh.vertices(b, axis))
        return mesh.vertices(a, axis) < mesh.vertices(b, axis);
    return a < b;
  };
  std::vector<char> moved(static_cast<std::size_t>(vertex_count), 0);
  int rings = 0;  // how far around the turned triangles vertices are moved
  for (int pass = 0; pass < max_passes; ++pass) {
    std::vector<int> seeds = turned_vertices();
    if (seeds.empty()) break;
    outcome.passes = pass + 1;
    const std::vector<char> near = vertices_within_rings(faces, vertex_count, seeds, rings);
    std::vector<int> candidates;
    for (int v = 0; v < vertex_count; ++v)
      if (near[static_cast<std::size_t>(v)]) candidates.push_back(v);
    std::sort(candidates.begin(), candidates.end(), before_in_space);
    const int turned_at_start = turned_count();
    for (const int v : candidates)
      if (move_into_kernel(faces, around[static_cast<std::size_t>(v)], v, points))
        moved[static_cast<std::size_t>(v)] = 1;
    // No progress: reach further out next time (a vertex whose kernel is empty can get one when
    // its neighbours make room).
    if (turned_count() >= turned_at_start) {
      if (++rings > kMostRings) break;
    }
  }
  outcome.turned_after = turned_count();
  // Never worse than the input.
  if (outcome.turned_after > outcome.turned_before) {
    points = input;
    outcome.turned_after = outcome.turned_before;
    std::fill(moved.begin(), moved.end(), 0);
  }
  outcome.moved_vertices = static_cast<int>(std::count(moved.begin(), moved.end(), 1));
  return outcome;
}

}  // namespace harmonia::detail
