#pragma once
//! \file texture_atlas.h
//! \brief Texture atlas of any triangle mesh: the surface cut into charts that are topological
//! disks, each chart flattened without a fold and with its faces' orientation, and the charts
//! packed into one square texture at one texel density.
//!
//!   1. Segmentation (host/atlas/chart_segmentation.h): charts grown over the faces by how far a
//!      face's normal turns from its chart's mean normal, with a compactness term, in rounds of
//!      re-seeding (variational shape approximation with normal proxies); seams fall along the
//!      creases. Scale-invariant, deterministic and independent of the face order.
//!   2. Topology: a planar chart with holes (a plate around a bore, a wall around a window) is laid
//!      out as it lies, by projection onto its plane; a chart with holes that is not planar has
//!      them cut open; any other chart that is not a disk (a band around a limb, a bowtie at a
//!      non-manifold vertex) is split in two, and again, until every chart is a disk.
//!   3. Flattening, best method first: linear ABF, then the free-boundary quasi-harmonic map, then
//!      a Tutte embedding with mean-value weights on a convex boundary (valid by construction). A
//!      result with a flipped or zero-area triangle, a boundary that crosses itself, or an L2
//!      stretch above max_distortion is refused; a chart that no method flattens within the limit
//!      is split in two and each half tried again (a single triangle always flattens exactly). A
//!      linear ABF layout whose only fault is a boundary crossing itself is cut between two
//!      boundary edges that cross, each piece keeping its part of the layout where that is valid
//!      and within the limit. Every chart keeps the orientation of its 3D faces (no mirrored
//!      chart).
//!   4. Packing (host/atlas/chart_packing.h): every chart scaled to one texel density, turned to
//!      its tightest bounding box, and placed into a resolution x resolution (or x height) atlas with `padding`
//!      texels between charts, at the largest density for which everything fits. Charts too long
//!      for the square (longer than the side of a square their area would fill) are also cut
//!      across their length, keeping their layouts, and the cut set is kept if it packs denser.
//!
//! No face is dropped: a face of zero 3D area becomes a chart of its own, drawn as a small
//! triangle of positive area.
//!
//! \code
//!   harmonia::TextureAtlasOptions options;
//!   options.resolution = 2048;
//!   const harmonia::TextureAtlas atlas = harmonia::texture_atlas(mesh, options);
//!   if (atlas.report.ok()) harmonia::write_atlas_obj("out.obj", mesh, atlas);
//! \endcode

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"
#include "harmonia/types.h"

