// SolverOptions::cross_check: every backend operation also runs on the CPU twin and the worst
// relative difference reaches SolveReport::cross_check_error. On lavapipe (fp32) it is small but
// not zero, for the solves and for the per-triangle assembly of the free-boundary map; a
// deliberately wrong primary (products, assembly) is caught; the CPU backend is not compared with
// itself.
#include <gtest/gtest.h>

#include "fallback/cpu_backend.h"
#include "harmonia/fixed_boundary_map.h"
#include "harmonia/free_boundary_map.h"
#include "harmonia/laplacian.h"
#include "harmonia/lscm.h"
#include "harmonia/procedural.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "kernels/kernel_test_data.h"
#include "solve/backend_selection.h"
#include "solve/cross_check_backend.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using detail::CrossCheckBackend;

TEST(CrossCheck, ConformalMapsOnLavapipeAgreeWithTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const Mesh mesh = hemisphere(14);
  SolverOptions solver;
  solver.backend = BackendChoice::vulkan;
  solver.vulkan_context = vulkan_test_context();
  solver.cross_check = true;

  FixedBoundaryOptions harmonic;
  harmonic.weights = WeightScheme::cotangent;
  harmonic.solver = solver;
  const MapResult fixed = fixed_boundary_map(mesh, harmonic);
  ASSERT_TRUE(fixed.report.ok()) << fixed.report.message;
  EXPECT_NE(fixed.report.device.find("cross-checked"), std::string::npos) << fixed.report.device;
  EXPECT_GT(fixed.report.cross_check_error, 0.0);
  EXPECT_LT(fixed.report.cross_check_error, 1e-4);

  LscmOptions conformal;
  conformal.solver = solver;
  const MapResult lscm_result = lscm(mesh, conformal);
  ASSERT_TRUE(lscm_result.report.ok()) << lscm_result.report.message;
  EXPECT_GT(lscm_result.report.cross_check_error, 0.0);
  EXPECT_LT(lscm_result.report.cross_check_error, 1e-4);

  // Cross-checking observes: the map is the unchecked one, bit for bit.
  harmonic.solver.cross_check = false;
  const MapResult unchecked = fixed_boundary_map(mesh, harmonic);
  EXPECT_TRUE((unchecked.uv.array() == fixed.uv.array()).all());
  EXPECT_EQ(unchecked.report.cross_check_error, 0.0);
}

TEST(CrossCheck, AFreeBoundaryMapOnLavapipeAgreesWithTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const Mesh mesh = hemisphere(14);
  FreeBoundaryOptions options;
  options.solver.backend = BackendChoice::vulkan;
  options.solver.vulkan_context = vulkan_test_context();
  options.solver.cross_check = true;
  // Its operators and P1's load are assembled on the device and compared too.
  const FreeBoundaryResult checked = free_boundary_map(mesh, options);
  ASSERT_TRUE(checked.report.ok()) << checked.report.message;
  EXPECT_GT(checked.report.cross_check_error, 0.0);
  EXPECT_LT(checked.report.cross_check_error, 1e-4);
  options.solver.cross_check = false;
  const FreeBoundaryResult unchecked = free_boundary_map(mesh, options);
  EXPECT_TRUE((unchecked.uv.array() == checked.uv.array()).all());
}

TEST(CrossCheck, TheCpuBackendIsNotComparedWithItself) {
  SolverOptions solver;
  solver.backend = BackendChoice::cpu;
  solver.cross_check = true;
  std::string message;
  const auto backend = detail::make_backend(solver, &message);
  ASSERT_NE(backend, nullptr);
  EXPECT_EQ(dynamic_cast<CrossCheckBackend*>(backend.get()), nullptr);
  FixedBoundaryOptions options;
  options.solver = solver;
  const MapResult result = fixed_boundary_map(hemisphere(8), options);
  ASSERT_TRUE(result.report.ok());
  EXPECT_EQ(result.report.cross_check_error, 0.0);
}

