// Tests of the one-ring machinery (ordered fans, exponential-map flattening) and of the ring-based
// weight schemes of thesis chapter 4 on single planar rings: the five Taylor conditions of least
// squares (4.56-4.60), the positive program after (4.61), Holmes-Connell (4.47), Floater's
// shape-preserving weights.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "operators/one_ring.h"
#include "operators/ring_weights.h"

namespace harmonia {
namespace {

using detail::FanKind;

// A star-shaped planar ring: n neighbours at jittered angles and radii around the origin.
std::vector<Eigen::Vector2d> jittered_ring(int n, double angle_jitter, double radius_jitter, unsigned seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Eigen::Vector2d> ring;
  for (int k = 0; k < n; ++k) {
    const double angle = 2.0 * std::numbers::pi * (k + angle_jitter * 0.45 * unit(generator)) / n;
    const double radius = 1.0 + radius_jitter * unit(generator);
    ring.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
  }
  return ring;
}

std::vector<Eigen::Vector2d> regular_ring(int n, double radius) {
  std::vector<Eigen::Vector2d> ring;
  for (int k = 0; k < n; ++k)
    ring.emplace_back(radius * std::cos(2.0 * std::numbers::pi * k / n), radius * std::sin(2.0 * std::numbers::pi * k / n));
  return ring;
}

// The five Taylor conditions (4.56-4.60) as residuals: (sum w x, sum w y, sum w x^2 - 2,
// sum w y^2 - 2, sum w x y).
Eigen::VectorXd taylor_residuals(const std::vector<Eigen::Vector2d>& ring, const Eigen::VectorXd& w) {
  Eigen::VectorXd residual = Eigen::VectorXd::Zero(5);
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const double x = ring[k].x(), y = ring[k].y(), wk = w[static_cast<Eigen::Index>(k)];
    residual += wk * Eigen::VectorXd((Eigen::VectorXd(5) << x, y, x * x, y * y, x * y).finished());
  }
  residual[2] -= 2.0;
  residual[3] -= 2.0;
  return residual;
}

double second_order_objective(const std::vector<Eigen::Vector2d>& ring, const Eigen::VectorXd& w) {
  return taylor_residuals(ring, w).tail<3>().squaredNorm();
}

TEST(VertexFans, OrderedCounterClockwiseWithBoundaryAndInteriorKinds) {
  const Mesh disk = planar_disk(3);
  const detail::VertexFans fans(disk.faces, disk.vertex_count());
  int interior = 0, boundary = 0;
  for (int v = 0; v < disk.vertex_count(); ++v) {
    const auto neighbours = fans.neighbours(v);
    const bool closed = fans.kind(v) == FanKind::interior;
    ASSERT_TRUE(closed || fans.kind(v) == FanKind::boundary);
    (closed ? interior : boundary)++;
    // Consecutive neighbours (a, b) must form the counter-clockwise face (v, a, b).
    const std::size_t pairs = closed ? neighbours.size() : neighbours.size() - 1;
    for (std::size_t k = 0; k < pairs; ++k) {
      const int a = neighbours[k], b = neighbours[(k + 1) % neighbours.size()];
      bool found = false;
      for (int f = 0; f < disk.face_count(); ++f)
        for (int c = 0; c < 3; ++c)
          if (disk.faces(f, c) == v && disk.faces(f, (c + 1) % 3) == a && disk.faces(f, (c + 2) % 3) == b) found = true;
      EXPECT_TRUE(found) << "vertex " << v << " pair " << a << "," << b;
    }
  }
  EXPECT_EQ(interior, 1 + 6 + 12);  // rings 0..2
  EXPECT_EQ(boundary, 18);          // ring 3
  EXPECT_EQ(fans.neighbours(0).size(), 6u);
}

TEST(VertexFans, BowtieAndUnusedVerticesAreRecognized) {
  // Two triangles sharing only vertex 0: its faces form two separate fans.
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 0, 3, 4;
  const detail::VertexFans fans(faces, 6);
  EXPECT_EQ(fans.kind(0), FanKind::irregular);
  EXPECT_EQ(fans.kind(1), FanKind::boundary);
  EXPECT_EQ(fans.kind(5), FanKind::isolated);
  EXPECT_TRUE(fans.neighbours(0).empty());

  // The ring schemes still give a finite operator with zero row sums (mean value rows there).
  Mesh bowtie;
  bowtie.faces = faces;
  bowtie.vertices.resize(6, 3);
  bowtie.vertices << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, -1, 0, 0, -0.5, -1, 0, 5, 5, 5;
  for (const WeightScheme scheme : {WeightScheme::least_squares_positive, WeightScheme::shape_preserving,
                                    WeightScheme::least_squares, WeightScheme::linear_precision}) {
    const Eigen::MatrixXd L(laplacian(bowtie, scheme));
    EXPECT_TRUE(L.allFinite()) << to_string(scheme);
    EXPECT_LT((L * Eigen::VectorXd::Ones(6)).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_GT(-L(0, 1), 0.0) << to_string(scheme);
    EXPECT_EQ(L.row(5).cwiseAbs().sum(), 0.0);  // an unused vertex has an empty row
  }
}

TEST(FlattenRing, PlanarRingIsKeptAndConeIsOpenedToAFullTurn) {
  const Mesh disk = planar_disk(3, 1.0);
  const detail::VertexFans fans(disk.faces, disk.vertex_count());
  for (const int v : {0, 3, 10}) {
    const auto neighbours = fans.neighbours(v);
    const auto ring = detail::flatten_ring(disk.vertices, v, neighbours, true);
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const std::size_t next = (k + 1) % ring.size();
      const double planar = (disk.vertices.row(neighbours[k]) - disk.vertices.row(neighbours[next])).norm();
      EXPECT_NEAR((ring[k] - ring[next]).norm(), planar, 1e-12);  // a rigid copy of the ring
      EXPECT_NEAR(ring[k].norm(), (disk.vertices.row(neighbours[k]) - disk.vertices.row(v)).norm(), 1e-14);
    }
  }
  // The pole of a hemisphere is a cone point (angles sum below 2 pi): scaled to a full turn.
  const Mesh cap = hemisphere(3);
  const detail::VertexFans cap_fans(cap.faces, cap.vertex_count());
  const auto pole_ring = detail::flatten_ring(cap.vertices, 0, cap_fans.neighbours(0), true);
  double total = 0.0;
  for (std::size_t k = 0; k < pole_ring.size(); ++k) {
    const Eigen::Vector2d a = pole_ring[k], b = pole_ring[(k + 1) % pole_ring.size()];
    total += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  }
  EXPECT_NEAR(total, 2.0 * std::numbers::pi, 1e-12);
  // A boundary vertex's open fan keeps its 3D angles: straight boundary of a disk -> about pi.
  const int boundary_vertex = cap.vertex_count() - 1;
  const auto open = detail::flatten_ring(cap.vertices, boundary_vertex, cap_fans.neighbours(boundary_vertex), false);
  const double opening = std::atan2(open.front().x() * open.back().y() - open.front().y() * open.back().x(),
                                    open.front().dot(open.back()));
  double angle_sum = 0.0;
  const auto neighbours = cap_fans.neighbours(boundary_vertex);
  const Eigen::Vector3d centre = cap.vertices.row(boundary_vertex);
  for (std::size_t k = 0; k + 1 < neighbours.size(); ++k)
    angle_sum += detail::angle_between(cap.vertices.row(neighbours[k]).transpose() - centre,
                                       cap.vertices.row(neighbours[k + 1]).transpose() - centre);
  EXPECT_NEAR(std::abs(opening), angle_sum, 1e-12);
  EXPECT_LT(angle_sum, std::numbers::pi);
}

TEST(LeastSquaresWeights, FiveConditionsHoldExactlyFromValenceSix) {
  for (int n = 6; n <= 11; ++n) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      const auto ring = jittered_ring(n, 1.0, 0.4, seed * 31 + static_cast<unsigned>(n));
      const Eigen::VectorXd w = detail::least_squares_weights(ring);
      EXPECT_LT(taylor_residuals(ring, w).cwiseAbs().maxCoeff(), 1e-11) << "valence " << n;
    }
  }
  // Valence 5: the square system has the unique solution.
  const auto five = jittered_ring(5, 0.5, 0.3, 7);
  EXPECT_LT(taylor_residuals(five, detail::least_squares_weights(five)).cwiseAbs().maxCoeff(), 1e-10);
  // Regular ring of radius h: the finite-difference weights 4 / (n h^2) of (4.19).
  const Eigen::VectorXd regular = detail::least_squares_weights(regular_ring(8, 0.5));
  for (Eigen::Index k = 0; k < regular.size(); ++k) EXPECT_NEAR(regular[k], 4.0 / (8 * 0.25), 1e-12);
  // Valence 4: cannot satisfy all five, but the result is finite and minimizes the residual.
  const auto four = jittered_ring(4, 0.5, 0.3, 3);
  const Eigen::VectorXd w4 = detail::least_squares_weights(four);
  EXPECT_TRUE(w4.allFinite());
  EXPECT_GT(taylor_residuals(four, w4).norm(), 1e-6);
}

