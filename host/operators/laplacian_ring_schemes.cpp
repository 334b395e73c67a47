// Ring-based weight schemes of thesis chapter 4 (linear precision 4.8, least squares 4.9, positive
// least squares after 4.61, Floater's shape-preserving weights 4.10). Each vertex's 1-ring is
// flattened by the exponential map (detail::flatten_ring) and the weights are computed on the planar
// ring with the centre at the origin. For numerical conditioning the ring is first scaled to unit
// mean radius; weights of second-order schemes scale back by 1 / radius^2.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "operators/one_ring.h"
#include "operators/ring_weights.h"

namespace harmonia::detail {
namespace {

double mean_radius(std::span<const Eigen::Vector2d> ring) {
  double total = 0.0;
  for (const Eigen::Vector2d& q : ring) total += q.norm();
  return ring.empty() ? 1.0 : total / static_cast<double>(ring.size());
}

// The ring as an n by 2 matrix, scaled to unit mean radius.
Eigen::MatrixX2d normalized_ring(std::span<const Eigen::Vector2d> ring, double radius) {
  Eigen::MatrixX2d points(static_cast<Eigen::Index>(ring.size()), 2);
  for (std::size_t k = 0; k < ring.size(); ++k)
    points.row(static_cast<Eigen::Index>(k)) = ring[k].transpose() / radius;
  return points;
}

// Angle at the origin from a to b, counter-clockwise, in [0, 2 pi).
double ccw_angle(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double angle = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  return angle < 0.0 ? angle + 2.0 * std::numbers::pi : angle;
}

// The small quadratic program of least_squares_positive_weights:
//   minimize |B w - c|^2 + delta |w|^2  subject to  A w = 0,  w >= floor,
// solved by the primal active-set method (Nocedal and Wright, algorithm 16.3): keep a feasible w,
// solve the equality-constrained problem with the active bounds held fixed, step until a bound
// blocks (add it) or, at a stationary point, release the bound with the most negative multiplier.
// The delta term makes the problem strictly convex, so its minimizer is unique (the second-order
// residuals alone are flat along n - 5 directions); among the weights that fit the second-order
// conditions equally well it prefers the smallest, like the least-norm solution of the
// unconstrained least squares scheme. It moves the optimum by O(delta) only.
Eigen::VectorXd positive_active_set(const Eigen::MatrixXd& second_order, const Eigen::Vector3d& target,
                                    const Eigen::MatrixXd& first_order, Eigen::VectorXd w, double floor) {
  const Eigen::Index n = w.size();
  constexpr double delta = 1e-8;  // relative to the O(1) entries of B^T B on a unit ring
  const Eigen::MatrixXd hessian =
      2.0 * (second_order.transpose() * second_order + delta * Eigen::MatrixXd::Identity(n, n));
  const Eigen::VectorXd linear = -2.0 * second_order.transpose() * target;
  std::vector<bool> active(static_cast<std::size_t>(n), false);

  const int max_iterations = 50 + 10 * static_cast<int>(n);
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    std::vector<Eigen::Index> free;
    for (Eigen::Index i = 0; i < n; ++i)
      if (!active[static_cast<std::size_t>(i)]) free.push_back(i);
    const auto free_count = static_cast<Eigen::Index>(free.size());
    const Eigen::VectorXd gradient = hessian * w + linear;

    // KKT system of the step p on the free variables: [H_FF A_F^T; A_F 0] [p; lambda] = [-g_F; 0].
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(free_count + 2, free_count + 2);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(free_count + 2);
    for (Eigen::Index a = 0; a < free_count; ++a) {
      for (Eigen::Index b = 0; b < free_count; ++b) kkt(a, b) = hessian(free[a], free[b]);
      kkt(a, free_count) = kkt(free_count, a) = first_order(0, free[a]);
      kkt(a, free_count + 1) = kkt(free_count + 1, a) = first_order(1, free[a]);
      rhs[a] = -gradient[free[a]];
    }
    const Eigen::VectorXd solution = kkt.completeOrthogonalDecomposition().solve(rhs);
    Eigen::VectorXd step = Eigen::VectorXd::Zero(n);
    for (Eigen::Index a = 0; a < free_count; ++a) step[free[a]] = solution[a];

    if (step.norm() <= 1e-14 * (1.0 + w.norm())) {
      // Stationary on this face: multipliers of the active bounds are (g + A^T lambda)_i.
      const Eigen::Vector2d lambda = solution.tail<2>();
      const Eigen::VectorXd multipliers = gradient + first_order.transpose() * lambda;
      Eigen::Index release = -1;
      double most_negative = -1e-12 * (1.0 + gradient.norm());
      for (Eigen::Index i = 0; i < n; ++i) {
        if (active[static_cast<std::size_t>(i)] && multipliers[i] < most_negative) {
          most_negative = multipliers[i];
          release = i;
        }
      }
      if (release < 0) break;  // KKT conditions hold: optimal
      active[static_cast<std::size_t>(release)] = false;
      continue;
    }

    // Longest step in [0, 1] that keeps every free weight above the floor.
    double length = 1.0;
    Eigen::Index blocking = -1;
    for (const Eigen::Index i : free) {
      if (step[i] < 0.0) {
        const double limit = (floor - w[i]) / step[i];
        if (limit < length) {
          length = std::max(limit, 0.0);
          blocking = i;
        }
      }
    }
    w += length * step;
    if (blocking >= 0) {
      w[blocking] = floor;
      active[static_cast<std::size_t>(blocking)] = true;
    }
  }
  return w;
}

// Floater's barycentric coordinates of the origin in triangle (a, b, c), or empty if the origin is
// outside it (a tolerance of a few ulps lets an origin exactly on an edge count as inside).
std::optional<Eigen::Vector3d> barycentric_of_origin(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                                     const Eigen::Vector2d& c) {
  const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
    return u.x() * v.y() - u.y() * v.x();
  };
  const double twice_area = cross(b - a, c - a);
  if (twice_area == 0.0) return std::nullopt;
  // Sub-triangle areas opposite each corner, with the origin as the apex.
  const Eigen::Vector3d coordinates =
      Eigen::Vector3d(cross(b, c), cross(c, a), cross(a, b)) / twice_area;
  const double tolerance = 1e-14;
  if (coordinates.minCoeff() < -tolerance) return std::nullopt;
  return coordinates;
}

}  // namespace

