#pragma once
//! \file gradient.h
//! \brief Per-triangle gradient of piecewise-linear functions and the divergence back to vertices:
//! the Poisson right-hand side div F from a fragmented (per-triangle) target (thesis 6.2.2).

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace harmonia {

//! Triangle areas, #F. positions: #V by 2 or #V by 3.
[[nodiscard]] Eigen::VectorXd triangle_areas(const Eigen::MatrixXd& positions, const Eigen::MatrixX3i& faces);

//! Gradient operator G of P1 functions: (d*#F) by #V, where d = positions.cols() (2 or 3); rows
//! d*f .. d*f+d-1 hold the gradient of the function on face f (in 3D, within the face's plane).
//! A zero-area face has zero gradient rows. Positions with another column count, or a face index out
//! of range, throw harmonia::Error(invalid_input) (all functions of this header).
[[nodiscard]] Eigen::SparseMatrix<double> gradient_operator(const Eigen::MatrixXd& positions,
                                                            const Eigen::MatrixX3i& faces);

//! Divergence of a per-triangle vector field, integrated over each vertex's dual cell:
//! div = G^T * diag(area) * field, #V. field: (d*#F), same layout as gradient_operator's rows.
//! With the cotangent Laplacian L (PSD convention) L = G^T diag(area) G, so L u = div(grad u).
[[nodiscard]] Eigen::VectorXd divergence(const Eigen::MatrixXd& positions, const Eigen::MatrixX3i& faces,
                                         const Eigen::VectorXd& field);

//! Poisson right-hand side from a fragmented mesh: each triangle f carries its own target
//! coordinates fragments.row(3*f + k) for corner k (#F*3 by m, any m, e.g. m = 2 for u and v).
//! Returns b (#V by m) with b = sum over triangles of the triangle's cotangent stiffness applied to
//! its own fragment coordinates, summed at shared vertices: the "Laplacian of the fragmented mesh,
//! gathered by the original connectivity". Solving L x = b (L = cotangent operator on `positions`)
//! gives the map whose gradients best match the fragments' gradients in the least-squares sense.
[[nodiscard]] Eigen::MatrixXd fragment_poisson_rhs(const Eigen::MatrixXd& positions,
                                                   const Eigen::MatrixX3i& faces,
                                                   const Eigen::MatrixXd& fragments);

}  // namespace harmonia
