#pragma once
// Internal: the greedy (breadth-first) reconstruction of UVs from corner angles (thesis section 3.3);
// see angle_reconstruction_greedy.cpp.

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia::detail {

//! UVs (#V x 2) laid out face by face from the corner angles: the first face containing
//! `start_vertex` with that vertex at the origin and its next corner at (1, 0), every further face
//! (breadth-first across edges) from its edge already placed. `angles` must be valid (#F x 3,
//! finite, in (0, pi)) and the mesh a disk (connected, consistently oriented).
[[nodiscard]] Eigen::MatrixX2d greedy_layout(const Mesh& mesh, const Eigen::MatrixX3d& angles,
                                             int start_vertex);

}  // namespace harmonia::detail
