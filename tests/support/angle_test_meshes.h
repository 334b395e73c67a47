#pragma once
// Small meshes for the angle-based methods (ABF, linear ABF, angles to UVs), shared by their tests.
// Header-only so that each test executable gets exactly what it uses.

#include <algorithm>
#include <cmath>
#include <complex>
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

// Largest distance between `uv` and the best similarity image of `reference` (complex least
// squares uv ~ a z + b), relative to the reference's bounding box.
inline double similarity_misfit(const Eigen::MatrixX2d& uv, const Eigen::MatrixX2d& reference) {
  using Complex = std::complex<double>;
  const Eigen::Index n = uv.rows();
  Complex mean_z = 0.0, mean_w = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    mean_z += Complex(reference(i, 0), reference(i, 1));
    mean_w += Complex(uv(i, 0), uv(i, 1));
  }
  mean_z /= static_cast<double>(n);
  mean_w /= static_cast<double>(n);
  Complex numerator = 0.0;
  double denominator = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Complex z = Complex(reference(i, 0), reference(i, 1)) - mean_z;
    const Complex w = Complex(uv(i, 0), uv(i, 1)) - mean_w;
    numerator += std::conj(z) * w;
    denominator += std::norm(z);
  }
  const Complex scale = numerator / denominator;
  double worst = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Complex z = Complex(reference(i, 0), reference(i, 1)) - mean_z;
    const Complex w = Complex(uv(i, 0), uv(i, 1)) - mean_w;
    worst = std::max(worst, std::abs(scale * z - w) / std::abs(scale));
  }
  const double extent = (reference.colwise().maxCoeff() - reference.colwise().minCoeff()).maxCoeff();
  return worst / extent;
}

// A long strip wound one and a quarter times around an axis and rising slowly along it (a thin
// piece of a helicoid, "alpha"-shaped as in thesis figure 2.2): nearly developable, so its
// angle-preserving flattening is nearly the planar spiral, whose ends overlap.
inline Mesh wound_strip(int segments = 80, double turns = 1.25) {
  const int rows = 3;  // Radii 1, 1.15, 1.3: the middle row is interior.
  Mesh mesh;
  mesh.vertices.resize((segments + 1) * rows, 3);
  for (int s = 0; s <= segments; ++s) {
    const double theta = 2.0 * std::numbers::pi * turns * s / segments;
    for (int r = 0; r < rows; ++r) {
      const double radius = 1.0 + 0.15 * r;
      mesh.vertices.row(s * rows + r) << radius * std::cos(theta), radius * std::sin(theta),
          0.04 * theta;
    }
  }
  mesh.faces.resize(2 * segments * (rows - 1), 3);
  int f = 0;
  for (int s = 0; s < segments; ++s)
    for (int r = 0; r + 1 < rows; ++r) {
      const int a = s * rows + r, b = a + 1, c = a + rows, d = c + 1;
      mesh.faces.row(f++) << a, c, d;
      mesh.faces.row(f++) << a, d, b;
    }
  return mesh;
}

}  // namespace harmonia::testing
