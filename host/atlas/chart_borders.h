#pragma once
// Internal: where the charts of a texture atlas meet, and the tests that a join of two
// neighbouring charts must pass whatever else it asks (flat_fold_merge.h joins across flat folds,
// stretch_bounded_join.h where the union flattens within the stretch limit).
//
// Both joins save a seam only where it is worth having and the union still packs as its parts
// did: a common border of one path (two disks make a disk, never an annulus) at least
// kLeastBorderShare of the shorter perimeter, the union about as compact as its parts
// (kCompactnessKept), and its normals within a cone of their mean, so that it stays a height
// field over one plane as the segmentation's charts are.

#include <map>
#include <utility>
#include <vector>

#include "atlas/face_geometry.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

//! The least share of the shorter perimeter of two charts that their common border must be for
//! them to join: a quarter of a square's perimeter (one side of a box against its neighbour) is
//! more, a single edge between two charts of dozens of faces is less.
inline constexpr double kLeastBorderShare = 0.2;

//! The least share of its parts' isoperimetric ratio (4 pi area / perimeter^2, their mean
//! weighted by area) that the union of two charts must keep to join: two squares side by side
//! (8/9 of a square's) keep enough; an L or a hook, which packs worse than its parts, does not.
inline constexpr double kCompactnessKept = 0.85;

//! The edges where two charts meet across an edge the segmentation may cross.
struct ChartBorder {
  double length = 0.0;
  std::vector<std::pair<int, int>> edges;  //!< Their vertex pairs.
};

//! The charts of a face labelling, as the joins see them.
struct ChartAdjacency {
  //! Per pair of neighbouring charts (the lower number first), their common border.
  std::map<std::pair<int, int>, ChartBorder> borders;
  std::vector<double> perimeter;  //!< Per chart: the length of its boundary.
  std::vector<double> area;       //!< Per chart: its 3D area.
};

//! The adjacency of charts 0 .. chart_count - 1, chart_of_face[f] the chart of face f of `mesh`
//! (-1: none).
[[nodiscard]] ChartAdjacency chart_adjacency(const Mesh& mesh, const FaceGeometry& geometry,
                                             const std::vector<int>& chart_of_face, int chart_count);

//! The pairs of neighbouring charts, longest common border first; ties by `rank` (per chart, a
//! rank that does not depend on the face order), the pair's lower rank first, then its higher.
[[nodiscard]] std::vector<std::pair<int, int>> pairs_longest_border_first(const ChartAdjacency& adjacency,
                                                                        const std::vector<int>& rank);

//! Whether charts a and b, neighbours, share a border worth a seam (kLeastBorderShare) and make a
//! union about as compact as they are (kCompactnessKept).
[[nodiscard]] bool border_worth_joining(const ChartAdjacency& adjacency, int a, int b);

//! The same for a join along only `joined_length` of their common border, the rest of it cut (a
//! seam inside the union, on its boundary twice).
[[nodiscard]] bool border_worth_joining(const ChartAdjacency& adjacency, int a, int b, double joined_length);

//! Whether the border's edges form one simple path (not a cycle, not several pieces).
[[nodiscard]] bool is_one_path(const ChartBorder& border);

//! Whether the normals of all `faces` lie within the cone of half-angle acos(cone_cosine) around
//! their area-weighted mean.
[[nodiscard]] bool normals_within_cone(const FaceGeometry& geometry, const std::vector<int>& faces, double cone_cosine);

}  // namespace harmonia::detail
