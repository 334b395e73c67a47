#pragma once
// Internal: the orientation of a triangle of sphere points against the sphere's outward normal,
// decided exactly, and its signed spherical area.
//
// Three points a, b, c of a sphere centred at the origin turn counter-clockwise seen from outside
// exactly when det[a, b, c] = a . (b x c) > 0 (the tetrahedron with the centre is positively
// oriented). The determinant is evaluated in floating point with Shewchuk's error bound for
// orient3d; when the estimate is within the bound it is expanded into its six triple products,
// each split exactly into four doubles (fused multiply-add), and summed without loss
// (planar/exact_orientation.h).

#include <array>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "planar/exact_orientation.h"

namespace harmonia::detail {

//! Sign of det[a, b, c]: +1 counter-clockwise seen from outside, -1 clockwise, 0 when the three
//! points and the centre are coplanar (a degenerate spherical triangle).
inline int sphere_orientation_sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                   const Eigen::Vector3d& c) {
  const double bc_x = b.y() * c.z() - b.z() * c.y();
  const double bc_y = b.z() * c.x() - b.x() * c.z();
  const double bc_z = b.x() * c.y() - b.y() * c.x();
  const double estimate = a.x() * bc_x + a.y() * bc_y + a.z() * bc_z;
  const double permanent =
      std::abs(a.x()) * (std::abs(b.y() * c.z()) + std::abs(b.z() * c.y())) +
      std::abs(a.y()) * (std::abs(b.z() * c.x()) + std::abs(b.x() * c.z())) +
      std::abs(a.z()) * (std::abs(b.x() * c.y()) + std::abs(b.y() * c.x()));
  // Shewchuk's orient3d bound (7 + 56 eps) eps times the permanent.
  constexpr double kEpsilon = 1.1102230246251565e-16;  // 2^-53
  const double bound = (7.0 + 56.0 * kEpsilon) * kEpsilon * permanent;
  if (estimate > bound) return 1;
  if (estimate < -bound) return -1;
  if (permanent == 0.0) return 0;
  // Exact: the six products s * p * q * r of the expansion, each split into four doubles.
  const std::array<std::array<double, 3>, 6> factors{{{a.x(), b.y(), c.z()},
                                                      {-a.x(), b.z(), c.y()},
                                                      {a.y(), b.z(), c.x()},
                                                      {-a.y(), b.x(), c.z()},
                                                      {a.z(), b.x(), c.y()},
                                                      {-a.z(), b.y(), c.x()}}};
  std::array<double, 24> terms{};
  for (std::size_t k = 0; k < factors.size(); ++k) {
    double high = 0.0, low = 0.0;
    two_product(factors[k][0], factors[k][1], high, low);
    two_product(high, factors[k][2], terms[4 * k], terms[4 * k + 1]);
    two_product(low, factors[k][2], terms[4 * k + 2], terms[4 * k + 3]);
  }
  return exact_sum_sign(terms);
}

//! Signed area of the spherical triangle a, b, c of the unit sphere (its spherical excess,
//! Van Oosterom and Strackee): positive counter-clockwise seen from outside.
inline double signed_spherical_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  const double triple = a.dot(b.cross(c));
  const double denominator = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
  return 2.0 * std::atan2(triple, denominator);
}

}  // namespace harmonia::detail
