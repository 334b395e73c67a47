#pragma once
// Internal: the charts that a mesh's own texture coordinates make, for repacking them
// (harmonia/texture_atlas.h, repack_texture_atlas).
//
// Two faces are in one chart where they share an edge whose two ends carry, in both faces, the
// same vertex and the same UV: the UV layout is continuous across that edge. A seam of the input
// (the same edge at two UVs), and an edge of one face only, are chart boundaries. A chart's
// vertices are the pairs (vertex, UV) of its corners, so a vertex on a seam is one chart vertex
// per chart. Each chart keeps its layout as it is, only scaled so that its UV area equals its 3D
// area: every chart then has the same texel density once packed (the packer's unit is 3D length).

#include <vector>

#include <Eigen/Core>

#include "atlas/chart_flattening.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

//! The charts of `corner_uv` (#F by 6, per face u0 v0 u1 v1 u2 v2; finite), sorted by their first
//! face, with ChartMethod::input_layout. A chart without UV area (its corners on a line or at one
//! point) is scaled by its 3D perimeter over its UV perimeter, or kept as it is when that is 0.
[[nodiscard]] std::vector<FinishedChart> input_charts(const Mesh& mesh,
                                                      const Eigen::Matrix<double, Eigen::Dynamic, 6>& corner_uv);

}  // namespace harmonia::detail
