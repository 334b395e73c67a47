#pragma once
// Internal: the exact sign of the 2D orientation determinant, for validity checks that must not be
// fooled by rounding (a nearly collinear triple of UVs decides whether two boundary edges cross).
//
// A cheap floating-point evaluation answers when its result is clearly larger than its worst-case
// rounding error; otherwise the determinant is expanded into its six products, each product is
// split exactly into a sum of two doubles (fused multiply-add), and the twelve terms are summed
// without loss into a floating-point expansion (a sum of non-overlapping doubles, Shewchuk 1997).
// The sign of such an expansion is the sign of its largest component. Exact as long as no product
// overflows or underflows (coordinates between about 1e-150 and 1e150 in magnitude, or zero).

#include <array>
#include <cmath>
#include <cstddef>

#include <Eigen/Core>

namespace harmonia::detail {

// a + b = sum + error exactly (Knuth's two-sum, valid for any order of magnitudes).
inline void two_sum(double a, double b, double& sum, double& error) {
  sum = a + b;
  const double b_virtual = sum - a;
  const double a_virtual = sum - b_virtual;
  error = (a - a_virtual) + (b - b_virtual);
}

// a * b = product + error exactly (the fused multiply-add computes the rounding error of a*b).
inline void two_product(double a, double b, double& product, double& error) {
  product = a * b;
  error = std::fma(a, b, -product);
}

// Sign (-1, 0, +1) of the exact sum of `count` doubles, accumulated into a non-overlapping
// expansion whose components grow in magnitude; zero components are dropped as they appear.
template <std::size_t Capacity>
int exact_sum_sign(const std::array<double, Capacity>& terms) {
  std::array<double, Capacity> expansion{};
  std::size_t length = 0;
  for (const double term : terms) {
    // Add `term` to the expansion: carry it up through the components, keeping the low parts.
    double carry = term;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < length; ++i) {
      double sum = 0.0, error = 0.0;
      two_sum(carry, expansion[i], sum, error);
      if (error != 0.0) expansion[kept++] = error;
      carry = sum;
    }
    if (carry != 0.0) expansion[kept++] = carry;
    length = kept;
  }
  if (length == 0) return 0;
  return expansion[length - 1] > 0.0 ? 1 : -1;
}

// Sign of det [b - a, c - a]: +1 when a, b, c turn counter-clockwise, -1 clockwise, 0 collinear.
inline int orientation_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                            const Eigen::Vector2d& c) {
  const double left = (a.x() - c.x()) * (b.y() - c.y());
  const double right = (a.y() - c.y()) * (b.x() - c.x());
  const double estimate = left - right;
  // Shewchuk's bound on the error of this evaluation: (3 + 16 eps) eps (|left| + |right|).
  constexpr double kEpsilon = 1.1102230246251565e-16;  // 2^-53
  const double bound = (3.0 + 16.0 * kEpsilon) * kEpsilon * (std::abs(left) + std::abs(right));
  if (estimate > bound) return 1;
  if (estimate < -bound) return -1;
  if (left == 0.0 && right == 0.0) return 0;

  // Exact: det = ax*by - ax*cy - ay*bx + ay*cx + bx*cy - by*cx, each product split into two
  // doubles.
  std::array<double, 12> terms{};
  two_product(a.x(), b.y(), terms[0], terms[1]);
  two_product(-a.x(), c.y(), terms[2], terms[3]);
  two_product(-a.y(), b.x(), terms[4], terms[5]);
  two_product(a.y(), c.x(), terms[6], terms[7]);
  two_product(b.x(), c.y(), terms[8], terms[9]);
  two_product(-b.y(), c.x(), terms[10], terms[11]);
  return exact_sum_sign(terms);
}

}  // namespace harmonia::detail
