#pragma once
// Internal: the quality of a texture atlas (harmonia/texture_atlas.h), measured with the same
// definitions as the independent evaluator atlaseval.py, so that the library reports what it will
// be judged by.
//
// Every figure is computed over the faces that belong to a chart (chart_of_face >= 0); a face of
// no chart is only counted, in dropped_faces. Per triangle, J is the Jacobian of the affine map
// from the 3D triangle (laid flat in its own frame) to its UV triangle, sigma1 >= sigma2 its
// singular values.
//
//   flipped_triangles   per chart, the triangles of the minority orientation (by count) plus the
//                       zero-area ones, summed over the charts. Orientation is the exact sign of
//                       the UV triangle (planar/exact_orientation.h); zero area means exactly zero
//                       or within what rounding its corners could change
//                       (planar/uv_layout_checks.h; this includes atlaseval's floating-point test
//                       for an area of exactly 0).
//   mirrored_charts     charts with more clockwise than counter-clockwise triangles.
//   overlapping_texels  texels whose centre lies strictly inside triangles of two or more charts,
//                       at resolution x resolution; coverage: texel centres strictly inside some
//                       triangle / resolution^2. Both rasterized with atlaseval's own expressions
//                       in texel units, so that they give the same count to the texel.
//   boundary_crossings  pairs of chart-boundary edges (edges of the UV layout used by one face,
//                       the UV layout having one UV per chart, vertex and position; see
//                       atlas_uv_layout) that cross properly: each edge has the other's ends
//                       strictly on opposite sides. Touching, collinear overlap and edges sharing a
//                       UV do not count. Exact orientation signs; both between charts and within a
//                       chart.
//   l2_stretch          Sander et al. (2001) L2 stretch of the map UV -> surface with every chart
//                       scaled so that its UV area equals its 3D area (1 for an isometry).
//   angle_distortion    3D-area-weighted mean of sigma1 / sigma2.
//   area_distortion     3D-area-weighted mean |log(UV area / 3D area)| with ONE scale for the
//                       whole atlas (atlaseval's area_global): how uniform the texel density is
//                       across the charts. Each chart's own area_distortion uses the chart's own
//                       scale instead (atlaseval's area): how much the flattening changes areas
//                       within the chart.
//   pages               an atlas of several pages (TextureAtlas::pages) is measured page by page:
//                       texels overlap and boundaries cross only between charts of one page, and
//                       coverage is over all pages' texels (page_coverage: each page's own).
//   texels_per_unit     sqrt(total UV area in texels^2 / total 3D area): the root-mean-square
//                       texel density (the packing's exact density when every chart is isometric).
//
// The distortion means leave out a triangle with zero 3D area, zero-area UVs or sigma2 = 0 (its
// ratios are unbounded), as atlaseval does; zero-area UV triangles are those counted as such above.

#include <string>

#include <Eigen/Core>

#include "harmonia/mesh.h"
#include "harmonia/texture_atlas.h"

namespace harmonia::detail {

//! The atlas' corners indexed as an OBJ file stores them: one UV row per distinct (chart, vertex,
//! UV position) in order of first use by the faces in input order, so that the faces of one chart
//! share a UV at a vertex where their corners agree (and only there).
struct AtlasUvLayout {
  Eigen::MatrixX2d uv;        //!< #UV by 2 (at most 3 #F rows), in atlas units as corner_uv.
  Eigen::MatrixX3i uv_faces;  //!< #F by 3 rows of uv.
};

//! Empty when `atlas` fits `mesh`: chart_of_face and corner_uv have one row per face, every chart
//! id is a chart of atlas.charts or -1 (no chart), every chart lists exactly its faces, the
//! resolution is 1..32768 and the faces' vertex indices are in range. Otherwise the first problem
//! found, naming the face or chart.
[[nodiscard]] std::string atlas_mismatch(const Mesh& mesh, const TextureAtlas& atlas);

//! The layout of an atlas that fits the mesh (atlas_mismatch is empty).
[[nodiscard]] AtlasUvLayout atlas_uv_layout(const Mesh& mesh, const TextureAtlas& atlas);

//! Measures `atlas` over `mesh` (see the top of this file). Fills each chart's l2_stretch,
//! angle_distortion, area_distortion (with the chart's own scale) and surface_area (its 3D area);
//! a chart with no measurable triangle keeps 1, 1 and 0. Returns the whole atlas' figures, for the
//! caller to store in atlas.metrics (and whose texels_per_unit it may replace with its packing's
//! exact density). Throws Error(invalid_input) with atlas_mismatch's message when the atlas does
//! not fit the mesh.
[[nodiscard]] AtlasMetrics measure_atlas(const Mesh& mesh, TextureAtlas& atlas);

}  // namespace harmonia::detail
