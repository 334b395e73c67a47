#pragma once
// Internal: exact rescaling of coordinates by a power of two, so that geometric tests and
// tolerances work the same at every scale of a model (1e-100 or 1e200 units): multiplying by 2^k
// changes only the exponent of each coordinate, so every relation between them is kept, and the
// squares and cross products that follow neither overflow nor underflow.

#include <cmath>

#include <Eigen/Core>

namespace harmonia::detail {

//! The power of two 2^-e that brings `largest_magnitude` (> 0, finite) into [1, 2); 1 for 0 or a
//! value that is not finite.
inline double unit_scale_for(double largest_magnitude) {
  if (!(largest_magnitude > 0.0) || !std::isfinite(largest_magnitude)) return 1.0;
  return std::ldexp(1.0, -std::ilogb(largest_magnitude));
}

//! `points` times the power of two that brings their largest absolute coordinate into [1, 2).
template <typename Matrix>
[[nodiscard]] Matrix scaled_to_unit(const Matrix& points) {
  if (points.size() == 0) return points;
  return points * unit_scale_for(points.cwiseAbs().maxCoeff());
}

}  // namespace harmonia::detail
