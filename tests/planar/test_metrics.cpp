// Validity counts (flips, boundary crossings) and distortion metrics of UV layouts, checked against
// maps whose distortion is known in closed form and against hand computations.
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "harmonia/metrics.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "planar/exact_orientation.h"

namespace harmonia {
namespace {

// The (x, y) coordinates of a planar mesh: the identity map of a mesh in the z = 0 plane.
Eigen::MatrixX2d planar_uv(const Mesh& mesh) { return mesh.vertices.leftCols<2>(); }

// A flat rectangle [0, length] x [0, width] on an nu x nv grid (vertex (i, j) = j*(nu+1) + i).
Mesh flat_strip(int nu, int nv, double length, double width) {
  // A huge radius rolls the strip onto an almost flat cylinder; flatten it exactly.
  Mesh strip = developable_strip(nu, nv, length, width, 1.0);
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      strip.vertices.row(j * (nu + 1) + i) << length * i / nu, width * j / nv, 0.0;
    }
  }
  return strip;
}

// ---------------------------------------------------------------------------------------------
// Exact orientation

// Sign of the orientation determinant computed exactly in 128-bit integers, for points whose
// coordinates lie in [512, 1024): there every double is an integer times 2^-43 below 2^53, so the
// differences stay below 2^53 and their products below 2^106.
int integer_orientation(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                        const Eigen::Vector2d& c) {
  const auto fixed = [](double value) {
    return static_cast<__int128>(std::llround(std::ldexp(value, 43)));
  };
  const __int128 det = (fixed(b.x()) - fixed(a.x())) * (fixed(c.y()) - fixed(a.y())) -
                       (fixed(b.y()) - fixed(a.y())) * (fixed(c.x()) - fixed(a.x()));
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

TEST(ExactOrientation, AgreesWithIntegerArithmeticOnNearlyCollinearPoints) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> start(560.0, 620.0), finish(700.0, 760.0);
  std::uniform_real_distribution<double> along(-0.2, 1.5);
  std::uniform_int_distribution<int> nudge(-2, 2);
  // Moves a coordinate by a few units in the last place (2^-43 throughout [512, 1024)).
  const auto nudged = [&](double value) { return value + std::ldexp(nudge(random), -43); };
  int collinear = 0, naive_wrong = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Eigen::Vector2d a(start(random), start(random));
    const Eigen::Vector2d b(finish(random), finish(random));
    // Every fifth triple extends a to b exactly (2b - a is representable here), so that exactly
    // collinear triples occur; the others are rounded points near the line.
    const Eigen::Vector2d on_line = trial % 5 == 0 ? Eigen::Vector2d(b + (b - a))
                                                   : Eigen::Vector2d(a + along(random) * (b - a));
    const Eigen::Vector2d c(nudged(on_line.x()), nudged(on_line.y()));
    const int expected = integer_orientation(a, b, c);
    ASSERT_EQ(detail::orientation_sign(a, b, c), expected) << "trial " << trial;
    ASSERT_EQ(detail::orientation_sign(b, c, a), expected) << "trial " << trial;
    ASSERT_EQ(detail::orientation_sign(c, a, b), expected) << "trial " << trial;
    ASSERT_EQ(detail::orientation_sign(b, a, c), -expected) << "trial " << trial;
    collinear += expected == 0;
    const double naive = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    naive_wrong += (naive > 0 ? 1 : (naive < 0 ? -1 : 0)) != expected;
  }
  // The cases are hard: exact collinearity occurs, and plain doubles misjudge many triples.
  EXPECT_GT(collinear, 100);
  EXPECT_GT(naive_wrong, 100);
}

// ---------------------------------------------------------------------------------------------
// Flips

TEST(CountFlips, IdentityMapOfAPlanarDiskHasNone) {
  const Mesh disk = planar_disk(6, 0.5);
  const FlipCount count = count_flips(planar_uv(disk), disk.faces);
  EXPECT_EQ(count.flipped, 0);
  EXPECT_EQ(count.zero_area, 0);
}

