#pragma once
// Internal: a Backend that runs every operation twice, on a primary backend (Vulkan) and on a
// CpuBackend twin, and measures how far the primary's results are from the twin's
// (SolverOptions::cross_check).
//
// Every matrix, vector block, normal product and preconditioner exists on both backends. After
// each spmv, dot, pcg, preconditioned pcg, minres, block_pcg, preconditioner application and
// normal-product update the two results are compared relative to their natural scale (below)
// and the worst difference so far is kept in cross_check_error(). The twin's result is then
// replaced by the primary's, so that each comparison measures one operation's error
// and differences do not compound along an algorithm; the primary's results flow on unchanged, so
// a cross-checked run computes exactly what an unchecked one does.
//
// Scales: spmv, max_i |y_p - y_t|_i / max_i (|A| |x|)_i (the rounding scale of the product, so
// that a product that cancels to zero, e.g. a Laplacian times a constant, is judged fairly); dot,
// |d_p - d_t| / (||x|| ||y||) (Cauchy-Schwarz); solves, normal products and everything the
// per-triangle operators return (matrices, tensors, fragment right-hand sides), max |p - t| /
// max |t|. Assembled matrices must have the same pattern, and tensors the same infinite entries
// (the markers of zero-area uv faces), else the difference is infinite. The per-triangle
// operators hand back the primary's results, which live on the host: there is nothing to resync.
//
// A CPU primary is not wrapped (make_backend): its twin would be itself, and cross_check_error()
// stays 0. Not thread-safe (as every backend).

#include <memory>
#include <string>

#include "backend/backend.h"

namespace harmonia::detail {

class CrossCheckBackend final : public Backend {
 public:
  // The primary must not be null.
  explicit CrossCheckBackend(std::unique_ptr<Backend> primary);
  ~CrossCheckBackend() override;

  [[nodiscard]] BackendKind kind() const override { return primary_->kind(); }
  [[nodiscard]] std::string description() const override;  // "<primary>, cross-checked on cpu".
  [[nodiscard]] bool supports(Feature feature) const override;
  [[nodiscard]] double cross_check_error() const override { return worst_error_; }

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

  [[nodiscard]] std::unique_ptr<DeviceNormalProduct> normal_product(
      const RowMajorSparse& b, const Eigen::Ref<const Eigen::VectorXd>& diagonal) override;

  [[nodiscard]] std::unique_ptr<TriangleOperators> triangle_operators(
      const Eigen::MatrixX3i& faces, int vertex_count) override;

  SolveStats pcg(const DeviceMatrix& a, const DeviceVectors& b, DeviceVectors& x,
                 const IterativeSettings& settings, const ProgressCallback& progress) override;
  [[nodiscard]] std::unique_ptr<Preconditioner> multilevel_preconditioner(
      const AggregationHierarchy& hierarchy) override;
  SolveStats preconditioned_pcg(const DeviceMatrix& a, Preconditioner& preconditioner,
                                const DeviceVectors& b, DeviceVectors& x,
                                const IterativeSettings& settings,
                                const ProgressCallback& progress) override;
  SolveStats minres(const DeviceMatrix& a, const DeviceVectors& b, DeviceVectors& x,
                    const IterativeSettings& settings, const ProgressCallback& progress) override;
  BlockSolveStats block_pcg(const DeviceMatrix& a, const BlockRows& blocks, const DeviceVectors& b,
                            DeviceVectors& x, const IterativeSettings& settings,
                            const ProgressCallback& progress) override;

  // The backends themselves (tests).
  [[nodiscard]] Backend& primary() const { return *primary_; }
  [[nodiscard]] Backend& twin() const { return *twin_; }

 private:
  // Keeps the larger of the worst error so far and `error` (a NaN counts as infinitely large).
  void record(double error);
  // Compares a vector block's two copies (max |p - t| / max |t|), then gives the twin the
  // primary's values.
  void compare_and_resync(DeviceVectors& result);
  // After a solve on both: compares the solutions when both converged (only converged solutions
  // are meant to agree), else gives the twin the primary's.
  void settle_twin_solve(const SolveStats& primary, const SolveStats& twin, DeviceVectors& x);

  std::unique_ptr<Backend> primary_;
  std::unique_ptr<Backend> twin_;
  double worst_error_ = 0.0;
};

}  // namespace harmonia::detail
