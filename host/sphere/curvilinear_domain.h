#pragma once
// Internal: the disk on which a spherical map is computed in curvilinear coordinates (thesis 7.1).
//
// The closed mesh is cut open along the date line (the shortest edge path from the north pole to
// the south pole, harmonia::cut_to_disk) and both poles are removed with their faces. What is left
// is a disk whose boundary runs around the north pole's ring, down one side of the date line,
// around the south pole's ring and up the other side. It is mapped onto a rectangle of longitude
// theta in [0, 2 pi] and Mercator latitude psi = ln cot(phi / 2) (phi the polar angle, 0 at the
// north pole); the plane (theta, psi) keeps the orientation of the surface seen from outside, east
// to the right and north up.
//
// Why psi and not phi itself, as the thesis writes: theta and psi are the sphere's conformal
// coordinates, both harmonic on the sphere without its poles, so the harmonic map of a sphere onto
// the (theta, psi) rectangle is the sphere itself (up to the discretization), while in (theta, phi)
// it is not (phi is not harmonic); and a triangle keeps its shape through the lift, where in
// (theta, phi) the lift squeezes longitudes by sin phi.
//
// Boundary conditions, with the date line scaled to length pi (a meridian of the unit sphere):
// - the pole rings: theta spaced as the angles between the ring's edges at the pole (the ring as
//   the pole sees it); phi = the ring's mean distance from its pole at that scale (where it would
//   be on a sphere), at least pole_margin;
// - the date line's two sides: theta = 0 on the side that follows the north ring in the boundary
//   loop (the loop runs counter-clockwise around the disk), theta = 2 pi on the other; phi from the
//   north ring's to the south ring's in proportion to the path's length.
// Both copies of a date-line vertex get the same phi and theta 0 and 2 pi: the same point of the
// sphere. The rectangle is convex, so positive weights give an embedding (Tutte); an edge joining
// two vertices of one side would be a chord of that side, which a shortest path cannot have and a
// pole ring has only where the mesh has a separating triangle through the pole.

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
  Eigen::MatrixX2d boundary_plane;   //!< Their (theta, psi).
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
