#pragma once
// Small meshes with known topology, built in code, for the topology, cleanup and cut tests.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia::testing {

//! Mesh from explicit lists.
Mesh make_mesh(const std::vector<std::array<double, 3>>& vertices,
               const std::vector<std::array<int, 3>>& faces);

//! Regular tetrahedron, outward (V 4, E 6, F 4).
Mesh tetrahedron();
//! Octahedron with vertices at the unit axis points, outward (V 6, E 12, F 8).
Mesh octahedron();
//! Square grid [0, n] x [0, m] in the z = 0 plane, two triangles per cell, counter-clockwise from
//! +z. Vertex (i, j) has index j * (n + 1) + i.
Mesh grid_disk(int n, int m);
//! Planar annulus 1 <= r <= 2 with `around` vertices per circle and `rings` + 1 circles, inner
//! circle first (indices 0 .. around-1), counter-clockwise from +z. Two boundary loops.
Mesh annulus(int around, int rings);
//! Torus of radii 2 and 0.5 on an nu x nv grid (periodic both ways), outward. Genus 1.
Mesh torus(int nu, int nv);
//! The closed surface of a slab of nx x ny x 1 unit voxels with one-voxel holes at the given
//! (i, j) cells (interior, not touching each other): genus = number of holes. Outward.
Mesh voxel_slab(int nx, int ny, const std::vector<std::array<int, 2>>& holes);
//! Moebius strip with `segments` quads along the band (non-orientable, one boundary loop).
Mesh moebius_strip(int segments);
//! Squares given by their corners (counter-clockwise seen from outside), each split into two
//! triangles (corners 0 1 2 and 0 2 3); corners at one position (within 1e-12) are one vertex.
Mesh squares(const std::vector<std::array<Eigen::Vector3d, 4>>& corners);
//! The same squares each made of four triangles around its centre (corners k, k + 1, centre), the
//! centre of square i raised by tents[i] along its outward normal: a developable square for a
//! tent of 0, one with a cone of curvature at its centre otherwise.
Mesh tented_squares(const std::vector<std::array<Eigen::Vector3d, 4>>& corners, const std::vector<double>& tents);
//! The cube [-1, 1]^3 with each side an n x n grid of quads, each split into two triangles,
//! counter-clockwise seen from outside.
Mesh grid_cube(int n);
//! The mesh without the listed faces (indices into mesh.faces).
Mesh without_faces(const Mesh& mesh, const std::vector<int>& removed);

}  // namespace harmonia::testing
