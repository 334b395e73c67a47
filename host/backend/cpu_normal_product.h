#pragma once
// Internal: the Eigen twin of the Vulkan weighted normal product (kernels/normal_product.h).

#include <Eigen/Core>

#include "backend/backend.h"

namespace harmonia::detail {

//! M = B diag(d) B^T, row-major. d: one weight per column of B.
[[nodiscard]] RowMajorSparse cpu_normal_product(const RowMajorSparse& b, const Eigen::VectorXd& d);

}  // namespace harmonia::detail
