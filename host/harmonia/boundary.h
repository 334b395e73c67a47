#pragma once
//! \file boundary.h
//! \brief Placement of boundary vertices for fixed-boundary maps (a separate, swappable component).

#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

enum class BoundaryShape {
  circle,  //!< Unit circle, spacing proportional to 3D arc length.
  square,  //!< Unit square [-1,1]^2 perimeter, arc-length spacing, corners at the four boundary
           //!< vertices closest to quarter arc-length positions.
  given,   //!< User-given positions for user-given vertices (BoundaryOptions::given_*).
};

struct BoundaryOptions {
  BoundaryShape shape = BoundaryShape::circle;
  Eigen::VectorXi given_vertices;  //!< shape == given: #B fixed vertex indices (at least 2 distinct).
  Eigen::MatrixX2d given_uv;       //!< shape == given: #B by 2 positions of those vertices.
};

//! Fixed vertices and their positions.
struct BoundaryPlacement {
  Eigen::VectorXi vertices;  //!< #B vertex indices.
  Eigen::MatrixX2d uv;       //!< #B by 2 positions.
};

//! Places `loop` (a boundary loop as returned by boundary_loops, mesh to its left) on the chosen
//! shape, counter-clockwise, starting at loop[0]. For `given`, returns the given data validated.
[[nodiscard]] BoundaryPlacement place_boundary(const Mesh& mesh, const std::vector<int>& loop,
                                               const BoundaryOptions& options);

}  // namespace harmonia
