#pragma once
// Internal: the Eigen CPU backend. Matrices are Eigen row-major CSR matrices, vector blocks are
// dense column-major matrices; every primitive is one Eigen expression over the whole block.

#include <memory>
#include <string>

#include "backend/backend.h"

namespace harmonia::detail {

class CpuMatrix final : public DeviceMatrix {
 public:
  explicit CpuMatrix(const RowMajorSparse& matrix);
  [[nodiscard]] int rows() const override { return static_cast<int>(matrix_.rows()); }
  [[nodiscard]] int cols() const override { return static_cast<int>(matrix_.cols()); }
  void update_values(const Eigen::Ref<const Eigen::VectorXd>& csr_values) override;
  [[nodiscard]] const RowMajorSparse& matrix() const { return matrix_; }
  [[nodiscard]] const RowMajorSparse& host() const override { return matrix_; }
  //! 1 / A(i,i), or 1 where the diagonal entry is zero (Jacobi then leaves that row unscaled).
  [[nodiscard]] const Eigen::VectorXd& inverse_diagonal() const { return inverse_diagonal_; }

 private:
  void refresh_diagonal();
  RowMajorSparse matrix_;
  Eigen::VectorXd inverse_diagonal_;
};

class CpuVectors final : public DeviceVectors {
 public:
  CpuVectors(int rows, int cols) : values_(Eigen::MatrixXd::Zero(rows, cols)) {}
  explicit CpuVectors(const Eigen::Ref<const Eigen::MatrixXd>& values) : values_(values) {}
  [[nodiscard]] int rows() const override { return static_cast<int>(values_.rows()); }
  [[nodiscard]] int cols() const override { return static_cast<int>(values_.cols()); }
  void upload(const Eigen::Ref<const Eigen::MatrixXd>& values) override;
  [[nodiscard]] Eigen::MatrixXd download() const override { return values_; }
  [[nodiscard]] Eigen::MatrixXd& values() { return values_; }
  [[nodiscard]] const Eigen::MatrixXd& values() const { return values_; }

 private:
  Eigen::MatrixXd values_;
};

class CpuBackend final : public Backend {
 public:
  [[nodiscard]] BackendKind kind() const override { return BackendKind::cpu; }
  [[nodiscard]] std::string description() const override;
  [[nodiscard]] bool supports(Feature feature) const override;

  [[nodiscard]] std::unique_ptr<DeviceMatrix> upload(const RowMajorSparse& matrix) override;
  [[nodiscard]] std::unique_ptr<DeviceVectors> upload(
      const Eigen::Ref<const Eigen::MatrixXd>& values) override;
  [[nodiscard]] std::unique_ptr<DeviceVectors> allocate(int rows, int cols) override;

  void spmv(const DeviceMatrix& a, const DeviceVectors& x, DeviceVectors& y) override;
  [[nodiscard]] Eigen::VectorXd dot(const DeviceVectors& x, const DeviceVectors& y) override;
  void axpy(const Eigen::VectorXd& alpha, const DeviceVectors& x, DeviceVectors& y) override;
  void xpay(const DeviceVectors& x, const Eigen::VectorXd& beta, DeviceVectors& y) override;
  void copy(const DeviceVectors& x, DeviceVectors& y) override;
  void jacobi(const DeviceMatrix& a, const DeviceVectors& r, DeviceVectors& z) override;

  // The host functions themselves (fallback/cpu_triangle_operators.h).
  [[nodiscard]] std::unique_ptr<TriangleOperators> triangle_operators(
      const Eigen::MatrixX3i& faces, int vertex_count) override;
};

}  // namespace harmonia::detail
