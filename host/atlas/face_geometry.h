#pragma once
// Internal: what the segmentation of a texture atlas needs to know about each face: its unit
// normal, area and centroid, the faces across its edges, and a rank that orders the faces by
// position, so that every tie the segmentation breaks is broken the same way whatever the order
// of the faces in the file.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia::detail {

struct FaceGeometry {
  std::vector<Eigen::Vector3d> normal;    // unit; zero for a degenerate face
  std::vector<Eigen::Vector3d> centroid;
  std::vector<double> area;
  std::vector<std::array<double, 3>> edge_length;  // edge k: from corner k to corner k+1
  // Per face and edge k (from corner k to corner k+1): the face across it, or -1 where the edge
  // is a boundary, is shared by more than two faces, or joins two faces of opposite orientation.
  // A chart never grows across such an edge, so that every chart is manifold and oriented.
  std::vector<std::array<int, 3>> across;
  // Faces with no normal: zero area, or an area below what the rounding of their corners allows
  // (|cross product| <= 16 eps |e1| |e2|, relative to the face itself, so at any scale), and
  // faces too small to keep an area on the grid below. Each becomes a chart of its own.
  std::vector<char> degenerate;
  // Position of each face in the order of (centroid x, y, z, area, index): a tie-break that does
  // not depend on the face order unless two faces share centroid and area.
  std::vector<int> rank;

  [[nodiscard]] int face_count() const { return static_cast<int>(area.size()); }
};

// `mesh` should be normalized to its size (texture_atlas does that). The normals, areas, lengths,
// centroids and ranks come from its vertices snapped to a grid of 2^-30: a mesh and the same mesh
// scaled (whose normalized coordinates differ in their last bits) then give the same figures to
// the bit, so the same ties and the same charts; the grid is far finer than any decision the
// segmentation takes. Only `degenerate` is decided on the exact coordinates, relative to each face.
// Computed on `threads` threads (the same figures for any count).
[[nodiscard]] FaceGeometry face_geometry(const Mesh& mesh, int threads = 1);

}  // namespace harmonia::detail
