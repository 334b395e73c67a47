#pragma once
// Internal: the element stiffness of one triangle under a 2x2 tensor, the building block of the
// tensor-cotangent operator (quasi_harmonic_operator.h) and of the fragment loads of the
// free-boundary maps (planar/fragment_targets.h).

#include <Eigen/Core>

namespace harmonia::detail {

//! The stiffness integrals of (C grad phi_a) . grad phi_b over the uv triangle `corner` for the
//! pairs (a, a + 1), a = 0, 1, 2: the off-diagonal entries S_ab of its element matrix (-w_ab, eq.
//! 5.10). e_k, the uv edge opposite corner k, gives the hat function of corner k the gradient
//! e_k^perp / (2 A) (section 5.3), hence the entry (e_a^perp)^T C e_b^perp / (4 A). Only the
//! symmetric part of C enters the energy (5.7). A zero-area uv triangle gives zeros.
[[nodiscard]] Eigen::Vector3d tensor_cotangent_pair_stiffness(const Eigen::MatrixX2d& uv,
                                                              const Eigen::Vector3i& corner,
                                                              const Eigen::Matrix2d& tensor);

}  // namespace harmonia::detail