Eigen::VectorXd planar_mean_value_weights(std::span<const Eigen::Vector2d> ring, bool closed) {
  const std::size_t count = ring.size();
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(count));
  const std::size_t wedges = closed ? count : (count == 0 ? 0 : count - 1);
  for (std::size_t k = 0; k < wedges; ++k) {
    const std::size_t next = (k + 1) % count;
    const double angle = ccw_angle(ring[k], ring[next]);
    const double tan_half = std::tan(angle / 2.0);
    weights[static_cast<Eigen::Index>(k)] += tan_half / ring[k].norm();
    weights[static_cast<Eigen::Index>(next)] += tan_half / ring[next].norm();
  }
  return weights;
}

Eigen::VectorXd linear_precision_weights(std::span<const Eigen::Vector2d> ring) {
  const double radius = mean_radius(ring);
  const Eigen::MatrixX2d points = normalized_ring(ring, radius);
  // Lagrange conditions of (4.44-4.46): w = 1 + X mu with (X^T X) mu = -X^T 1, i.e. (4.47) with the
  // moments I_xx, I_yy, I_xy (4.48-4.50) in X^T X and R_x, R_y (4.51-4.52) in X^T 1.
  const Eigen::Matrix2d moments = points.transpose() * points;
  const Eigen::Vector2d first_moments = points.colwise().sum().transpose();
  const Eigen::Vector2d mu = moments.completeOrthogonalDecomposition().solve(-first_moments);
  return Eigen::VectorXd::Ones(points.rows()) + points * mu;  // dimensionless: invariant to scale
}

