#pragma once
// Internal: tangential Laplacian relaxation on the sphere (thesis 7.3, and the baseline of figure
// 7.9).
//
// One step moves every movable vertex x_i by the tangential part of its Laplacian
// L(x_i) = sum_j w_ij (x_j - x_i) / sum_j w_ij (w: the mean value weights of the 3D mesh, positive,
// so L(x_i) points into the convex hull of the neighbours),
//   x_i += L(x_i) - <L(x_i), x_i> x_i,
// and projects it back onto the sphere, x_i /= |x_i|; all vertices move at once (a Jacobi step),
// so the result does not depend on the vertex order.
//
// `keep_valid`: a step may turn a triangle over. Then the vertices of every triangle that the step
// turned over (positive before, not after; exact orientation, sphere_orientation.h) go back to
// where they were, and the check repeats until no triangle turns over: a valid map stays valid.

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace harmonia::detail {

struct RelaxationOutcome {
  int moved_vertices = 0;  //!< Vertices that moved in at least one step.
  int held_back = 0;       //!< Vertex moves undone because they turned a triangle over.
};

//! `weights`: a Laplacian of the mesh (laplacian.h convention: off-diagonal -w_ij), e.g. its mean
//! value one; `movable`: #V flags; `points`: #V by 3 on the unit sphere, updated in place.
[[nodiscard]] RelaxationOutcome relax_on_sphere(const Eigen::SparseMatrix<double>& weights,
                                                const Eigen::MatrixX3i& faces,
                                                const std::vector<char>& movable, int steps,
                                                bool keep_valid, Eigen::MatrixX3d& points);

//! The vertices within `rings` edges of `seeds` (rings = 0: the seeds themselves), as #V flags.
[[nodiscard]] std::vector<char> vertices_within_rings(const Eigen::MatrixX3i& faces,
                                                      int vertex_count,
                                                      const std::vector<int>& seeds, int rings);

}  // namespace harmonia::detail