TEST(LeastSquaresPositiveWeights, PositiveFirstOrderExactAndOptimal) {
  int rings_with_negative_least_squares = 0;
  for (int n = 4; n <= 10; ++n) {
    for (unsigned seed = 1; seed <= 6; ++seed) {
      const auto ring = jittered_ring(n, 1.0, 0.6, seed * 17 + static_cast<unsigned>(n));
      if (!detail::origin_strictly_inside(ring)) continue;
      const auto positive = detail::least_squares_positive_weights(ring);
      ASSERT_TRUE(positive.has_value());
      const Eigen::VectorXd& w = *positive;
      EXPECT_GT(w.minCoeff(), 0.0);
      const Eigen::VectorXd residual = taylor_residuals(ring, w);
      EXPECT_LT(std::abs(residual[0]) + std::abs(residual[1]), 1e-12 * w.cwiseAbs().sum());
      if (detail::least_squares_weights(ring).minCoeff() < 0.0) ++rings_with_negative_least_squares;

      // Optimality: no feasible perturbation (first-order conditions kept, weights positive) does
      // noticeably better on the second-order residuals.
      Eigen::MatrixXd first_order(2, n);
      for (int k = 0; k < n; ++k) first_order.col(k) = ring[static_cast<std::size_t>(k)];
      const Eigen::MatrixXd null_space = first_order.fullPivLu().kernel();
      std::mt19937 generator(seed);
      std::normal_distribution<double> normal;
      const double best = second_order_objective(ring, w);
      for (int trial = 0; trial < 200; ++trial) {
        Eigen::VectorXd direction(null_space.cols());
        for (Eigen::Index c = 0; c < direction.size(); ++c) direction[c] = normal(generator);
        const Eigen::VectorXd candidate = w + 0.05 * w.norm() * (null_space * direction) / direction.norm();
        if (candidate.minCoeff() <= 0.0) continue;
        EXPECT_GE(second_order_objective(ring, candidate), best - 1e-7 * (1.0 + best));
      }
    }
  }
  EXPECT_GT(rings_with_negative_least_squares, 0);  // the positive program was really needed somewhere

  // On a regular ring the unconstrained optimum is positive: both schemes agree.
  const auto regular = regular_ring(7, 2.0);
  const Eigen::VectorXd positive = *detail::least_squares_positive_weights(regular);
  const Eigen::VectorXd plain = detail::least_squares_weights(regular);
  EXPECT_LT((positive - plain).cwiseAbs().maxCoeff(), 1e-12 * plain.cwiseAbs().maxCoeff());

  // A half-open fan (all neighbours in a half plane): no positive solution exists.
  std::vector<Eigen::Vector2d> half = {{1, 0}, {0.5, 0.5}, {0, 1}, {-0.5, 0.4}};
  EXPECT_FALSE(detail::origin_strictly_inside(half));
  EXPECT_FALSE(detail::least_squares_positive_weights(half).has_value());
}