Eigen::VectorXd least_squares_weights(std::span<const Eigen::Vector2d> ring) {
  const double radius = mean_radius(ring);
  const Eigen::MatrixX2d points = normalized_ring(ring, radius);
  const Eigen::Index n = points.rows();
  // Rows: sum w x = 0 (4.56), sum w y = 0 (4.57), sum w x^2 = 2 (4.58), sum w y^2 = 2 (4.59),
  // sum w x y = 0 (4.60).
  Eigen::Matrix<double, 5, Eigen::Dynamic> conditions(5, n);
  conditions.row(0) = points.col(0).transpose();
  conditions.row(1) = points.col(1).transpose();
  conditions.row(2) = points.col(0).array().square().matrix().transpose();
  conditions.row(3) = points.col(1).array().square().matrix().transpose();
  conditions.row(4) = (points.col(0).array() * points.col(1).array()).matrix().transpose();
  Eigen::Matrix<double, 5, 1> target;
  target << 0.0, 0.0, 2.0, 2.0, 0.0;
  // With full row rank (valence >= 5, non-degenerate ring) the minimum-norm solution is
  // A^T (A A^T)^-1 b, a 5 by 5 solve; its residual tells whether that shortcut was well conditioned.
  if (n >= 5) {
    const Eigen::Matrix<double, 5, 5> gram = conditions * conditions.transpose();
    const Eigen::LLT<Eigen::Matrix<double, 5, 5>> cholesky(gram);
    if (cholesky.info() == Eigen::Success) {
      const Eigen::VectorXd weights = conditions.transpose() * cholesky.solve(target);
      if ((conditions * weights - target).norm() <= 1e-10 * target.norm())
        return weights / (radius * radius);
    }
  }
  const Eigen::VectorXd weights = Eigen::MatrixXd(conditions).completeOrthogonalDecomposition().solve(target);
  return weights / (radius * radius);
}

bool origin_strictly_inside(std::span<const Eigen::Vector2d> ring) {
  if (ring.size() < 3) return false;
  for (std::size_t k = 0; k < ring.size(); ++k) {
    if (ring[k].squaredNorm() == 0.0) return false;
    const double gap = ccw_angle(ring[k], ring[(k + 1) % ring.size()]);
    if (!(gap > 0.0 && gap < std::numbers::pi)) return false;
  }
  // The gaps must also add up to one turn (not wind around twice).
  double total = 0.0;
  for (std::size_t k = 0; k < ring.size(); ++k) total += ccw_angle(ring[k], ring[(k + 1) % ring.size()]);
  return std::abs(total - 2.0 * std::numbers::pi) < 1e-9;
}

std::optional<Eigen::VectorXd> least_squares_positive_weights(std::span<const Eigen::Vector2d> ring) {
  if (!origin_strictly_inside(ring)) return std::nullopt;
  const double radius = mean_radius(ring);
  const Eigen::MatrixX2d points = normalized_ring(ring, radius);
  const Eigen::Index n = points.rows();
  Eigen::MatrixXd first_order(2, n);
  first_order.row(0) = points.col(0).transpose();
  first_order.row(1) = points.col(1).transpose();
  Eigen::MatrixXd second_order(3, n);
  second_order.row(0) = points.col(0).array().square().matrix().transpose();
  second_order.row(1) = points.col(1).array().square().matrix().transpose();
  second_order.row(2) = (points.col(0).array() * points.col(1).array()).matrix().transpose();
  const Eigen::Vector3d target(2.0, 2.0, 0.0);

  // The floor keeps the weights strictly positive; it is far below the typical weight 4/n of a unit
  // ring (4.19), so it only matters where the bound is active.
  const double floor = 1e-8 * 4.0 / static_cast<double>(n);

  // Where the least squares weights are already positive they satisfy all five conditions (valence
  // >= 5) or minimize their residual, so they solve the program exactly: keep them.
  const Eigen::VectorXd unconstrained = least_squares_weights(ring) * (radius * radius);
  if (n >= 5 && unconstrained.minCoeff() >= floor &&
      (first_order * unconstrained).norm() <= 1e-12 * unconstrained.norm()) {
    return unconstrained / (radius * radius);
  }

  // Feasible start: mean value weights satisfy the first-order conditions on a closed planar ring
  // and are positive; scale them to fit the second-order conditions as well as a multiple can.
  std::vector<Eigen::Vector2d> unit_ring(ring.size());
  for (std::size_t k = 0; k < ring.size(); ++k) unit_ring[k] = points.row(static_cast<Eigen::Index>(k));
  const Eigen::VectorXd mean_value = planar_mean_value_weights(unit_ring, true);
  const Eigen::Vector3d fitted = second_order * mean_value;
  double scale = fitted.dot(target) / fitted.squaredNorm();
  scale = std::max(scale, 2.0 * floor / mean_value.minCoeff());
  const Eigen::VectorXd weights =
      positive_active_set(second_order, target, first_order, scale * mean_value, floor);
  return weights / (radius * radius);
}

