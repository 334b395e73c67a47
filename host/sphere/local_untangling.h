#pragma once
// Internal: untangling the triangles a spherical map turned over, one vertex at a time.
//
// The lift of a valid map of the rectangle onto the sphere can still turn a triangle over: its
// edges are straight in (theta, phi), but on the sphere the triangle is the chord triangle of its
// corners, whose edges are great circles, and a wide, flat triangle of a squashed region (a
// latitude circle is no great circle) can have its chord pass beyond its third corner.
//
// Around one vertex the sphere has a chart in which this cannot happen: the central (gnomonic)
// projection onto the tangent plane at the vertex maps great circles to straight lines, and
// det[a, b, c] of three sphere points has the sign of the planar orientation of their projections.
// In that chart each triangle (v, a, b) around v faces outward exactly when v lies to the left of
// the line a -> b; the set of such positions, the kernel of v's ring, is a convex polygon. A vertex
// whose kernel is not empty moves to the kernel's centroid: every triangle around it then faces
// outward, and no other triangle changes. A vertex whose kernel is empty moves to the point that is
// farthest inside the worst of its triangles (a small linear program), if that is better than
// where it is and turns no more of its triangles over. Each pass visits the vertices of the turned
// triangles, and of the rings around them when a pass made no progress (neighbours that move to
// their kernels' centroids make room), in the order of their 3D positions (not of their indices),
// until no turned triangle is left or nothing helps. The result never has more turned triangles
// than the input.

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia::detail {

struct UntanglingOutcome {
  int turned_before = 0;  //!< Triangles turned over or degenerate on entry.
  int turned_after = 0;   //!< ... and on return.
  int moved_vertices = 0;
  int passes = 0;
};

//! `points`: #V by 3 unit-sphere points of the mesh's vertices, updated in place.
[[nodiscard]] UntanglingOutcome untangle_on_sphere(const Mesh& mesh, int max_passes,
                                                   Eigen::MatrixX3d& points);

}  // namespace harmonia::detail
