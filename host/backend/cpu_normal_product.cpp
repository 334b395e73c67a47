#include "backend/cpu_normal_product.h"

#include <stdexcept>

namespace harmonia::detail {

RowMajorSparse cpu_normal_product(const RowMajorSparse& b, const Eigen::VectorXd& d) {
  if (d.size() != b.cols())
    throw std::invalid_argument("normal product: one weight per column of B is needed");
  RowMajorSparse result = b * d.asDiagonal() * b.transpose();
  result.makeCompressed();
  return result;
}

}  // namespace harmonia::detail