// Per-triangle operators that get every result 1% wrong.
class WrongTriangleOperators final : public detail::TriangleOperators {
 public:
  explicit WrongTriangleOperators(std::unique_ptr<detail::TriangleOperators> right)
      : right_(std::move(right)) {}
  Eigen::SparseMatrix<double> cotangent(const Eigen::MatrixX3d& positions) override {
    return right_->cotangent(positions) * 1.01;
  }
  Eigen::SparseMatrix<double> tensor_cotangent(const Eigen::MatrixX2d& uv,
                                               const detail::TriangleTensorRows& tensors) override {
    return right_->tensor_cotangent(uv, tensors) * 1.01;
  }
  detail::QuasiHarmonicOperator quasi_harmonic(const Eigen::MatrixX3d& positions,
                                               const Eigen::MatrixX2d& uv) override {
    detail::QuasiHarmonicOperator result = right_->quasi_harmonic(positions, uv);
    result.tensors *= 1.01;
    result.matrix *= 1.01;
    return result;
  }
  Eigen::MatrixXd fragment_poisson_rhs(const Eigen::MatrixX3d& positions,
                                       const Eigen::MatrixXd& fragments) override {
    return right_->fragment_poisson_rhs(positions, fragments) * 1.01;
  }

 private:
  std::unique_ptr<detail::TriangleOperators> right_;
};

// A primary that gets the products and the per-triangle operators 1% wrong (and says it is a
// device).
class WrongBackend final : public detail::Backend {
 public:
  [[nodiscard]] BackendKind kind() const override { return BackendKind::vulkan; }
  [[nodiscard]] std::string description() const override { return "wrong"; }
  [[nodiscard]] bool supports(detail::Feature feature) const override {
    return feature == detail::Feature::float64;
  }
  [[nodiscard]] std::unique_ptr<detail::DeviceMatrix> upload(
      const detail::RowMajorSparse& matrix) override {
    return cpu_.upload(matrix);
  }
  [[nodiscard]] std::unique_ptr<detail::DeviceVectors> upload(
      const Eigen::Ref<const Eigen::MatrixXd>& values) override {
    return cpu_.upload(values);
  }
  [[nodiscard]] std::unique_ptr<detail::DeviceVectors> allocate(int rows, int cols) override {
    return cpu_.allocate(rows, cols);
  }
  void spmv(const detail::DeviceMatrix& a, const detail::DeviceVectors& x,
            detail::DeviceVectors& y) override {
    cpu_.spmv(a, x, y);
    y.upload(y.download() * 1.01);
  }
  [[nodiscard]] Eigen::VectorXd dot(const detail::DeviceVectors& x,
                                    const detail::DeviceVectors& y) override {
    return cpu_.dot(x, y);
  }
  void axpy(const Eigen::VectorXd& alpha, const detail::DeviceVectors& x,
            detail::DeviceVectors& y) override {
    cpu_.axpy(alpha, x, y);
  }
  void xpay(const detail::DeviceVectors& x, const Eigen::VectorXd& beta,
            detail::DeviceVectors& y) override {
    cpu_.xpay(x, beta, y);
  }
  void copy(const detail::DeviceVectors& x, detail::DeviceVectors& y) override { cpu_.copy(x, y); }
  void jacobi(const detail::DeviceMatrix& a, const detail::DeviceVectors& r,
              detail::DeviceVectors& z) override {
    cpu_.jacobi(a, r, z);
  }
  [[nodiscard]] std::unique_ptr<detail::TriangleOperators> triangle_operators(
      const Eigen::MatrixX3i& faces, int vertex_count) override {
    return std::make_unique<WrongTriangleOperators>(cpu_.triangle_operators(faces, vertex_count));
  }

 private:
  detail::CpuBackend cpu_;
};

