#pragma once
// Internal: one chart of a texture atlas as a mesh of its own, and what makes it a disk.
//
// The chart's faces keep their corners, but a vertex of the surface becomes one chart vertex per
// fan of chart faces around it (faces joined across edges the segmentation may cross,
// FaceGeometry::across): a chart that touches itself at a vertex, or whose faces meet at an edge
// it may not cross, is cut apart there rather than glued. So a chart mesh is always manifold and
// consistently oriented, and it is a disk exactly when it is connected with Euler characteristic 1
// and one boundary loop.

#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "atlas/face_geometry.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

struct ChartMesh {
  Mesh mesh;                       // the chart's faces over its own vertices
  std::vector<int> surface_vertex; // per chart vertex: the vertex of the surface it copies
  std::vector<int> surface_face;   // per chart face: the face of the surface, in increasing order
};

// An edge of the surface by its two vertices, the lower first.
using SurfaceEdge = std::pair<int, int>;

// `faces`: faces of `surface` (any order; none degenerate). The chart is also cut apart along
// `cuts`: edges of the surface that its faces may not share.
[[nodiscard]] ChartMesh chart_mesh(const Mesh& surface, const FaceGeometry& geometry,
                                   std::vector<int> faces, const std::set<SurfaceEdge>& cuts = {});

// A chart with holes (connected, genus 0, several boundary loops: a chart around islands of
// other charts) cut open into a disk: each hole joined to the outer boundary (the longest loop),
// or to a hole already joined, by the shortest path through the chart's interior, and the chart
// cut along those paths. Nothing for a chart that is not of that kind (a handle: split it).
[[nodiscard]] std::optional<ChartMesh> cut_holes_open(const Mesh& surface, const FaceGeometry& geometry,
                                                      const ChartMesh& chart);

// The chart mesh of a face set, cut open around its holes (cut_holes_open) where that makes it a
// disk.
[[nodiscard]] ChartMesh opened_chart(const Mesh& surface, const FaceGeometry& geometry,
                                     const std::vector<int>& faces);

// Connected, one boundary loop, Euler characteristic 1.
[[nodiscard]] bool is_disk(const ChartMesh& chart);

// Splits the faces of a chart into two connected halves: the faces nearer (in steps across
// edges) to one of two faces far apart than to the other; ties go by rank. Both halves are
// non-empty when the chart has two faces or more.
[[nodiscard]] std::vector<std::vector<int>> split_in_two(const FaceGeometry& geometry,
                                                         const std::vector<int>& faces);

// The same split around two given faces of the chart (surface face indices in `faces`, distinct):
// the faces nearer to `first` (ties included) and those nearer to `second`.
[[nodiscard]] std::vector<std::vector<int>> split_between(const FaceGeometry& geometry,
                                                          const std::vector<int>& faces, int first,
                                                          int second);

}  // namespace harmonia::detail