TEST(CountFlips, MirroredMapFlipsEveryTriangle) {
  const Mesh disk = planar_disk(5, 0.5);
  Eigen::MatrixX2d uv = planar_uv(disk);
  uv.col(0) *= -1.0;
  const FlipCount count = count_flips(uv, disk.faces);
  EXPECT_EQ(count.flipped, disk.face_count());
  EXPECT_EQ(count.zero_area, 0);
}

TEST(CountFlips, OneFoldedCornerTriangleIsExactlyOneFlip) {
  // Vertex (0, 1) of the strip belongs to one triangle only, (0,0)-(1,1)-(0,1); reflecting it
  // across that triangle's diagonal turns only that triangle over.
  const int nu = 4;
  const Mesh strip = flat_strip(nu, 1, 2.0, 1.0);  // cells 0.5 wide, 1 high
  Eigen::MatrixX2d uv = planar_uv(strip);
  const Eigen::Vector2d diagonal = Eigen::Vector2d(0.5, 1.0).normalized();
  const Eigen::Vector2d corner = uv.row(nu + 1);
  const Eigen::Vector2d reflected = 2.0 * corner.dot(diagonal) * diagonal - corner;
  uv.row(nu + 1) = reflected;
  const FlipCount count = count_flips(uv, strip.faces);
  EXPECT_EQ(count.flipped, 1);
  EXPECT_EQ(count.zero_area, 0);
}

TEST(CountFlips, ZeroAreaTrianglesAreCountedApartFromFlips) {
  const Mesh strip = flat_strip(3, 1, 3.0, 1.0);
  Eigen::MatrixX2d uv = planar_uv(strip);
  // Vertex (0, 1) onto the line through (0, 0) and (1, 1): its only triangle becomes a segment.
  uv.row(4) << 0.5, 0.5;
  FlipCount count = count_flips(uv, strip.faces);
  EXPECT_EQ(count.zero_area, 1);
  EXPECT_EQ(count.flipped, 0);
  // A non-finite coordinate is degenerate too, never silently ignored.
  uv.row(4) << std::nan(""), 0.5;
  count = count_flips(uv, strip.faces);
  EXPECT_EQ(count.zero_area, 1);
}

TEST(CountFlips, ATinyTriangleWhoseShapeIsResolvedIsValid) {
  // A map that shrinks part of the surface by 1e-9 in length (1e-18 in area) is still a valid
  // map: the corners resolve the triangle to about 1e-7 of its size. It is counted as tiny.
  Eigen::MatrixX2d uv(6, 2);
  uv << 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.5, 0.5, 0.5 + 1e-9, 0.5, 0.5, 0.5 + 1e-9;
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 3, 4, 5;
  FlipCount count = count_flips(uv, faces);
  EXPECT_EQ(count.flipped, 0);
  EXPECT_EQ(count.zero_area, 0);
  EXPECT_EQ(count.tiny, 1);
  // Mirrored, the tiny triangle is a flip like any other.
  uv.row(4) << 0.5 - 1e-9, 0.5;
  count = count_flips(uv, faces);
  EXPECT_EQ(count.flipped, 1);
  EXPECT_EQ(count.tiny, 0);
}

TEST(CountFlips, ASliverWithinTheRoundingOfItsCornersIsZeroArea) {
  // Far from the origin a coordinate is known to about 1e6 * eps = 2e-10; a triangle of height
  // 1e-12 there is positive by the exact test but its area is noise.
  Eigen::MatrixX2d uv(6, 2);
  uv << 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1e6, 0.0, 1e6 + 1.0, 0.0, 1e6 + 0.5, 1e-12;
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 3, 4, 5;
  const FlipCount count = count_flips(uv, faces);
  EXPECT_EQ(count.zero_area, 1);
  EXPECT_EQ(count.flipped, 0);
}

