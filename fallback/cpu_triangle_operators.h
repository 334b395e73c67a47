#pragma once
// Internal: the CPU backend's per-triangle operators (TriangleOperators, backend/backend.h): the
// host functions themselves, so that a method assembling through the backend interface computes
// on the CPU exactly what it computed calling them directly:
//   cotangent:            harmonia::laplacian(mesh, WeightScheme::cotangent)
//   tensor_cotangent:     harmonia::tensor_cotangent_laplacian
//   quasi_harmonic:       harmonia::quasi_harmonic_tensors, then tensor_cotangent_laplacian
//   fragment_poisson_rhs: the surface's cotangent stiffness gathered by gather_fragment_load
//                         (fallback/fragment_load.h): harmonia::fragment_poisson_rhs in the
//                         summation order of the free-boundary map's loads.

#include "backend/backend.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

class CpuTriangleOperators final : public TriangleOperators {
 public:
  // Throws harmonia::Error(invalid_input) naming a face with an index outside [0, vertex_count).
  CpuTriangleOperators(const Eigen::MatrixX3i& faces, int vertex_count);

  [[nodiscard]] Eigen::SparseMatrix<double> cotangent(const Eigen::MatrixX3d& positions) override;
  [[nodiscard]] Eigen::SparseMatrix<double> tensor_cotangent(
      const Eigen::MatrixX2d& uv, const TriangleTensorRows& tensors) override;
  [[nodiscard]] QuasiHarmonicOperator quasi_harmonic(const Eigen::MatrixX3d& positions,
                                                     const Eigen::MatrixX2d& uv) override;
  [[nodiscard]] Eigen::MatrixXd fragment_poisson_rhs(const Eigen::MatrixX3d& positions,
                                                     const Eigen::MatrixXd& fragments) override;

 private:
  // The surface with the positions of the latest call (the host functions take a Mesh).
  const Mesh& surface(const Eigen::MatrixX3d& positions);

  Mesh mesh_;
};

}  // namespace harmonia::detail