namespace harmonia {

struct TextureAtlasOptions {
  //! The atlas is resolution x resolution texels (16..32768), or resolution wide and `height`
  //! high when `height` is not 0 (a non-square atlas, 16..32768 too).
  int resolution = 1024;
  int height = 0;
  //! Empty texels kept between two charts, so that texture filtering and mip-mapping do not
  //! bleed one chart into the next (0..64). Half of them, rounded up, are kept between a chart
  //! and each edge of the atlas: a texture sampled with wrapping (glTF's default) continues
  //! across the edge, where two charts then stay `padding` apart too.
  int padding = 2;
  //! The largest Sander L2 stretch a chart may keep (each chart scaled to its own 3D area; 1 is an
  //! isometry). A chart above it is split. Must be > 1. The default keeps every chart within
  //! 0.25 % of an isometry: smaller charts pack as tightly as large ones (they fill the gaps), so
  //! it costs little coverage, and the atlas' stretch stays below xatlas's on the closed corpus,
  //! its 16x subdivisions and real assets. Measured: at 1.01, elephant x16 came out at 1.0037
  //! against xatlas's 1.0030 (at 1.006, 1.0026); at 1.006, suzanne.ply (a low-polygon head of
  //! 968 faces, curved everywhere) at 1.0016 against xatlas's 1.0011 (at 1.0025, 1.0010, with
  //! 76 charts to xatlas's 143), for a few more charts elsewhere (rabbit.obj 42 to 48, xatlas
  //! 39; cow 111 to 121, xatlas 107) and at most 0.02 of coverage.
  double max_distortion = 1.0025;
  //! 0 (the default): the densest packing that fits one atlas. Greater: exactly this many texels
  //! per unit of the model's length, the same for every mesh made at it (a lightmap's texel
  //! density); charts that do not fit one atlas of the resolution at it go on further ones, the
  //! atlas' pages (see max_pages). Must be finite and not negative.
  double texels_per_unit = 0.0;
  //! With texels_per_unit: the most pages the atlas may have, 0 (the default) for as many as the
  //! charts need; a mesh whose charts do not fit that many is refused (invalid_input: a larger
  //! resolution, or a smaller density, makes room), as is one with a chart larger than a page.
  //! Each chart is on one page (AtlasChart::page), its UVs over that page's square. Not negative.
  int max_pages = 0;
  //! Segmentation: the most a face's normal may turn from its chart's mean normal, in degrees
  //! (1..89). Smaller: more, flatter charts.
  double max_normal_deviation_degrees = 60.0;
  //! Charts follow the surface the mesh describes, not its file's splits: vertices at one point
  //! (within kCoincidentVertexTolerance of the model's largest side, transitively) are one point
  //! while the atlas is made, so a chart may span a seam or hard edge where an exporter split the
  //! vertices, and both sides of such a split get the same UVs. An edge of that welded surface
  //! held by more than two faces, or by two faces of opposite orientation, is a chart boundary.
  //! With keep_splits, every split of the file is a chart boundary too (the file's seams kept).
  bool keep_splits = false;
  //! After the flattening, neighbouring charts whose union flattens within max_distortion become
  //! one chart (the union flattened afresh), round after round while any pair does: fewer charts
  //! and seams, at the price of some coverage (larger charts leave larger gaps to pack) and time
  //! (a flattening per pair tried). Off by default; docs/methods.md has the figures.
  bool join_charts = false;
  //! Worker threads for the flattening of the charts (0: one per core). Each chart's solve runs
  //! on its worker alone (no helper threads beside it), so the flattening uses this many threads.
  int threads = 0;
  //! The backend of the flattening's linear algebra. On a device (BackendChoice::vulkan, or
  //! automatic on a hardware GPU) the first linear ABF round of every chart is solved in one
  //! batch per wave of charts (block-diagonal PCG, one block per chart), the rest of each chart's
  //! work on the CPU; on the CPU backend each chart is factorized directly on its worker thread.
  //! `automatic` looks for a device only for a mesh of kSmallestAtlasForDevice faces or more.
  SolverOptions solver;
};

//! Below this many faces, BackendChoice::automatic flattens on the CPU without looking for a
//! device: finding one and starting it takes longer (0.26 s on a machine with only a software
//! driver, the same order to start a GPU) than the whole atlas of such a mesh on the CPU (0.1 s
//! at 4K faces), and its charts are too few to fill a batch. The report's backend_notice says so.
inline constexpr long kSmallestAtlasForDevice = 50000;

//! Vertices closer than this, relative to the model's largest bounding-box side, are one point of
//! the surface an atlas charts (TextureAtlasOptions::keep_splits): 2^-24, about float32's
//! relative precision, so vertices an exporter split and wrote from one float position are one
//! point, and no two vertices a mesh means apart (its edges are far longer) are.
inline constexpr double kCoincidentVertexTolerance = 0x1p-24;

//! How a chart was flattened.
enum class ChartMethod {
  single_triangle,  //!< One face, laid out isometrically.
  linear_abf,       //!< Linear angle based flattening.
  //! Linear ABF's layout relaxed toward an isometry (the boundary-free step 6.2 repeated from it,
  //! each fragment in its own triangle's frame): less stretch, a little more angle distortion.
  relaxed_linear_abf,
  free_boundary,    //!< The free-boundary quasi-harmonic map.
  tutte,            //!< Mean-value weights on a convex boundary (the fall-back of last resort).
  degenerate,       //!< A face of zero 3D area, drawn as a small valid triangle.
  input_layout,     //!< The input's own UVs, kept as they are (repack_texture_atlas).
  projection,       //!< A chart with holes over a plane, projected onto it (no cut needed).
};
[[nodiscard]] std::string_view to_string(ChartMethod method);

struct AtlasChart {
  std::vector<int> faces;  //!< The chart's faces, in input order.
  ChartMethod method = ChartMethod::single_triangle;
  //! A piece of a larger chart that was cut apart (its layout crossed or touched its own
  //! boundary, or it was too long for the square), keeping its part of that chart's layout by
  //! `method` instead of a solve of its own.
  bool piece_of_a_cut = false;
  //! The page it is on (0 unless TextureAtlas::pages > 1): its UVs are over that page's square.
  int page = 0;
  //! Distortion of the chart's flattening (each chart scaled to its own 3D area): Sander L2
  //! stretch, 3D-area-weighted mean conformal ratio sigma1/sigma2, mean |log area ratio|.
  double l2_stretch = 1.0;
  double angle_distortion = 1.0;
  double area_distortion = 0.0;
  double surface_area = 0.0;  //!< The chart's 3D area.
  //! Its bounding box in the atlas, in texels (x right, y up from the atlas' bottom-left corner).
  Eigen::AlignedBox2d texel_box;
};

//! Quality of the whole atlas (the figures atlaseval.py computes, measured in the library).
struct AtlasMetrics {
  int charts = 0;
  int faces = 0;
  //! Per chart, the triangles of the minority orientation, plus the zero-area ones (a mirrored
  //! chart's triangles count as a mirrored chart, not as flips).
  int flipped_triangles = 0;
  int mirrored_charts = 0;          //!< Charts whose faces are mostly clockwise.
  int overlapping_texels = 0;       //!< Texel centres inside triangles of two charts of one page.
  int boundary_crossings = 0;       //!< Crossing pairs of chart-boundary edges in UV.
  int dropped_faces = 0;            //!< Faces left out of every chart (0: none is dropped).
  //! Texel centres covered by a triangle / (pages x the atlas' texels); and the same per page.
  double coverage = 0.0;
  std::vector<double> page_coverage;
  double texels_per_unit = 0.0;     //!< Texels per unit of 3D length (one density for all).
  double l2_stretch = 1.0;          //!< Sander L2 over the atlas, each chart scaled to its area.
  double angle_distortion = 1.0;    //!< 3D-area-weighted mean sigma1/sigma2.
  double area_distortion = 0.0;     //!< 3D-area-weighted mean |log(uv area / 3D area)|, one scale.
};

struct TextureAtlas {
  std::vector<AtlasChart> charts;
  std::vector<int> chart_of_face;  //!< #F: the chart of each face.
  //! #F by 6: per face the UVs of its three corners (u0 v0 u1 v1 u2 v2), in [0, 1] over the atlas,
  //! v up (OBJ's convention). Texel (x, y) covers [x, x+1] / resolution x [y, y+1] / height_texels().
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv;
  int resolution = 0;  //!< The atlas' width in texels.
  int height = 0;      //!< Its height in texels; 0: as wide as high.
  [[nodiscard]] int height_texels() const { return height > 0 ? height : resolution; }
  //! The atlases of resolution x height texels the charts are on (1 unless a texel density
  //! was asked for and the charts did not fit one).
  int pages = 1;
  //! Vertices that were one point with an earlier one (TextureAtlasOptions::keep_splits): the
  //! file's splits the charts could span.
  int welded_vertices = 0;
  AtlasMetrics metrics;
  //! status ok, or invalid_input for a mesh the atlas cannot take (the message names the face or
  //! vertex); timings per phase (segmentation, flattening, packing, metrics).
  SolveReport report;
};

[[nodiscard]] TextureAtlas texture_atlas(const Mesh& mesh, const TextureAtlasOptions& options = {});

//! The page of each face's chart (#F; -1 for a face in no chart), or nothing for an atlas of one
//! page.
[[nodiscard]] std::vector<int> page_of_face(const TextureAtlas& atlas);

//! The atlas of a mesh that has UVs already, keeping its charts: a repack. The charts are the
//! input's own (faces joined across an edge whose two ends carry the same vertex and the same UV
//! in both faces; every seam of the input a chart boundary), each laid out as it is, only scaled
//! to the one texel density of the atlas and moved, turned by quarter turns at most: for an asset
//! whose UVs are good but spread over several squares, tiled or at uneven densities, or a
//! lightmap set made from a texture set. Nothing is flattened or cut, so what the input's layout
//! holds (flips, overlaps within a chart, mirrored charts) the atlas' metrics report as it is.
//! `corner_uv`: #F by 6, per face u0 v0 u1 v1 u2 v2 (any range: tiling is undone chart by chart).
//! Of the options, resolution, height, padding, texels_per_unit, max_pages and threads apply. invalid_input for a
//! corner_uv of the wrong size or not finite (naming the face), and as texture_atlas.
[[nodiscard]] TextureAtlas repack_texture_atlas(const Mesh& mesh, const Eigen::Matrix<double, Eigen::Dynamic, 6>& corner_uv,
                                                const TextureAtlasOptions& options = {});

}  // namespace harmonia