TEST(CountFlips, RejectsAnIndexOutsideTheUvRows) {
  const Mesh strip = flat_strip(2, 1, 2.0, 1.0);
  Eigen::MatrixX3i faces = strip.faces;
  faces(2, 1) = 99;
  try {
    (void)count_flips(planar_uv(strip), faces);
    FAIL() << "no error for an out-of-range index";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("uv_faces row 2 corner 1"), std::string::npos)
        << error.what();
  }
}

// ---------------------------------------------------------------------------------------------
// Boundary self-intersections

TEST(BoundarySelfIntersections, ConvexDiskHasNone) {
  const Mesh disk = planar_disk(8, 0.5);
  EXPECT_EQ(count_boundary_self_intersections(planar_uv(disk), disk.faces), 0);
}

// A strip of width 1 wound around a spiral: angle = turns * 2 pi * x / length, radius growing by
// half the width per turn, so that after one turn its end lies over its start.
Eigen::MatrixX2d spiral_layout(const Mesh& strip, double length, double turns) {
  Eigen::MatrixX2d uv(strip.vertex_count(), 2);
  const double base_radius = 4.0;
  for (int v = 0; v < strip.vertex_count(); ++v) {
    const double x = strip.vertices(v, 0), y = strip.vertices(v, 1);
    const double angle = turns * 2.0 * std::numbers::pi * x / length;
    // Radius decreases with y so the winding keeps triangles counter-clockwise.
    const double radius = base_radius - y + 0.5 * angle / (2.0 * std::numbers::pi);
    uv.row(v) << radius * std::cos(angle), radius * std::sin(angle);
  }
  return uv;
}

TEST(BoundarySelfIntersections, StripWoundPastOneTurnCrossesItselfTwice) {
  // Wound 1.2 turns: the end covers angles [0, 0.4 pi] again at radii shifted by 0.5. The end's
  // inner side crosses the start edge (at angle 0) and the end edge crosses the start's outer side.
  // 50 cells of 0.048 pi each: neither crossing falls on a vertex.
  const double length = 10.0;
  const Mesh strip = flat_strip(50, 1, length, 1.0);
  const Eigen::MatrixX2d uv = spiral_layout(strip, length, 1.2);
  const FlipCount flips = count_flips(uv, strip.faces);
  ASSERT_EQ(flips.flipped, 0);  // Every triangle is fine; only the boundary overlaps.
  EXPECT_EQ(count_boundary_self_intersections(uv, strip.faces), 2);
  // Wound less than a turn the same strip is a simple polygon.
  EXPECT_EQ(count_boundary_self_intersections(spiral_layout(strip, length, 0.8), strip.faces), 0);
}

TEST(BoundarySelfIntersections, CollinearOverlapsAndTouchingEndpointsCount) {
  // Two separate triangles whose horizontal edges overlap on [1, 2] x {0}:
  //   A = (0,0) (2,0) (1,1) above, B = (1,0) (2,-1) (3,0) below.
  // Meeting pairs: A's bottom with B's top (overlap), A's right side with B's top (A's corner
  // (2,0) lies on it), B's left side with A's bottom (B's corner (1,0) lies on it).
  Eigen::MatrixX2d uv(6, 2);
  uv << 0, 0, 2, 0, 1, 1, 1, 0, 2, -1, 3, 0;
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 3, 4, 5;
  ASSERT_EQ(count_flips(uv, faces).flipped, 0);
  EXPECT_EQ(count_boundary_self_intersections(uv, faces), 3);
  // Moved apart by one unit in the last place of 0, B's top edge no longer touches A.
  uv(3, 1) = uv(5, 1) = -std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(count_boundary_self_intersections(uv, faces), 0);
}

