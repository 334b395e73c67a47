#pragma once
// Internal: the texels a chart touches. Conservative rasterization (every texel whose closed square
// meets a triangle, Hasselgren et al. 2005) is what keeps two packed charts apart: charts whose
// conservative rasters, one of them grown by the padding, share no texel are at least `padding`
// texels apart everywhere, not only at texel centres.

#include <Eigen/Core>

#include "atlas/texel_bitmap.h"

namespace harmonia::detail {

//! How far (in texels) a triangle is grown before it is rasterized, so that rounding in the
//! corners' final position (scale, rotation and offset applied in another order, at most a few
//! units in the last place of 32768) can never reach a texel the raster left out.
inline constexpr double raster_tolerance = 1e-6;

//! Sets every texel of `bitmap` whose closed square [x, x + 1] x [y, y + 1] comes within
//! raster_tolerance of the closed triangle (a, b, c) (either orientation, or degenerate); texels
//! outside the bitmap are left out.
void rasterize_triangle_conservatively(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                       const Eigen::Vector2d& c, TexelBitmap& bitmap);

//! Sets every texel of `bitmap` whose centre lies strictly inside the triangle (a, b, c) (either
//! orientation; none for a degenerate one): the texels a renderer fills, which the atlas' coverage
//! counts.
void rasterize_triangle_centres(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               const Eigen::Vector2d& c, TexelBitmap& bitmap);

}  // namespace harmonia::detail
