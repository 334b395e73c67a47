#include "fallback/triangle_assembly.h"

#include "harmonia/laplacian.h"

namespace harmonia::detail {

RowMajorSparse cpu_cotangent_assembly(const Mesh& mesh) {
  RowMajorSparse result = laplacian(mesh, WeightScheme::cotangent);
  result.makeCompressed();
  return result;
}

RowMajorSparse cpu_tensor_assembly(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& faces,
                                   const TriangleTensors& tensors) {
  RowMajorSparse result = tensor_cotangent_laplacian(uv, faces, tensors);
  result.makeCompressed();
  return result;
}

}  // namespace harmonia::detail