std::optional<Eigen::VectorXd> shape_preserving_weights(std::span<const Eigen::Vector2d> ring) {
  const std::size_t count = ring.size();
  if (!origin_strictly_inside(ring)) return std::nullopt;
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(count));
  for (std::size_t k = 0; k < count; ++k) {
    // The edge (q_l, q_{l+1}) of the ring polygon that the ray from q_k through the origin leaves
    // by: its triangle with q_k contains the origin. Search from the neighbour after k onwards.
    bool found = false;
    for (std::size_t step = 1; step + 1 < count && !found; ++step) {
      const std::size_t l = (k + step) % count, next = (l + 1) % count;
      const auto coordinates = barycentric_of_origin(ring[k], ring[l], ring[next]);
      if (!coordinates) continue;
      weights[static_cast<Eigen::Index>(k)] += (*coordinates)[0];
      weights[static_cast<Eigen::Index>(l)] += (*coordinates)[1];
      weights[static_cast<Eigen::Index>(next)] += (*coordinates)[2];
      found = true;
    }
    if (!found) return std::nullopt;
  }
  return weights / static_cast<double>(count);
}

std::vector<bool> assemble_ring_scheme(const Mesh& mesh, WeightScheme scheme, AdjacencyPattern& pattern) {
  const VertexFans fans(mesh.faces, mesh.vertex_count());
  std::vector<bool> mean_value_rows(static_cast<std::size_t>(mesh.vertex_count()), false);
  for (int vertex = 0; vertex < mesh.vertex_count(); ++vertex) {
    const FanKind kind = fans.kind(vertex);
    if (kind == FanKind::isolated) continue;
    if (kind == FanKind::irregular) {
      mean_value_rows[static_cast<std::size_t>(vertex)] = true;
      continue;
    }
    const bool closed = kind == FanKind::interior;
    const std::span<const int> neighbours = fans.neighbours(vertex);
    const std::vector<Eigen::Vector2d> ring = flatten_ring(mesh.vertices, vertex, neighbours, closed);

    // Boundary vertices: linear precision and least squares are well defined on the open fan and
    // keep their meaning (linear precision along a straight planar boundary); the positive schemes
    // need the centre strictly inside the ring, which a boundary vertex is not, so their boundary
    // rows are mean value rows. Fixed-boundary maps replace boundary rows anyway.
    std::optional<Eigen::VectorXd> weights;
    switch (scheme) {
      case WeightScheme::linear_precision: weights = linear_precision_weights(ring); break;
      case WeightScheme::least_squares: weights = least_squares_weights(ring); break;
      case WeightScheme::least_squares_positive:
        if (closed) weights = least_squares_positive_weights(ring);
        break;
      case WeightScheme::shape_preserving:
        if (closed) weights = shape_preserving_weights(ring);
        break;
      case WeightScheme::uniform:
      case WeightScheme::chord_length:
      case WeightScheme::mean_value:
      case WeightScheme::cotangent: break;  // not ring schemes: never dispatched here
    }
    if (!weights || !weights->allFinite()) {
      mean_value_rows[static_cast<std::size_t>(vertex)] = true;
      continue;
    }
    for (std::size_t k = 0; k < neighbours.size(); ++k)
      pattern.add(vertex, neighbours[k], -(*weights)[static_cast<Eigen::Index>(k)]);
  }
  return mean_value_rows;
}

}  // namespace harmonia::detail
