// The CPU backend's per-triangle operators: the host functions (cpu_triangle_operators.h).

#include "fallback/cpu_triangle_operators.h"

#include <stdexcept>
#include <string>

#include "fallback/fragment_load.h"
#include "harmonia/laplacian.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "mesh/adjacency_pattern.h"

namespace harmonia::detail {

CpuTriangleOperators::CpuTriangleOperators(const Eigen::MatrixX3i& faces, int vertex_count) {
  check_face_indices(faces, vertex_count, "triangle operators");
  mesh_.faces = faces;
  mesh_.vertices = Eigen::MatrixX3d::Zero(vertex_count, 3);
}

const Mesh& CpuTriangleOperators::surface(const Eigen::MatrixX3d& positions) {
  if (positions.rows() != mesh_.vertices.rows())
    throw std::invalid_argument("cpu triangle operators: " + std::to_string(positions.rows()) +
                                " positions for " + std::to_string(mesh_.vertices.rows()) +
                                " vertices");
  mesh_.vertices = positions;
  return mesh_;
}

Eigen::SparseMatrix<double> CpuTriangleOperators::cotangent(const Eigen::MatrixX3d& positions) {
  return laplacian(surface(positions), WeightScheme::cotangent);
}

Eigen::SparseMatrix<double> CpuTriangleOperators::tensor_cotangent(
    const Eigen::MatrixX2d& uv, const TriangleTensorRows& tensors) {
  return tensor_cotangent_laplacian(uv, mesh_.faces, tensors);
}

QuasiHarmonicOperator CpuTriangleOperators::quasi_harmonic(const Eigen::MatrixX3d& positions,
                                                           const Eigen::MatrixX2d& uv) {
  QuasiHarmonicOperator result;
  result.tensors = quasi_harmonic_tensors(surface(positions), uv);
  result.matrix = tensor_cotangent_laplacian(uv, mesh_.faces, result.tensors);
  return result;
}

Eigen::MatrixXd CpuTriangleOperators::fragment_poisson_rhs(const Eigen::MatrixX3d& positions,
                                                           const Eigen::MatrixXd& fragments) {
  if (fragments.rows() != 3 * mesh_.faces.rows())
    throw std::invalid_argument("cpu fragment rhs: " + std::to_string(fragments.rows()) +
                                " fragment rows for " + std::to_string(mesh_.faces.rows()) +
                                " faces");
  const Mesh& current = surface(positions);
  return gather_fragment_load(current.faces, current.vertex_count(),
                              cotangent_pair_stiffness(current.vertices, current.faces), fragments);
}

}  // namespace harmonia::detail