TEST(LinearPrecisionWeights, FirstOrderConditionsAndUnitWeightsOnRegularRings) {
  for (int n = 3; n <= 9; ++n) {
    const auto ring = jittered_ring(n, 1.0, 0.5, static_cast<unsigned>(n));
    const Eigen::VectorXd w = detail::linear_precision_weights(ring);
    const Eigen::VectorXd residual = taylor_residuals(ring, w);
    EXPECT_LT(std::abs(residual[0]) + std::abs(residual[1]), 1e-12) << n;
    // Among weights with linear precision, these are closest to 1 (4.44): any null-space move is worse.
    Eigen::MatrixXd first_order(2, n);
    for (int k = 0; k < n; ++k) first_order.col(k) = ring[static_cast<std::size_t>(k)];
    const Eigen::MatrixXd null_space = first_order.fullPivLu().kernel();
    const Eigen::VectorXd perturbation = w - Eigen::VectorXd::Ones(n);
    EXPECT_LT((null_space.transpose() * perturbation).norm(), 1e-12) << n;
  }
  const Eigen::VectorXd regular = detail::linear_precision_weights(regular_ring(6, 3.0));
  EXPECT_LT((regular - Eigen::VectorXd::Ones(6)).cwiseAbs().maxCoeff(), 1e-14);
  // A collinear ring has a singular moment matrix: the pseudo-inverse keeps it finite.
  const std::vector<Eigen::Vector2d> collinear = {{1, 0}, {2, 0}, {-1, 0}};
  EXPECT_TRUE(detail::linear_precision_weights(collinear).allFinite());
}

