#pragma once
// Internal: the quadratic form of the least-squares conformal energy (host/planar/lscm.cpp).

#include <vector>

#include <Eigen/SparseCore>

#include "harmonia/mesh.h"

namespace harmonia::detail {

//! Q (2V by 2V, unknowns u_0..u_{V-1} then v_0..v_{V-1}) with x^T Q x = sum over the triangles T of
//! area_T |grad u + rot90(grad v)|^2, where a triangle with zero 3D area carries no energy.
//! Assembled as [L N; N^T L]: L the cotangent Laplacian (the Dirichlet energies of u and v) and N
//! the coupling of twice the signed layout area, which the interior edges cancel from, so it
//! lives on the boundary `loop` (mesh to its left) and around zero-area triangles only.
[[nodiscard]] Eigen::SparseMatrix<double> lscm_quadratic_form(const Mesh& mesh,
                                                              const std::vector<int>& loop);

}  // namespace harmonia::detail
