// The Laplacian family of thesis chapter 4: scheme names, the per-edge symmetric schemes (uniform,
// chord length, cotangent), the per-triangle mean value weights, and the dispatch to the ring-based
// schemes (laplacian_ring_schemes.cpp). Every operator is accumulated into one precomputed sparsity
// pattern (detail::AdjacencyPattern): O(F) work, no triplet sort, deterministic summation order.

#include "harmonia/laplacian.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "harmonia/types.h"
#include "mesh/adjacency_pattern.h"
#include "mesh/power_of_two_scale.h"
#include "operators/ring_weights.h"

namespace harmonia {
namespace {

constexpr WeightScheme every_scheme[] = {
    WeightScheme::uniform,          WeightScheme::chord_length,
    WeightScheme::mean_value,       WeightScheme::cotangent,
    WeightScheme::linear_precision, WeightScheme::least_squares,
    WeightScheme::least_squares_positive, WeightScheme::shape_preserving};

void check_finite_vertices(const Mesh& mesh) {
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    if (!mesh.vertices.row(v).allFinite()) {
      throw Error(Status::invalid_input,
                  "laplacian: vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
  }
}

// The power of two that brings vectors whose largest coordinate is `largest` into the safe range
// (1 inside it): lengths, dot and cross products of the scaled vectors neither underflow (a model
// in units of 1e-100) nor overflow (1e200), and scale-free quantities (angles, cotangents) come out
// exactly as for the model at unit size.
double safe_scale(double largest) { return detail::safe_range_scale_for(largest); }

// |d| without underflow or overflow of its square; the same bits as d.norm() in the safe range.
double safe_length(const Eigen::Vector3d& d) {
  const double scale = safe_scale(d.cwiseAbs().maxCoeff());
  return scale == 1.0 ? d.norm() : (d * scale).norm() / scale;
}

// Edge-based schemes: one weight per undirected edge, a function of the edge alone. The pattern
// already lists every edge once per column, so the weight is written straight into column c.
template <typename EdgeWeight>
void assemble_edge_scheme(const Mesh& mesh, detail::AdjacencyPattern& pattern, EdgeWeight weight) {
  for (int col = 0; col < pattern.vertex_count(); ++col) {
    for (const int* row = pattern.column_begin(col); row != pattern.column_end(col); ++row) {
      if (*row != col) pattern.add(*row, col, -weight(mesh.vertices.row(*row), mesh.vertices.row(col)));
    }
  }
}

// Cotangent weights (4.41), assembled per triangle: each triangle adds cot(theta_k)/2 to the edge
// opposite its corner k, so an interior edge sums (cot a + cot b)/2 over its two opposite angles and
// a boundary edge gets its single angle.
// `face_weights`, when given, multiplies each triangle's contributions (the scalar
// quasi-harmonic operator, face_weighted_laplacian).
void assemble_cotangent(const Mesh& mesh, detail::AdjacencyPattern& pattern,
                        const Eigen::VectorXd* face_weights = nullptr) {
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3i corner = mesh.faces.row(f);
    Eigen::Vector3d half_cot = cotangent_half_weights(
        mesh.vertices.row(corner[0]), mesh.vertices.row(corner[1]), mesh.vertices.row(corner[2]));
    if (face_weights != nullptr) half_cot *= (*face_weights)[f];
    for (int k = 0; k < 3; ++k) {
      const int i = corner[(k + 1) % 3], j = corner[(k + 2) % 3];
      pattern.add(i, j, -half_cot[k]);
      pattern.add(j, i, -half_cot[k]);
    }
  }
}

// Mean value weights (4.25), per triangle: the wedge of triangle (i, j, k) at i with 3D angle gamma
// contributes tan(gamma/2) / |p_j - p_i| to w_ij and tan(gamma/2) / |p_k - p_i| to w_ik. Summing over
// the fan gives (tan(a/2) + tan(b/2)) / r_ij for the two wedges beside edge ij. tan(gamma/2) is
// evaluated as |u x v| / (|u||v| + u.v), exact for small angles. A zero-area triangle contributes
// nothing. `rows`, when given, restricts the assembly to the flagged rows; `face_weights`
// multiplies each triangle's wedges (the scalar quasi-harmonic operator, 7.2).
void assemble_mean_value(const Mesh& mesh, detail::AdjacencyPattern& pattern,
                         const std::vector<bool>* rows,
                         const Eigen::VectorXd* face_weights = nullptr) {
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const double face_weight = face_weights != nullptr ? (*face_weights)[f] : 1.0;
    for (int k = 0; k < 3; ++k) {
      const int i = mesh.faces(f, k), j = mesh.faces(f, (k + 1) % 3), l = mesh.faces(f, (k + 2) % 3);
      if (rows != nullptr && !(*rows)[static_cast<std::size_t>(i)]) continue;
      Eigen::Vector3d u = mesh.vertices.row(j) - mesh.vertices.row(i);
      Eigen::Vector3d v = mesh.vertices.row(l) - mesh.vertices.row(i);
      // The wedge scaled into the safe range: tan(gamma/2) does not change, 1/|u| gains the scale.
      const double scale = safe_scale(std::max(u.cwiseAbs().maxCoeff(), v.cwiseAbs().maxCoeff()));
      if (scale != 1.0) {
        u *= scale;
        v *= scale;
      }
      const double sine_part = u.cross(v).norm();
      if (sine_part == 0.0) continue;
      const double tan_half = face_weight * sine_part / (u.norm() * v.norm() + u.dot(v));
      pattern.add(i, j, -tan_half * scale / u.norm());
      pattern.add(i, l, -tan_half * scale / v.norm());
    }
  }
}

// How a ring scheme's weights change with the model's size: as length^degree (4.47 is scale-free;
// the second-order conditions 4.58-4.59 make the least squares weights go as 1/length^2; Floater's
// convex combinations are scale-free).
int ring_scheme_degree(WeightScheme scheme) {
  switch (scheme) {
    case WeightScheme::least_squares:
    case WeightScheme::least_squares_positive: return -2;
    default: return 0;
  }
}

// The ring schemes flatten each 1-ring with lengths, angles and moments that underflow or overflow
// far from unit size, so they are computed on the copy of unit size (power_of_two_scale.h), and each
// row goes back to the model's units by its degree: the ring scheme's, or -1 for a row that fell
// back to mean value weights. Power-of-two scaling is exact, so a model of ordinary size gets the
// same bits as if computed where it is.
Eigen::SparseMatrix<double> ring_scheme_laplacian(const Mesh& mesh, WeightScheme scheme,
                                                  detail::AdjacencyPattern& pattern) {
  const detail::ScaledMesh unit = detail::unit_scaled(mesh);
  const std::vector<bool> mean_value_rows =
      detail::assemble_ring_scheme(unit.mesh, scheme, pattern);
  assemble_mean_value(unit.mesh, pattern, &mean_value_rows);
  pattern.set_diagonal_from_rows();
  Eigen::SparseMatrix<double> matrix = pattern.take_matrix();
  if (unit.scale == 1.0) return matrix;
  // A weight of degree d on the unit copy is the model's times scale^d: multiply by scale -d times
  // (one factor at a time, so that scale^2 cannot overflow where the weight itself does not).
  const int ring_degree = ring_scheme_degree(scheme);
  for (Eigen::Index column = 0; column < matrix.outerSize(); ++column) {
    for (Eigen::SparseMatrix<double>::InnerIterator entry(matrix, column); entry; ++entry) {
      const bool mean_value_row = mean_value_rows[static_cast<std::size_t>(entry.row())];
      for (int k = 0; k < -(mean_value_row ? -1 : ring_degree); ++k) entry.valueRef() *= unit.scale;
    }
  }
  return matrix;
}

}  // namespace

