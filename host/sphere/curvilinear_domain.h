#pragma once
// Internal: the disk on which a spherical map is computed in curvilinear coordinates (thesis 7.1).
//
// The closed mesh is cut open along the date line (the shortest edge path from the north pole to
// the south pole, harmonia::cut_to_disk) and both poles are removed with their faces. What is left
// is a disk whose boundary runs around the north pole's ring, down one side of the date line,
// around the south pole's ring and up the other side. It is mapped onto the rectangle of
// longitude theta in [0, 2 pi] and latitude lambda = pi/2 - phi in [-(pi/2 - eps), pi/2 - eps]
// (phi the polar angle): the plane coordinates (theta, lambda) keep the orientation of the surface
// seen from outside, east to the right and north up.
//
// Boundary conditions:
// - the date line's two sides: theta = 0 on the side that follows the north ring in the boundary
//   loop (the loop runs counter-clockwise around the disk), theta = 2 pi on the other; phi grows
//   from eps at the north ring to pi - eps at the south ring in proportion to the path's length;
// - the pole rings: theta spaced as the angles between the ring's edges at the pole (the ring as
//   the pole sees it), phi = eps (north) or pi - eps (south), bulged by eps/2 sin(theta/2) toward
//   the pole. The bulge makes the rectangle's top and bottom strictly convex, so that an edge
//   joining two vertices of one ring (a chord of the ring) is no edge of a straight side, which
//   Tutte's theorem forbids; the corners keep phi = eps, and the pole fan stays inside phi < eps.
// Both copies of a date-line vertex get the same phi and theta 0 and 2 pi: the same point of the
// sphere.

#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia::detail {

struct CurvilinearDomain {
  Mesh disk;                         //!< The cut mesh without the poles.
  std::vector<int> original_vertex;  //!< Per disk vertex: the input vertex it is (or copies).
  std::vector<int> original_face;    //!< Per disk face: the input face.
  std::vector<int> date_line;        //!< Input vertices from the north pole to the south pole.
  Eigen::VectorXi boundary;          //!< The disk's boundary vertices, in loop order.
  Eigen::MatrixX2d boundary_plane;   //!< Their (theta, lambda).
};

//! The domain for the given poles (pole_problem() empty). Throws harmonia::Error(numerical_failure)
//! if the cut does not give the disk described above (a bug, not an input problem).
[[nodiscard]] CurvilinearDomain curvilinear_domain(const Mesh& mesh, int north, int south,
                                                   double pole_margin);

//! (theta, phi) of plane coordinates (theta, psi).
[[nodiscard]] Eigen::MatrixX2d polar_angles(const Eigen::MatrixX2d& plane);
//! The Mercator latitude psi = ln cot(phi / 2) of the polar angle phi, and back.
[[nodiscard]] double mercator_latitude(double phi);
[[nodiscard]] double polar_angle(double psi);

}  // namespace harmonia::detail