TEST(BoundarySelfIntersections, CountIsTheSameAsAllPairsOnARandomLayout) {
  // Many small disjoint triangles scattered at random: compare the grid count with the plain
  // quadratic loop over all pairs of boundary edges.
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> position(0.0, 10.0), offset(-0.6, 0.6);
  const int triangles = 400;
  Eigen::MatrixX2d uv(3 * triangles, 2);
  Eigen::MatrixX3i faces(triangles, 3);
  for (int t = 0; t < triangles; ++t) {
    const Eigen::Vector2d centre(position(random), position(random));
    for (int k = 0; k < 3; ++k)
      uv.row(3 * t + k) = centre + Eigen::Vector2d(offset(random), offset(random));
    faces.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
  }
  int expected = 0;
  for (int s = 0; s < triangles; ++s) {
    for (int t = s + 1; t < triangles; ++t) {
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const Eigen::Vector2d p1 = uv.row(faces(s, i)), p2 = uv.row(faces(s, (i + 1) % 3));
          const Eigen::Vector2d q1 = uv.row(faces(t, j)), q2 = uv.row(faces(t, (j + 1) % 3));
          const auto side = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const Eigen::Vector2d& c) {
            return detail::orientation_sign(a, b, c);
          };
          // Random reals: no collinear triples, so proper crossings are all there is.
          expected +=
              side(p1, p2, q1) * side(p1, p2, q2) < 0 && side(q1, q2, p1) * side(q1, q2, p2) < 0;
        }
      }
    }
  }
  ASSERT_GT(expected, 50);
  EXPECT_EQ(count_boundary_self_intersections(uv, faces), expected);
}

// ---------------------------------------------------------------------------------------------
// Distortion

Eigen::Matrix2d rotation(double angle) {
  Eigen::Matrix2d r;
  r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return r;
}

// uv = linear * (x, y) + offset for a planar mesh.
Eigen::MatrixX2d affine_uv(const Mesh& mesh, const Eigen::Matrix2d& linear,
                           const Eigen::Vector2d& offset) {
  Eigen::MatrixX2d uv(mesh.vertex_count(), 2);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    uv.row(v) = (linear * mesh.vertices.row(v).head<2>().transpose() + offset).transpose();
  }
  return uv;
}

TEST(EvaluateMap, IdentityOfAPlanarDiskIsFreeOfDistortion) {
  const Mesh disk = planar_disk(6, 0.5);
  const DistortionMetrics metrics = evaluate_map(disk, planar_uv(disk), disk.faces);
  EXPECT_EQ(metrics.faces, disk.face_count());
  EXPECT_EQ(metrics.flipped_triangles, 0);
  EXPECT_EQ(metrics.zero_area_triangles, 0);
  EXPECT_EQ(metrics.degenerate_input_triangles, 0);
  EXPECT_EQ(metrics.boundary_self_intersections, 0);
  EXPECT_NEAR(metrics.angle_error_mean_squared, 0.0, 1e-24);
  EXPECT_NEAR(metrics.abf_energy, 0.0, 1e-24);
  EXPECT_NEAR(metrics.conformal_distortion_mean, 1.0, 1e-12);
  EXPECT_NEAR(metrics.conformal_distortion_max, 1.0, 1e-12);
  EXPECT_NEAR(metrics.area_distortion_mean, 0.0, 1e-12);
  EXPECT_NEAR(metrics.area_distortion_max, 0.0, 1e-12);
  EXPECT_NEAR(metrics.l2_stretch, 1.0, 1e-12);
  ASSERT_EQ(metrics.face_conformal_distortion.size(), disk.face_count());
  EXPECT_NEAR(metrics.face_conformal_distortion.maxCoeff(), 1.0, 1e-12);
  EXPECT_NEAR(metrics.face_area_log_ratio.cwiseAbs().maxCoeff(), 0.0, 1e-12);
}

