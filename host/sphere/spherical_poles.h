#pragma once
// Internal: the poles of a spherical map (thesis 7.1, 7.4).
//
// The thesis leaves the poles to the user and asks that they be far enough apart for the surface
// to unfold between them. Chosen automatically they are the two ends of a geodesic diameter of the
// edge graph (Euclidean edge lengths), found by a double sweep: from a start vertex the farthest
// vertex A, from A the farthest vertex B. A is the north pole, B the south pole. The start is the
// vertex farthest from the centroid of the vertices, so the choice depends on the shape alone and
// not on the order of the vertices in the file; exact ties (symmetric shapes) go to the
// lexicographically smallest position, which is order-independent too.

#include <array>
#include <string>

#include "harmonia/mesh.h"

namespace harmonia::detail {

//! The ends of the double sweep described above, north first. `mesh` is connected.
[[nodiscard]] std::array<int, 2> automatic_poles(const Mesh& mesh);

//! Empty when the poles can be used: in range, distinct, and at least three edges apart (the
//! rectangle's top and bottom, the poles' rings, must not share a vertex); otherwise one sentence
//! saying why not.
[[nodiscard]] std::string pole_problem(const Mesh& mesh, const std::array<int, 2>& poles);

}  // namespace harmonia::detail