std::span<const WeightScheme> all_weight_schemes() { return every_scheme; }

std::string_view to_string(WeightScheme scheme) {
  switch (scheme) {
    case WeightScheme::uniform: return "uniform";
    case WeightScheme::chord_length: return "chord";
    case WeightScheme::mean_value: return "mean-value";
    case WeightScheme::cotangent: return "cotangent";
    case WeightScheme::linear_precision: return "linear-precision";
    case WeightScheme::least_squares: return "least-squares";
    case WeightScheme::least_squares_positive: return "least-squares-positive";
    case WeightScheme::shape_preserving: return "shape-preserving";
  }
  return "unknown";
}

std::optional<WeightScheme> weight_scheme_from_string(std::string_view name) {
  for (const WeightScheme scheme : every_scheme)
    if (to_string(scheme) == name) return scheme;
  return std::nullopt;
}

bool has_positive_weights(WeightScheme scheme) {
  switch (scheme) {
    case WeightScheme::uniform:
    case WeightScheme::chord_length:
    case WeightScheme::mean_value:
    case WeightScheme::least_squares_positive:
    case WeightScheme::shape_preserving: return true;
    case WeightScheme::cotangent:
    case WeightScheme::linear_precision:
    case WeightScheme::least_squares: return false;
  }
  return false;
}