TEST(EvaluateMap, RotatedScaledCopyIsConformalAndAfterNormalizationAuthalic) {
  const Mesh disk = planar_disk(6, 0.5);
  const Eigen::MatrixX2d uv = affine_uv(disk, 3.0 * rotation(0.7), Eigen::Vector2d(5.0, -2.0));
  const DistortionMetrics metrics = evaluate_map(disk, uv, disk.faces);
  EXPECT_EQ(metrics.flipped_triangles, 0);
  EXPECT_NEAR(metrics.angle_error_mean_squared, 0.0, 1e-24);
  EXPECT_NEAR(metrics.conformal_distortion_mean, 1.0, 1e-12);
  EXPECT_NEAR(metrics.conformal_distortion_max, 1.0, 1e-12);
  EXPECT_NEAR(metrics.area_distortion_mean, 0.0, 1e-12);
  EXPECT_NEAR(metrics.area_distortion_max, 0.0, 1e-12);
  EXPECT_NEAR(metrics.l2_stretch, 1.0, 1e-12);
}

TEST(EvaluateMap, StretchingXByTwoGivesSingularValueRatioTwoEverywhere) {
  const Mesh disk = planar_disk(5, 0.5);
  const Eigen::MatrixX2d uv = affine_uv(
      disk, Eigen::Vector2d(2.0, 1.0).asDiagonal().toDenseMatrix(), Eigen::Vector2d::Zero());
  const DistortionMetrics metrics = evaluate_map(disk, uv, disk.faces);
  for (int f = 0; f < disk.face_count(); ++f) {
    EXPECT_NEAR(metrics.face_conformal_distortion[f], 2.0, 1e-12) << "face " << f;
    EXPECT_NEAR(metrics.face_area_log_ratio[f], 0.0, 1e-12) << "face " << f;  // All doubled.
  }
  EXPECT_NEAR(metrics.conformal_distortion_mean, 2.0, 1e-12);
  EXPECT_NEAR(metrics.area_distortion_mean, 0.0, 1e-12);
  // Singular values (2, 1): stretch^2 = (1/4 + 1)/2, normalized by sqrt(uv area / 3D area) =
  // sqrt 2.
  EXPECT_NEAR(metrics.l2_stretch, std::sqrt(0.625) * std::sqrt(2.0), 1e-12);
  EXPECT_GT(metrics.angle_error_mean_squared, 1e-3);
}

TEST(EvaluateMap, MirroredMapHasEveryTriangleFlippedAndStaysFinite) {
  const Mesh disk = planar_disk(4, 0.5);
  const Eigen::MatrixX2d uv = affine_uv(
      disk, Eigen::Vector2d(-1.0, 1.0).asDiagonal().toDenseMatrix(), Eigen::Vector2d::Zero());
  const DistortionMetrics metrics = evaluate_map(disk, uv, disk.faces);
  EXPECT_EQ(metrics.flipped_triangles, disk.face_count());
  // Documented choice: a mirror image measures its shape, which is undistorted.
  EXPECT_NEAR(metrics.conformal_distortion_mean, 1.0, 1e-12);
  EXPECT_NEAR(metrics.l2_stretch, 1.0, 1e-12);
}

// An orthographic projection of the hemisphere: per face, the singular values from an SVD of the
// 3x2 Jacobian of the inverse map (UV -> 3D), computed independently with Eigen.
TEST(EvaluateMap, ProjectedHemisphereMatchesAnIndependentSvd) {
  const Mesh cap = hemisphere(5);
  const Eigen::MatrixX2d uv = cap.vertices.leftCols<2>();
  const DistortionMetrics metrics = evaluate_map(cap, uv, cap.faces);
  EXPECT_EQ(metrics.flipped_triangles, 0);
  double area_total = 0.0, conformal_weighted = 0.0, stretch_weighted = 0.0, uv_total = 0.0;
  for (int f = 0; f < cap.face_count(); ++f) {
    const Eigen::Vector3d p0 = cap.vertices.row(cap.faces(f, 0)),
                          p1 = cap.vertices.row(cap.faces(f, 1)),
                          p2 = cap.vertices.row(cap.faces(f, 2));
    const Eigen::Vector2d u0 = uv.row(cap.faces(f, 0)), u1 = uv.row(cap.faces(f, 1)),
                          u2 = uv.row(cap.faces(f, 2));
    Eigen::Matrix<double, 3, 2> surface_edges;
    surface_edges << p1 - p0, p2 - p0;
    Eigen::Matrix2d uv_edges;
    uv_edges << u1 - u0, u2 - u0;
    const Eigen::Matrix<double, 3, 2> inverse_jacobian = surface_edges * uv_edges.inverse();
    const Eigen::Vector2d singular =
        Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>>(inverse_jacobian).singularValues();
    EXPECT_NEAR(metrics.face_conformal_distortion[f], singular[0] / singular[1], 1e-9)
        << "face " << f;
    const double area = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    area_total += area;
    uv_total += 0.5 * std::abs(uv_edges.determinant());
    conformal_weighted += area * singular[0] / singular[1];
    stretch_weighted += area * singular.squaredNorm() / 2.0;
  }
  EXPECT_NEAR(metrics.conformal_distortion_mean, conformal_weighted / area_total, 1e-9);
  EXPECT_NEAR(metrics.l2_stretch,
              std::sqrt(stretch_weighted / area_total) * std::sqrt(uv_total / area_total), 1e-9);
  EXPECT_GT(metrics.conformal_distortion_max, 1.5);  // Steep near the equator.
}

