#pragma once
// Small meshes for the angle-based methods (ABF, linear ABF, angles to UVs), shared by their tests.
// Header-only so that each test executable gets exactly what it uses.

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "harmonia/mesh.h"
#include "harmonia/procedural.h"

namespace harmonia::testing {

//! The thesis' "obtuse" example (figure 3.3): three long triangles closing a fan around one
//! interior vertex (vertex 0) raised above its boundary triangle and outside it. Its central
//! angles sum to far less than 2 pi (angular deficit about 4.56 rad, as in the thesis), which makes
//! the linear conformal maps (LSCM / DNCP) fold a triangle, while ABF and linear ABF stay valid.
//! Vertices 1, 2, 3 form the boundary (counter-clockwise seen from above).
inline Mesh obtuse_fan() {
  Mesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 1.5, 1.0, 0.8,  // The apex: raised, outside the base triangle.
      0.0, 0.0, 0.0,                 //
      1.0, 0.0, 0.0,                 //
      0.5, 0.866025403784438597, 0.0;
  mesh.faces.resize(3, 3);
  mesh.faces << 0, 1, 2,  //
      0, 2, 3,            //
      0, 3, 1;
  return mesh;
}

//! A planar disk (procedural planar_disk with jittered interior vertices, so that its angles are
//! irregular) placed in a tilted plane of 3D space: its own angles are a valid flattening, so an
//! angle-based method must return them, and a UV layout similar to the mesh itself.
inline Mesh tilted_planar_disk(int rings = 6, double jitter = 0.3) {
  Mesh mesh = planar_disk(rings, jitter);
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 0.5).normalized())).toRotationMatrix();
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    mesh.vertices.row(v) =
        (2.5 * rotation * Eigen::Vector3d(mesh.vertices.row(v)) + Eigen::Vector3d(1.0, -2.0, 0.5))
            .transpose();
  return mesh;
}

//! The same planar disk as laid out in its own plane (the z = 0 plane, the UVs an angle-based method
//! should reproduce up to a similarity).
inline Eigen::MatrixX2d planar_disk_layout(int rings = 6, double jitter = 0.3) {
  return planar_disk(rings, jitter).vertices.leftCols<2>();
}

//! A planar disk whose interior vertex nearest the centre is lifted into a sharp spike of height
//! `height`: a large angular deficit at one vertex of an otherwise flat mesh.
inline Mesh spiked_disk(int rings = 5, double height = 1.5) {
  Mesh mesh = planar_disk(rings, 0.15);
  mesh.vertices(0, 2) = height;  // Vertex 0 is the centre (planar_disk's layout).
  return mesh;
}

//! A non-developable, curved disk: the unit hemisphere.
inline Mesh test_hemisphere(int rings = 8) { return hemisphere(rings); }

//! A closed surface (not a disk): a tetrahedron.
inline Mesh tetrahedron() {
  Mesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  mesh.faces.resize(4, 3);
  mesh.faces << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return mesh;
}

}  // namespace harmonia::testing
