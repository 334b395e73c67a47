#pragma once
//! \file boundary.h
//! \brief Placement of boundary vertices for fixed-boundary maps (a separate, swappable component).

#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

enum class BoundaryShape {
  circle,  //!< Unit circle, spaced as BoundaryOptions::spacing says (3D arc length by default).
  square,  //!< Unit square [-1,1]^2 perimeter, spaced the same way, corners at the four boundary
           //!< vertices closest to quarter positions.
  given,   //!< User-given positions for user-given vertices (BoundaryOptions::given_*).
};

//! How the boundary vertices are spaced along a circle or square.
enum class BoundarySpacing {
  arc_length,  //!< Proportional to 3D arc length (the boundary's own proportions).
  //! Each boundary edge's share is the geometric mean of its length and the side of its triangle,
  //! sqrt(|e| sqrt(A)): the same as arc length on an even tessellation, but a long edge of a thin
  //! triangle (a long cut through little area, thesis 6.5) no longer takes a large share of the
  //! perimeter. The start map of the free-boundary maps uses it.
  edge_and_triangle_size,
};

struct BoundaryOptions {
  BoundaryShape shape = BoundaryShape::circle;
  BoundarySpacing spacing = BoundarySpacing::arc_length;  //!< circle and square.
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
