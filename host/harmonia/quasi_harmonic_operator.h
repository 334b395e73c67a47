#pragma once
//! \file quasi_harmonic_operator.h
//! \brief The quasi-harmonic operator div(C grad f) of thesis chapter 5 on a planar map.
//!
//! For a current map uv of a 3D mesh, each triangle's first fundamental form I = J^T J (J the 3x2
//! Jacobian of uv -> 3D) gives K = sqrt(I) (closed form for a 2x2 SPD matrix, eq. 5.5) and the
//! tensor C = K^-1 (eq. 5.7). Discretized over the centroid dual (eq. 5.10) the edge weight reduces
//! to the cotangent weight when C = identity.

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "harmonia/mesh.h"

namespace harmonia {

//! Per-triangle 2x2 symmetric tensors, stored row-wise: #F by 4 with (C00, C01, C10, C11).
using TriangleTensors = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>;

//! Closed-form square root of a 2x2 symmetric positive definite matrix (the unique SPD root).
[[nodiscard]] Eigen::Matrix2d spd_sqrt(const Eigen::Matrix2d& m);

//! First fundamental form per triangle of the map uv -> mesh.vertices (#F by 4 row-wise 2x2).
//! A triangle with zero uv area gets a non-finite form; callers check with `all_finite`.
[[nodiscard]] TriangleTensors first_fundamental_forms(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! C = (sqrt(I))^-1 per triangle (eq. 5.5-5.7): the conductance tensor of the quasi-harmonic map.
[[nodiscard]] TriangleTensors quasi_harmonic_tensors(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! Scalar special case: one kappa per triangle (C = kappa * Id), e.g. the ratio of uv area to 3D area.
//! Returns the tensors kappa*Id for use with the functions below.
[[nodiscard]] TriangleTensors scalar_tensors(const Eigen::VectorXd& kappa);

//! Tensor-cotangent operator (eq. 5.10): #V by #V, symmetric, PSD convention as in laplacian.h.
//! uv: #V by 2 current map; faces: #F by 3; tensors: #F rows (their symmetric part is used).
//! Per triangle the stiffness is (e_a^perp)^T C e_b^perp / (4 A) with e_k the uv edge opposite corner
//! k and A the unsigned uv area; a zero-area uv triangle contributes nothing. A tensor count that
//! differs from the face count, or a face index out of range, throws harmonia::Error(invalid_input).
[[nodiscard]] Eigen::SparseMatrix<double> tensor_cotangent_laplacian(const Eigen::MatrixX2d& uv,
                                                                     const Eigen::MatrixX3i& faces,
                                                                     const TriangleTensors& tensors);

//! Poisson right-hand side of the quasi-harmonic equation div(C grad u) = div(C grad F) for a
//! fragmented target (thesis eq. 6.4): each triangle f carries its own corner coordinates
//! fragments.row(3*f + k) (#F*3 by m). Returns b (#V by m), each triangle's stiffness under its
//! tensor (as in tensor_cotangent_laplacian on `uv`) applied to its fragment and summed at the
//! shared vertices. With L the tensor-cotangent operator, L x = b gives the map whose gradients
//! best match the fragments' gradients in the C-weighted least-squares sense; when the fragments
//! are the triangles of uv itself, x = uv. Same errors as above, and a fragment row count other
//! than 3 * #F throws harmonia::Error(invalid_input).
[[nodiscard]] Eigen::MatrixXd tensor_fragment_poisson_rhs(const Eigen::MatrixX2d& uv,
                                                          const Eigen::MatrixX3i& faces,
                                                          const TriangleTensors& tensors,
                                                          const Eigen::MatrixXd& fragments);

//! Tensor mean-value operator (thesis section 5.4): positive weights for any triangle shapes and any
//! SPD tensors, non-symmetric. Same shapes, convention and errors. The wedge of triangle (i, j, k) at
//! i (angle g) adds to w_ij  [(a + 2b) tan(g/2) + 2c sin^2 g + (a - b) sin g cos g] / (3 |u_j - u_i|)
//! with a = e^T C e, b = f^T C f, c = e^T C f in the frame e along u_k - u_i, f across towards u_j
//! (derivation in the source); for C = Id these are the mean value weights (4.25) of the uv layout.
[[nodiscard]] Eigen::SparseMatrix<double> tensor_mean_value_laplacian(const Eigen::MatrixX2d& uv,
                                                                      const Eigen::MatrixX3i& faces,
                                                                      const TriangleTensors& tensors);

}  // namespace harmonia