TEST(ShapePreservingWeights, ConvexCombinationWithLinearPrecision) {
  for (int n = 3; n <= 10; ++n) {
    const auto ring = jittered_ring(n, 1.0, 0.6, 100u + static_cast<unsigned>(n));
    if (!detail::origin_strictly_inside(ring)) continue;
    const auto weights = detail::shape_preserving_weights(ring);
    ASSERT_TRUE(weights.has_value()) << n;
    EXPECT_NEAR(weights->sum(), 1.0, 1e-14);
    EXPECT_GT(weights->minCoeff(), 0.0);
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (int k = 0; k < n; ++k) centre += (*weights)[k] * ring[static_cast<std::size_t>(k)];
    EXPECT_LT(centre.norm(), 1e-14);
  }
  // Regular hexagon: every opposite neighbour is hit exactly, the weights are uniform 1/6.
  const auto hexagon = *detail::shape_preserving_weights(regular_ring(6, 1.0));
  for (Eigen::Index k = 0; k < 6; ++k) EXPECT_NEAR(hexagon[k], 1.0 / 6.0, 1e-14);
  // All neighbours on one side of the centre: no triangle of the ring contains it.
  const std::vector<Eigen::Vector2d> outside = {{1, 0.1}, {2, 1}, {1, 1}, {1.5, 0.2}};
  EXPECT_FALSE(detail::shape_preserving_weights(outside).has_value());
}

TEST(PlanarMeanValueWeights, RegularRingAndLinearPrecision) {
  const Eigen::VectorXd regular = detail::planar_mean_value_weights(regular_ring(6, 2.0), true);
  for (Eigen::Index k = 0; k < 6; ++k) EXPECT_NEAR(regular[k], 2.0 * std::tan(std::numbers::pi / 6.0) / 2.0, 1e-14);
  const auto ring = jittered_ring(7, 1.0, 0.5, 5);
  const Eigen::VectorXd w = detail::planar_mean_value_weights(ring, true);
  const Eigen::VectorXd residual = taylor_residuals(ring, w);
  EXPECT_LT(std::abs(residual[0]) + std::abs(residual[1]), 1e-13);
}

TEST(RingSchemes, RingRowsReallyComeFromTheRingFormulas) {
  // On a curved mesh, the interior row of the positive least squares scheme equals the weights of
  // its flattened ring (scaled back), not a mean value fallback.
  const Mesh cap = hemisphere(4);
  const detail::VertexFans fans(cap.faces, cap.vertex_count());
  const int vertex = 8;  // a second-ring vertex, interior
  ASSERT_EQ(fans.kind(vertex), FanKind::interior);
  const auto neighbours = fans.neighbours(vertex);
  const auto ring = detail::flatten_ring(cap.vertices, vertex, neighbours, true);
  const struct {
    WeightScheme scheme;
    Eigen::VectorXd weights;
  } cases[] = {{WeightScheme::least_squares_positive, *detail::least_squares_positive_weights(ring)},
               {WeightScheme::least_squares, detail::least_squares_weights(ring)},
               {WeightScheme::linear_precision, detail::linear_precision_weights(ring)},
               {WeightScheme::shape_preserving, *detail::shape_preserving_weights(ring)}};
  for (const auto& entry : cases) {
    const Eigen::SparseMatrix<double> L = laplacian(cap, entry.scheme);
    for (std::size_t k = 0; k < neighbours.size(); ++k)
      EXPECT_NEAR(-L.coeff(vertex, neighbours[k]), entry.weights[static_cast<Eigen::Index>(k)],
                  1e-13 * entry.weights.cwiseAbs().maxCoeff())
          << to_string(entry.scheme);
  }
}

}  // namespace
}  // namespace harmonia
