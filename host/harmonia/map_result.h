#pragma once
//! \file map_result.h
//! \brief The result every planar map returns: UVs plus the report.

#include <Eigen/Core>

#include "harmonia/types.h"

namespace harmonia {

struct MapResult {
  //! #V by 2 texture coordinates, one per vertex of the (disk) input mesh, in its vertex order.
  //! Finite whenever report.status is ok or flipped_triangles; empty on other failures.
  Eigen::MatrixX2d uv;
  SolveReport report;
};

}  // namespace harmonia
