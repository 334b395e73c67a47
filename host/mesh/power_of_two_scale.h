#pragma once
// Internal: exact rescaling of coordinates by a power of two, so that geometric tests and
// tolerances work the same at every scale of a model (1e-100 or 1e200 units). Multiplying by 2^k
// changes only the exponent of each coordinate (exactly, as long as nothing becomes subnormal),
// so every relation between them is kept, and each floating-point result is the unscaled one
// times a power of two. The methods compute on a copy of unit size (unit_scaled); the checks and
// measures, which must keep even a subnormal coordinate exact, rescale only coordinates outside a
// safe range, [2^-64, 2^64] in largest magnitude (scaled_into_safe_range), where squares and cross
// products cannot overflow or underflow.

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia::detail {

//! The power of two 2^-e that brings `largest_magnitude` (> 0, finite) into [1, 2); 1 for 0 or a
//! value that is not finite. The scale is at most 2^1023, the largest power of two a double holds:
//! a subnormal magnitude (below 2^-1022) would need more, and an infinite scale would turn every
//! zero coordinate into NaN. Such a magnitude comes out in [2^-51, 2), still in the safe range.
inline double unit_scale_for(double largest_magnitude) {
  if (!(largest_magnitude > 0.0) || !std::isfinite(largest_magnitude)) return 1.0;
  constexpr int largest_exponent = std::numeric_limits<double>::max_exponent - 1;  // 1023
  return std::ldexp(1.0, std::min(-std::ilogb(largest_magnitude), largest_exponent));
}

//! 1 when `largest_magnitude` lies in [2^-64, 2^64], else unit_scale_for(largest_magnitude).
inline double safe_range_scale_for(double largest_magnitude) {
  const double low = std::ldexp(1.0, -64), high = std::ldexp(1.0, 64);
  if (largest_magnitude >= low && largest_magnitude <= high) return 1.0;
  return unit_scale_for(largest_magnitude);
}

//! `points` times safe_range_scale_for of their largest absolute coordinate.
template <typename Matrix>
[[nodiscard]] Matrix scaled_into_safe_range(const Matrix& points) {
  if (points.size() == 0 || !points.allFinite()) return points;
  const double scale = safe_range_scale_for(points.cwiseAbs().maxCoeff());
  return scale == 1.0 ? points : Matrix(points * scale);
}

//! The copy of a mesh that a method computes on: its vertices times `scale`, the power of two
//! that brings the largest absolute coordinate into [1, 2), whatever it was. Weights, areas and
//! tolerances computed on it neither overflow nor underflow at any unit of the model, and since
//! every power-of-two rescaling of the input gives the same copy, the method gives the same bits
//! for all of them (a method whose operator scales with the model, such as the quasi-harmonic
//! tensors, would otherwise round differently for odd exponents). A mesh with non-finite
//! coordinates is copied unscaled (validation refuses it).
struct ScaledMesh {
  Mesh mesh;
  double scale = 1.0;
};

[[nodiscard]] inline ScaledMesh unit_scaled(const Mesh& input) {
  ScaledMesh scaled;
  scaled.scale = input.vertices.size() > 0 && input.vertices.allFinite()
                     ? unit_scale_for(input.vertices.cwiseAbs().maxCoeff())
                     : 1.0;
  scaled.mesh.vertices = input.vertices * scaled.scale;
  scaled.mesh.faces = input.faces;
  return scaled;
}

}  // namespace harmonia::detail