TEST(CrossCheck, AWrongPrimaryIsCaught) {
  CrossCheckBackend backend(std::make_unique<WrongBackend>());
  const detail::RowMajorSparse a = hemisphere_laplacian(8);
  const Eigen::MatrixXd x = random_block(static_cast<int>(a.rows()), 2, 11u);
  const auto matrix = backend.upload(a);
  const auto input = backend.upload(x);
  const auto output = backend.allocate(static_cast<int>(a.rows()), 2);
  EXPECT_EQ(backend.cross_check_error(), 0.0);
  const Eigen::VectorXd dots = backend.dot(*input, *input);
  EXPECT_EQ(backend.cross_check_error(), 0.0) << "the dot product is right";
  EXPECT_GT(dots.minCoeff(), 0.0);
  backend.spmv(*matrix, *input, *output);
  // 1% of each entry of A x, measured against max (|A| |x|): large, and at most 1%.
  EXPECT_GT(backend.cross_check_error(), 1e-3);
  EXPECT_LE(backend.cross_check_error(), 1.01e-2);
  // What flows on is the primary's result.
  EXPECT_TRUE(output->download().isApprox((a * x) * 1.01, 1e-12));
  // A whole solve on the wrong primary: its PCG (the default over the wrong products) disagrees
  // with the twin's.
  CrossCheckBackend solver_backend(std::make_unique<WrongBackend>());
  const auto system = solver_backend.upload(a);
  const auto rhs = solver_backend.upload(x);
  const auto solution = solver_backend.allocate(static_cast<int>(a.rows()), 2);
  detail::IterativeSettings settings;
  const detail::SolveStats stats = solver_backend.pcg(*system, *rhs, *solution, settings, {});
  EXPECT_EQ(stats.status, Status::ok) << stats.message;
  EXPECT_GT(solver_backend.cross_check_error(), 1e-3);
}

// Each per-triangle operation is compared on its own: 1% off, measured against the twin's largest
// entry, is 1% (up to the rounding of the scaling).
TEST(CrossCheck, AWrongAssemblyIsCaught) {
  const Mesh mesh = hemisphere(8);
  const Eigen::MatrixX2d uv = mesh.vertices.leftCols<2>();  // The cap seen from above.
  const auto expect_one_percent = [](const CrossCheckBackend& backend, const char* what) {
    EXPECT_GT(backend.cross_check_error(), 0.99e-2) << what;
    EXPECT_LE(backend.cross_check_error(), 1.01e-2) << what;
  };
  {
    CrossCheckBackend backend(std::make_unique<WrongBackend>());
    const auto operators = backend.triangle_operators(mesh.faces, mesh.vertex_count());
    const Eigen::SparseMatrix<double> cotangent = operators->cotangent(mesh.vertices);
    expect_one_percent(backend, "cotangent");
    // What flows on is the primary's result.
    EXPECT_TRUE(cotangent.isApprox(laplacian(mesh, WeightScheme::cotangent) * 1.01, 1e-12));
  }
  {
    CrossCheckBackend backend(std::make_unique<WrongBackend>());
    const auto operators = backend.triangle_operators(mesh.faces, mesh.vertex_count());
    (void)operators->quasi_harmonic(mesh.vertices, uv);
    expect_one_percent(backend, "quasi-harmonic");
  }
  {
    CrossCheckBackend backend(std::make_unique<WrongBackend>());
    const auto operators = backend.triangle_operators(mesh.faces, mesh.vertex_count());
    const TriangleTensors identity =
        scalar_tensors(Eigen::VectorXd::Ones(mesh.faces.rows()));
    (void)operators->tensor_cotangent(uv, identity);
    expect_one_percent(backend, "tensor-cotangent");
  }
  {
    CrossCheckBackend backend(std::make_unique<WrongBackend>());
    const auto operators = backend.triangle_operators(mesh.faces, mesh.vertex_count());
    (void)operators->fragment_poisson_rhs(
        mesh.vertices, random_block(3 * static_cast<int>(mesh.faces.rows()), 2, 5u));
    expect_one_percent(backend, "fragment right-hand side");
  }
}

}  // namespace
}  // namespace harmonia::testing
