#pragma once
//! \file procedural.h
//! \brief Meshes built in code: the demo's default input and the analytic test cases.

#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

//! Upper unit hemisphere (z >= 0), a disk: `rings` rings of latitude between pole and equator,
//! ring k (1-based) has 6k vertices (so triangles stay near-equilateral). Vertex 0 is the pole.
//! Boundary = the equator. Faces counter-clockwise seen from outside.
[[nodiscard]] Mesh hemisphere(int rings);

//! Planar triangulated disk of radius 1 in the z = 0 plane with `rings` rings (same layout as
//! hemisphere), slightly perturbed interior vertices when `jitter` > 0 (deterministic).
[[nodiscard]] Mesh planar_disk(int rings, double jitter = 0.0);

//! A developable strip: a rectangle [0, length] x [0, width] triangulated on an nu x nv grid and
//! rolled onto a cylinder of radius `radius` (x -> angle). Isometric to its flat rectangle.
[[nodiscard]] Mesh developable_strip(int nu, int nv, double length, double width, double radius);

//! The demo's built-in input: a wavy "mountain" cap over a disk (a height field with several bumps),
//! about 2*rings^2*3 faces; deliberately far from developable so the maps differ visibly.
[[nodiscard]] Mesh demo_surface(int rings = 40);

//! The unit sphere as a subdivided icosahedron: 20 * 4^subdivisions faces (subdivisions in
//! [0, 8]), every vertex on the sphere, faces counter-clockwise seen from outside.
[[nodiscard]] Mesh unit_sphere(int subdivisions);

//! unit_sphere(subdivisions) with long thin tentacles: the vertices within `cap_angle` radians of
//! each of `directions` are pulled out along it into a tube of about the cap's radius that reaches
//! `length` beyond the sphere and closes at its tip. The directions must be more than 2 cap_angle
//! apart; cap_angle in (0, 1). A closed genus-0 mesh whose harmonic maps squash each tentacle
//! exponentially in its length-to-radius ratio.
[[nodiscard]] Mesh tentacle_sphere(int subdivisions, const std::vector<Eigen::Vector3d>& directions,
                                   double length, double cap_angle);

}  // namespace harmonia