TEST(EvaluateMap, AbfEnergyOfTwoTrianglesMatchesAHandComputation) {
  // A unit square split along (0,0)-(1,1); in UV the corner (1,1) is moved to (1,2).
  //   3D angles: face 0 (v0 v1 v2): 45, 90, 45 degrees; face 1 (v0 v2 v3): 45, 45, 90.
  //   UV face 0: at v0 atan 2, at v1 90, at v2 atan(1/2).
  //   UV face 1: at v0 90 - atan 2 = atan(1/2); at v2 between (-1,-1) and (-1,-2): atan(1/3);
  //              at v3 between (0,-1) and (1,1): 135 degrees.
  Mesh square;
  square.vertices.resize(4, 3);
  square.vertices << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  square.faces.resize(2, 3);
  square.faces << 0, 1, 2, 0, 2, 3;
  Eigen::MatrixX2d uv(4, 2);
  uv << 0, 0, 1, 0, 1, 2, 0, 1;
  const double quarter = std::numbers::pi / 4, half = std::numbers::pi / 2;
  const double errors[6][2] = {
      {std::atan(2.0) - quarter, quarter},       {0.0, half},
      {std::atan(0.5) - quarter, quarter},       {std::atan(0.5) - quarter, quarter},
      {std::atan(1.0 / 3.0) - quarter, quarter}, {3 * quarter - half, half}};
  double abf = 0.0, squared = 0.0;
  for (const auto& [error, angle] : errors) {
    abf += error * error / (angle * angle);
    squared += error * error;
  }
  const DistortionMetrics metrics = evaluate_map(square, uv, square.faces);
  EXPECT_NEAR(metrics.abf_energy, abf / 6.0, 1e-14);
  EXPECT_NEAR(metrics.angle_error_mean_squared, squared / 6.0, 1e-14);
  // By hand: three corners off by atan 2 - pi/4 = 0.32175 (relative 0.40966, squared 0.16782),
  // one by atan(1/3) - pi/4 (relative 0.59034, squared 0.34850), the right angle at v3 by a half
  // (0.25): (3 * 0.16782 + 0.34850 + 0.25) / 6 = 0.18366.
  EXPECT_NEAR(metrics.abf_energy, 0.18366, 1e-5);
}

