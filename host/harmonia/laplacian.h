#pragma once
//! \file laplacian.h
//! \brief The Laplacian family of thesis chapter 4: one sparse operator per weight scheme.
//!
//! Every scheme produces weights w_ij > or < 0 on the directed edges i->j of the 1-ring; the
//! operator is L with L(i,j) = -w_ij and L(i,i) = sum_j w_ij (positive semi-definite convention:
//! L applied to a constant is zero, and for symmetric schemes L is symmetric PSD). Schemes that are
//! defined per vertex ring (mean value, linear precision, least squares, shape preserving) give a
//! non-symmetric L; a Dirichlet map then needs an LU-type solve.
//!
//! Ring-based schemes that need planar coordinates of the 1-ring flatten it by the exponential map
//! (edge lengths kept, angles at the centre scaled to sum to 2 pi; Floater's shape-preserving
//! construction). For boundary vertices the open fan is flattened without scaling.
//!
//! Rows that a scheme does not define get mean value weights (positive, finite): boundary rows of
//! least_squares_positive and shape_preserving (the centre of an open fan is not strictly inside its
//! ring, so no positive linear-precision weights exist), interior rows where the flattened ring
//! admits no positive solution (an angular gap >= pi), and non-manifold vertices (several fans).
//! linear_precision and least_squares use their formulas on the open fan of boundary vertices.
//! Fixed-boundary maps replace boundary rows anyway. A triangle of zero area contributes nothing to
//! the per-triangle schemes (cotangent, mean value); an unused vertex has an empty row.
//!
//! Errors: a face index out of range or a non-finite coordinate throws harmonia::Error with
//! Status::invalid_input and a message naming the face or vertex.

#include <optional>
#include <span>
#include <string_view>

#include <Eigen/SparseCore>

#include "harmonia/mesh.h"

namespace harmonia {

enum class WeightScheme {
  uniform,                 //!< Finite difference (4.14): w = 1.
  chord_length,            //!< Chord-length Laplacian (4.21): w = 1 / |p_i - p_j|.
  mean_value,              //!< Floater's mean value weights (4.25): (tan(a/2)+tan(b/2)) / r_ij.
  cotangent,               //!< Finite element linear triangle (4.41): (cot a + cot b) / 2.
  linear_precision,        //!< Holmes-Connell linearity-preserving weights (4.47).
  least_squares,           //!< Five Taylor conditions (4.56-4.60), least-norm for valence < 5.
  least_squares_positive,  //!< Same conditions with w > 0 enforced (4.61 and the program after).
  shape_preserving,        //!< Floater's shape-preserving (convex-combination) weights.
};

//! Every scheme, in the order of the enum (for loops over schemes and for listing them).
[[nodiscard]] std::span<const WeightScheme> all_weight_schemes();

//! Canonical CLI spelling: "uniform", "chord", "mean-value", "cotangent", "linear-precision",
//! "least-squares", "least-squares-positive", "shape-preserving".
[[nodiscard]] std::string_view to_string(WeightScheme scheme);
[[nodiscard]] std::optional<WeightScheme> weight_scheme_from_string(std::string_view name);
//! True for schemes whose weights are positive on every mesh (uniform, chord, mean value, shape
//! preserving, least squares positive): with a convex boundary Tutte's theorem guarantees no flips.
[[nodiscard]] bool has_positive_weights(WeightScheme scheme);
//! True for schemes whose L is symmetric (uniform, chord, cotangent).
[[nodiscard]] bool is_symmetric(WeightScheme scheme);

//! The #V by #V operator described above, for the 3D mesh `mesh` (rows of every vertex, boundary
//! ones included). Column-major, compressed, deterministic (same input -> same bits).
[[nodiscard]] Eigen::SparseMatrix<double> laplacian(const Mesh& mesh, WeightScheme scheme);

//! The scalar quasi-harmonic operator div(kappa grad) on the surface (thesis 7.2): the cotangent
//! or mean value weights of `mesh` with every triangle's contributions multiplied by its weight
//! kappa_T (face_weights, #F, finite and >= 0): the cotangent edge weight becomes
//! (kappa_1 cot a + kappa_2 cot b) / 2 and the mean value one
//! (kappa_1 tan(a/2) + kappa_2 tan(b/2)) / r_ij, the two triangles beside the edge weighted by
//! their own kappa. All weights 1 give laplacian(mesh, scheme) bit for bit. Other schemes, a
//! weight count other than #F or a negative or non-finite weight throw
//! harmonia::Error(invalid_input).
[[nodiscard]] Eigen::SparseMatrix<double> face_weighted_laplacian(
    const Mesh& mesh, WeightScheme scheme, const Eigen::VectorXd& face_weights);

//! Cotangent weights of one triangle: half the cotangent of the angle at each corner, i.e.
//! entry k is the weight of the edge opposite corner k (cot(theta_k)/2). Planar corners are passed
//! with z = 0. A zero-area triangle gives zeros.
[[nodiscard]] Eigen::Vector3d cotangent_half_weights(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                     const Eigen::Vector3d& c);

}  // namespace harmonia
