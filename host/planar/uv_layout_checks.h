#pragma once
// Internal: per-triangle facts about a UV layout shared by the validity counts, the distortion
// metrics and the pictures, so that all three agree on which triangles are flipped or degenerate.

#include <vector>

#include <Eigen/Core>

namespace harmonia::detail {

// A 3D triangle whose area is at most this fraction of the total area counts as degenerate input;
// a UV triangle this small is valid but reported as tiny (FlipCount::tiny).
inline constexpr double kZeroAreaFraction = 1e-14;
// A UV triangle counts as zero-area when |area| <= this * eps * (largest |coordinate| of its
// corners) * (its perimeter): rounding its corners could change its area that much.
inline constexpr double kAreaResolutionFactor = 8.0;

enum class TriangleState {
  positive,    // Counter-clockwise, with a resolvable area.
  flipped,     // Clockwise (negative signed area).
  degenerate,  // Zero area (exactly, or within the rounding of its corners), or not finite.
};

// Throws Error(invalid_input) naming the first uv_faces entry that is not a row of uv.
void check_uv_faces(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces,
                    const char* caller);

// Signed area of every UV triangle (positive when counter-clockwise).
[[nodiscard]] std::vector<double> signed_uv_areas(const Eigen::MatrixX2d& uv,
                                                  const Eigen::MatrixX3i& uv_faces);

// Sum of |area| over the finite entries.
[[nodiscard]] double total_finite_area(const std::vector<double>& signed_areas);

// The state of one triangle; the sign comes from the exact orientation predicate, so a triangle
// is never called flipped because of rounding.
[[nodiscard]] TriangleState classify_uv_triangle(const Eigen::MatrixX2d& uv,
                                                 const Eigen::MatrixX3i& uv_faces,
                                                 Eigen::Index face, double signed_area);

}  // namespace harmonia::detail