bool is_symmetric(WeightScheme scheme) {
  switch (scheme) {
    case WeightScheme::uniform:
    case WeightScheme::chord_length:
    case WeightScheme::cotangent: return true;
    case WeightScheme::mean_value:
    case WeightScheme::linear_precision:
    case WeightScheme::least_squares:
    case WeightScheme::least_squares_positive:
    case WeightScheme::shape_preserving: return false;
  }
  return false;
}

Eigen::Vector3d cotangent_half_weights(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  // cot(theta) = (u . v) / |u x v| for the two edges u, v leaving the corner. |u x v| = 2 * area is
  // the same at every corner; a zero-area triangle gets zero weights rather than infinities.
  // Cotangents do not depend on the triangle's size, so legs outside the safe range are scaled by
  // a power of two first: no underflow of |u x v| at 1e-100, no overflow at 1e200.
  Eigen::Vector3d ab = b - a, bc = c - b, ca = a - c;
  const double scale = safe_scale(
      std::max({ab.cwiseAbs().maxCoeff(), bc.cwiseAbs().maxCoeff(), ca.cwiseAbs().maxCoeff()}));
  if (scale != 1.0) {
    ab *= scale;
    bc *= scale;
    ca *= scale;
  }
  const double twice_area = ab.cross(-ca).norm();
  if (twice_area == 0.0) return Eigen::Vector3d::Zero();
  const double half_over_twice_area = 0.5 / twice_area;
  return Eigen::Vector3d(ab.dot(-ca), bc.dot(-ab), ca.dot(-bc)) * half_over_twice_area;
}

Eigen::SparseMatrix<double> laplacian(const Mesh& mesh, WeightScheme scheme) {
  check_finite_vertices(mesh);
  detail::AdjacencyPattern pattern(mesh.faces, mesh.vertex_count());
  switch (scheme) {
    case WeightScheme::uniform:  // finite difference (4.14): every neighbour counts once
      assemble_edge_scheme(mesh, pattern, [](const auto&, const auto&) { return 1.0; });
      break;
    case WeightScheme::chord_length:  // (4.21): w = 1 / r_ij; a zero-length edge gets weight 0
      assemble_edge_scheme(mesh, pattern, [](const auto& p, const auto& q) {
        const double length = safe_length(p - q);
        return length > 0.0 ? 1.0 / length : 0.0;
      });
      break;
    case WeightScheme::cotangent:
      assemble_cotangent(mesh, pattern);
      break;
    case WeightScheme::mean_value:
      assemble_mean_value(mesh, pattern, nullptr);
      break;
    case WeightScheme::linear_precision:
    case WeightScheme::least_squares:
    case WeightScheme::least_squares_positive:
    case WeightScheme::shape_preserving:
      return ring_scheme_laplacian(mesh, scheme, pattern);
  }
  pattern.set_diagonal_from_rows();
  return pattern.take_matrix();
}

Eigen::SparseMatrix<double> face_weighted_laplacian(const Mesh& mesh, WeightScheme scheme,
                                                    const Eigen::VectorXd& face_weights) {
  check_finite_vertices(mesh);
  if (face_weights.size() != mesh.faces.rows())
    throw Error(Status::invalid_input, "face_weighted_laplacian: " +
                                           std::to_string(face_weights.size()) + " weights for " +
                                           std::to_string(mesh.faces.rows()) + " faces");
  for (Eigen::Index f = 0; f < face_weights.size(); ++f) {
    if (!(face_weights[f] >= 0.0) || !std::isfinite(face_weights[f]))
      throw Error(Status::invalid_input, "face_weighted_laplacian: the weight of face " +
                                             std::to_string(f) + " is not a finite number >= 0");
  }
  detail::AdjacencyPattern pattern(mesh.faces, mesh.vertex_count());
  switch (scheme) {
    case WeightScheme::cotangent:
      assemble_cotangent(mesh, pattern, &face_weights);
      break;
    case WeightScheme::mean_value:
      assemble_mean_value(mesh, pattern, nullptr, &face_weights);
      break;
    default:
      throw Error(Status::invalid_input,
                  "face_weighted_laplacian: only the per-triangle schemes cotangent and mean-value "
                  "take face weights, not " + std::string(to_string(scheme)));
  }
  pattern.set_diagonal_from_rows();
  return pattern.take_matrix();
}

}  // namespace harmonia
