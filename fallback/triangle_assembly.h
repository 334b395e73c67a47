#pragma once
// Internal: the Eigen twins of the Vulkan per-triangle assembly (kernels/triangle_assembly.h),
// in the CSR layout the device writes. They call the host assembly itself
// (harmonia::laplacian, harmonia::tensor_cotangent_laplacian): one definition of the mathematics.
// The twin of the device tensor kernel (kernels/triangle_tensors.h) is
// harmonia::quasi_harmonic_tensors itself, and those of the gradient, divergence and fragment
// Poisson right-hand side (kernels/triangle_calculus.h) are harmonia::gradient_operator,
// harmonia::divergence and harmonia::fragment_poisson_rhs: all in the layout the device writes.

#include <Eigen/Core>

#include "backend/backend.h"
#include "harmonia/mesh.h"
#include "harmonia/quasi_harmonic_operator.h"

namespace harmonia::detail {

//! The cotangent Laplacian (4.41) of `mesh`, row-major.
[[nodiscard]] RowMajorSparse cpu_cotangent_assembly(const Mesh& mesh);

//! The tensor-cotangent operator (5.10) of the planar map uv with per-triangle tensors, row-major.
[[nodiscard]] RowMajorSparse cpu_tensor_assembly(const Eigen::MatrixX2d& uv,
                                                 const Eigen::MatrixX3i& faces,
                                                 const TriangleTensors& tensors);

}  // namespace harmonia::detail
