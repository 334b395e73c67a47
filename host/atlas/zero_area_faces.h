#pragma once
// Internal: the faces of zero area (FaceGeometry::degenerate) drawn inside a neighbouring chart.
//
// Such a face covers none of the surface (a UV sphere's pole ring, where an exporter repeated the
// pole once per column; a needle whose corners are collinear), so no texel of the texture is
// ever seen through it. A chart of its own for each would only cost room and padding in the
// atlas; dropping it would leave a face without UVs. Instead each such face that shares a vertex
// with a face of area (its host) is drawn as a small triangle strictly inside the host's layout,
// in the host's chart: its corners where their points fall on the host (the closest point of
// the host to each), pulled a little towards the host's interior so that the triangle has the
// host's orientation and a positive area. It then crosses no boundary, overlaps no other chart
// and keeps the packing as it was. A face of zero area touching none of area keeps a chart of its
// own (texture_atlas). Several faces in one host each take a triangle of their own out of it
// (triangles that touch at corners only), so that they do not cross each other either.

#include <vector>

#include "atlas/chart_flattening.h"
#include "atlas/face_geometry.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

// Per face of `surface`: for a degenerate face, the face of area it is drawn in (sharing the most
// of its vertices, then the largest, then the lowest rank: the same for any face order), or -1
// where it touches none; -1 for every face of area.
[[nodiscard]] std::vector<int> zero_area_hosts(const Mesh& surface, const FaceGeometry& geometry);

// Adds every face with a host to the chart holding that host, as described above. `charts` hold
// every face of area (their layouts final: call after the packing, which they leave unchanged).
void draw_inside_hosts(const Mesh& surface, const FaceGeometry& geometry, const std::vector<int>& host_of_face,
                       std::vector<FinishedChart>& charts);

}  // namespace harmonia::detail
