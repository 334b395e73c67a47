#pragma once
// Internal: the Poisson load of a fragmented mesh on the CPU (thesis 6.2.2): every face's element
// stiffness S_f applied to its own fragment F_f, gathered at the shared vertices, sum_f S_f F_f.
// The CPU backend's fragment right-hand side (fallback/cpu_triangle_operators.h) gathers the
// cotangent stiffness of the surface with it; the free-boundary map gathers the tensor-cotangent
// stiffness of its quasi-harmonic step (planar/fragment_targets.h), for which no device kernel
// exists.
//
// Row a of S F is the sum over b != a of S_ab (F_b - F_a), since an element matrix's rows sum to
// zero. The faces are split in two fixed halves summed on two threads, and the halves added:
// deterministic, whatever the timing.

#include <Eigen/Core>

namespace harmonia::detail {

//! Per face, the element stiffness entries S_ab of its pairs (0, 1), (1, 2), (2, 0).
using PairStiffness = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

//! The cotangent stiffness (4.41) of the triangles of the surface with these positions (#V x 3):
//! S_ab = -cot(angle opposite a, b) / 2; zeros for a zero-area triangle.
[[nodiscard]] PairStiffness cotangent_pair_stiffness(const Eigen::MatrixX3d& positions,
                                                     const Eigen::MatrixX3i& faces);

//! sum_f S_f F_f (#V x m), with fragments.row(3 f + k) the target of corner k of face f
//! (3 #F x m) and `stiffness` one row per face.
[[nodiscard]] Eigen::MatrixXd gather_fragment_load(const Eigen::MatrixX3i& faces, int vertex_count,
                                                   const PairStiffness& stiffness,
                                                   const Eigen::MatrixXd& fragments);

}  // namespace harmonia::detail
