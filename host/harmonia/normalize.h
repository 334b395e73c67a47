#pragma once
//! \file normalize.h
//! \brief Output normalization of a planar layout (see UvNormalization in solver_options.h).

#include <Eigen/Core>

#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia {

//! Normalizes uv in place. Orientation rule: if the summed signed UV area is negative the layout is
//! mirrored (v -> -v) so faces are counter-clockwise. Principal axis: the eigenvector of the
//! area-weighted second moment with the largest eigenvalue becomes +u; the sign is fixed so that the
//! area-weighted third moment along u is >= 0 (deterministic). Then the scale rule of `mode`.
//! mesh3d gives the 3D areas; uv_faces indexes uv (equal to mesh3d.faces without seams).
void normalize_uv(const Mesh& mesh3d, const Eigen::MatrixX3i& uv_faces, Eigen::MatrixX2d& uv,
                  UvNormalization mode);

}  // namespace harmonia
