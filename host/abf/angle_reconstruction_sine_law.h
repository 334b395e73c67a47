#pragma once
// Internal: how a triangle's planar angles fix its shape (thesis section 3.3, [SLMB05]).
//
// For a counter-clockwise triangle with corners (i, j, k) and angles (a_i, a_j, a_k), the edge
// i->k is the edge i->j turned counter-clockwise by a_i and scaled by the sine law
// |ik| / |ij| = sin a_j / sin a_k. In complex numbers:
//   p_k - p_i = (sin a_j / sin a_k) e^{i a_i} (p_j - p_i).
// Both reconstructions use this relation: greedy places p_k from a placed edge (i, j), least
// squares asks it of every triangle at once.

#include <cmath>
#include <complex>

#include <Eigen/Core>

namespace harmonia::detail {

//! The relation above for one face: `placed` is the corner k whose position it predicts, `anchor`
//! the corner i where the edge turns, `along` the corner j (corner numbers 0..2 of the face, in
//! its counter-clockwise order i -> j -> k), and `factor` the complex multiplier.
struct SineLawRelation {
  int placed = 0;
  int anchor = 1;
  int along = 2;
  std::complex<double> factor;
};

//! The relation of a face (its three angles, in face corner order) that predicts corner `placed`.
[[nodiscard]] inline SineLawRelation sine_law_relation(const Eigen::Vector3d& face_angles,
                                                       int placed) {
  SineLawRelation relation;
  relation.placed = placed;
  relation.anchor = (placed + 1) % 3;
  relation.along = (placed + 2) % 3;
  const double ratio = std::sin(face_angles[relation.along]) / std::sin(face_angles[placed]);
  relation.factor = std::polar(ratio, face_angles[relation.anchor]);
  return relation;
}

//! The corner whose angle has the largest sine (the first one on ties): dividing by it keeps the
//! sine-law ratio at most 1, so no relation of a face amplifies the error of its angles.
[[nodiscard]] inline int largest_sine_corner(const Eigen::Vector3d& face_angles) {
  int best = 0;
  for (int corner = 1; corner < 3; ++corner)
    if (std::sin(face_angles[corner]) > std::sin(face_angles[best])) best = corner;
  return best;
}

}  // namespace harmonia::detail
