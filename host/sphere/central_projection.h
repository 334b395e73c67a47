#pragma once
// Internal: the spherical map of a mesh too coarse for curvilinear coordinates, by central
// projection.
//
// The thesis' construction (7.1) removes the two poles and maps the disk left between their rings
// onto a rectangle, so the rings must not share a vertex: the poles must be at least three edges
// apart. The simplest closed meshes (a tetrahedron, a cube or box of 12 triangles, low-poly props
// and collision hulls) have no such pair. For them, a mesh that is star-shaped about a point c
// (every face's plane has c strictly on its inner side) maps bijectively onto the sphere by
// central projection p -> (p - c) / |p - c|: each face then sees c on its inner side, so its chord
// triangle turns counter-clockwise seen from outside, and triangles that all face outward on a
// closed genus-0 mesh cover the sphere once (the degree of the map is 1). The centres tried are
// the centroid of the solid the mesh bounds, the centroid of its vertices and the centre of its
// bounding box; the projection is kept only when every chord triangle is found positively
// oriented by the exact predicate (sphere_orientation.h), so a kept map is valid by construction
// and by check.

#include <array>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia::detail {

struct CentralProjection {
  Eigen::MatrixX3d points;     // #V by 3, unit vectors, the north pole at +z
  Eigen::Vector3d centre;      // where it projects from
  std::string centre_name;     // "the centroid of the solid", ...
};

// The projection from the first centre about which `mesh` (closed, genus 0, consistently oriented
// outward) is star-shaped, turned so that the north pole lies at +z and the south pole on the
// meridian of longitude 0 (where it is not at -z, which has no longitude); nothing when it is
// star-shaped about none of them.
[[nodiscard]] std::optional<CentralProjection> central_projection(const Mesh& mesh, const std::array<int, 2>& poles);

}  // namespace harmonia::detail