TEST(EvaluateMap, SeamsWithSeparateUvCopiesAreEvaluatedPerCorner) {
  // Faces right of x = 0 take their UVs from a second copy of the vertices, rotated by half a turn
  // and moved away: two undistorted pieces that do not overlap.
  const Mesh disk = planar_disk(5, 0.5);
  const int vertices = disk.vertex_count();
  Eigen::MatrixX2d uv(2 * vertices, 2);
  uv.topRows(vertices) = planar_uv(disk);
  uv.bottomRows(vertices) = affine_uv(disk, rotation(std::numbers::pi), Eigen::Vector2d(5.0, 0.0));
  Eigen::MatrixX3i uv_faces = disk.faces;
  int moved = 0;
  for (int f = 0; f < disk.face_count(); ++f) {
    double centroid_x = 0.0;
    for (int corner = 0; corner < 3; ++corner)
      centroid_x += disk.vertices(disk.faces(f, corner), 0);
    if (centroid_x > 0.0) {
      uv_faces.row(f).array() += vertices;
      ++moved;
    }
  }
  ASSERT_GT(moved, 10);
  const DistortionMetrics metrics = evaluate_map(disk, uv, uv_faces);
  EXPECT_EQ(metrics.flipped_triangles, 0);
  EXPECT_EQ(metrics.boundary_self_intersections, 0);
  EXPECT_NEAR(metrics.angle_error_mean_squared, 0.0, 1e-24);
  EXPECT_NEAR(metrics.conformal_distortion_max, 1.0, 1e-12);
  EXPECT_NEAR(metrics.area_distortion_max, 0.0, 1e-12);
  EXPECT_NEAR(metrics.l2_stretch, 1.0, 1e-12);
  // Read as if seamless (mesh faces into the same uv array) the right half would be torn apart.
  const DistortionMetrics torn = evaluate_map(disk, uv, disk.faces);
  EXPECT_NEAR(torn.l2_stretch, 1.0, 1e-12);  // Uses only the first copy: identity again.
  // Half the faces into the first copy, the other half into the second, but swapped: torn.
  Eigen::MatrixX3i mixed = uv_faces;
  mixed(0, 0) += mixed(0, 0) < vertices ? vertices : -vertices;
  EXPECT_GT(evaluate_map(disk, uv, mixed).conformal_distortion_max, 2.0);
}

TEST(EvaluateMap, ZeroAreaTrianglesAreCountedAndKeptOutOfTheMeans) {
  const Mesh strip = flat_strip(3, 1, 3.0, 1.0);
  Eigen::MatrixX2d uv = planar_uv(strip);
  uv.row(4) << 0.5, 0.5;  // Squashes face (0,0)-(1,1)-(0,1) onto the diagonal.
  const DistortionMetrics metrics = evaluate_map(strip, uv, strip.faces);
  EXPECT_EQ(metrics.zero_area_triangles, 1);
  EXPECT_EQ(metrics.flipped_triangles, 0);
  EXPECT_TRUE(std::isinf(metrics.face_conformal_distortion[1]));
  EXPECT_TRUE(std::isfinite(metrics.conformal_distortion_mean));
  EXPECT_TRUE(std::isfinite(metrics.l2_stretch));
  EXPECT_TRUE(std::isfinite(metrics.area_distortion_mean));
  EXPECT_GT(metrics.angle_error_mean_squared, 0.0);  // Its angles still count.

  // A 3D triangle without area is reported apart and has no figures at all.
  Mesh flattened = strip;
  flattened.vertices.row(4) << 0.5, 0.5, 0.0;
  const DistortionMetrics input = evaluate_map(flattened, planar_uv(strip), strip.faces);
  EXPECT_EQ(input.degenerate_input_triangles, 1);
  EXPECT_TRUE(std::isfinite(input.abf_energy));
  EXPECT_TRUE(std::isfinite(input.conformal_distortion_mean));
}

TEST(EvaluateMap, RejectsFaceCountMismatchAndBadVertexIndices) {
  const Mesh strip = flat_strip(2, 1, 2.0, 1.0);
  try {
    (void)evaluate_map(strip, planar_uv(strip), strip.faces.topRows(2));
    FAIL() << "no error for mismatched face counts";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("uv_faces has 2 rows but the mesh has 4 faces"),
              std::string::npos)
        << error.what();
  }
  Mesh broken = strip;
  broken.faces(3, 2) = -1;
  try {
    (void)evaluate_map(broken, planar_uv(strip), strip.faces);
    FAIL() << "no error for a negative vertex index";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("face 3 corner 2"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace harmonia
