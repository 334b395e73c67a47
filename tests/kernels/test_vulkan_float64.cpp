// The fp64 kernels (every shader compiled with HARMONIA_FP64, DevicePrecision::float64) on a
// lavapipe device with shaderFloat64 enabled (tests/kernels/float64_test_context.h), with
// validation: each primitive against its Eigen twin within bounds derived from double rounding
// (u = 2^-53), the normal product, cotangent assembly and gradient kernels, PCG and MINRES
// without refinement rounds, conformal (fixed-boundary cotangent) and LSCM maps within 1e-9 of
// the CPU's bounding box; and float64 asked of a context without it refused with
// Status::unsupported and a message saying why.
#include <gtest/gtest.h>

#include "backend/cpu_normal_product.h"
#include "harmonia/fixed_boundary_map.h"
#include "harmonia/laplacian.h"
#include "harmonia/lscm.h"
#include "harmonia/procedural.h"
#include "kernels/float64_test_context.h"
#include "kernels/kernel_test_data.h"
#include "kernels/normal_product.h"
#include "kernels/triangle_assembly.h"
#include "kernels/vulkan_backend.h"

namespace harmonia::testing {
namespace {

using vulkan::detail::VulkanBackend;
constexpr double unit_roundoff = 0x1p-53;

class VulkanFloat64 : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_FLOAT64_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(float64_test_context(), DevicePrecision::float64);
  }
  std::unique_ptr<VulkanBackend> gpu_;
};

TEST(VulkanFloat64Context, Float64WithoutTheFeatureIsUnsupportedWithAReason) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  try {
    VulkanBackend backend(vulkan_test_context(), DevicePrecision::float64);
    FAIL() << "float64 on a context without shaderFloat64 enabled was accepted";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::unsupported);
    EXPECT_NE(std::string(error.what()).find("shaderFloat64"), std::string::npos) << error.what();
  }
  VulkanBackend fp32(vulkan_test_context());
  EXPECT_FALSE(fp32.supports(detail::Feature::float64));
  EXPECT_NE(fp32.description().find("fp32"), std::string::npos);
}

TEST_F(VulkanFloat64, DescribesItselfAndSupportsFloat64) {
  EXPECT_TRUE(gpu_->supports(detail::Feature::float64));
  EXPECT_NE(gpu_->description().find("fp64"), std::string::npos) << gpu_->description();
}

TEST_F(VulkanFloat64, SpmvAndBlasMatchEigenToDoubleRounding) {
  for (const auto& [rows, mean, seed] : {std::tuple{1, 1, 1u}, std::tuple{37, 5, 2u},
                                         std::tuple{2001, 7, 3u}, std::tuple{3000, 40, 4u}}) {
    const RowMajorSparse a = random_sparse(rows, rows, mean, seed);
    const Eigen::MatrixXd x = random_block(rows, 2, seed + 10);
    const Eigen::MatrixXd y = random_block(rows, 2, seed + 20);
    const auto a_gpu = gpu_->upload(a);
    const auto x_gpu = gpu_->upload(x);
    auto y_gpu = gpu_->upload(y);
    int longest = 0;
    for (int r = 0; r < rows; ++r)
      longest = std::max(longest, a.outerIndexPtr()[r + 1] - a.outerIndexPtr()[r]);
    gpu_->spmv(*a_gpu, *x_gpu, *y_gpu);
    const Eigen::MatrixXd bound = (longest + 2) * unit_roundoff * (a.cwiseAbs() * x.cwiseAbs());
    EXPECT_LE(((y_gpu->download() - a * x).cwiseAbs() - bound).maxCoeff(), 0.0) << rows;
    // The errors are far below fp32's: an fp32 kernel would be off by ~1e-7 here.
    const Eigen::VectorXd dots = gpu_->dot(*x_gpu, *x_gpu);
    for (int c = 0; c < 2; ++c)
      EXPECT_NEAR(dots[c], x.col(c).squaredNorm(),
                  (rows + 20) * unit_roundoff * x.col(c).squaredNorm());
    y_gpu->upload(y);
    const Eigen::Vector2d alpha(0.3, -1.7);
    gpu_->axpy(alpha, *x_gpu, *y_gpu);
    const Eigen::MatrixXd axpy = y + x * alpha.asDiagonal();
    EXPECT_LE((y_gpu->download() - axpy).cwiseAbs().maxCoeff(), 4 * unit_roundoff * 3.0);
    gpu_->xpay(*x_gpu, alpha, *y_gpu);
    const Eigen::MatrixXd xpay = x + axpy * alpha.asDiagonal();
    EXPECT_LE((y_gpu->download() - xpay).cwiseAbs().maxCoeff(), 4 * unit_roundoff * 8.0);
    gpu_->copy(*x_gpu, *y_gpu);
    EXPECT_EQ((y_gpu->download() - x).cwiseAbs().maxCoeff(), 0.0) << "a copy is exact";
    gpu_->scale(alpha, *y_gpu);
    EXPECT_EQ((y_gpu->download() - x * alpha.asDiagonal()).cwiseAbs().maxCoeff(), 0.0)
        << "one rounded product, as in Eigen";
    gpu_->jacobi(*a_gpu, *x_gpu, *y_gpu);
    Eigen::VectorXd inverse = Eigen::VectorXd::Ones(rows);
    for (int r = 0; r < rows; ++r)
      if (a.coeff(r, r) != 0.0) inverse[r] = 1.0 / a.coeff(r, r);
    const Eigen::MatrixXd jacobi = inverse.asDiagonal() * x;
    EXPECT_LE((y_gpu->download() - jacobi).cwiseAbs().maxCoeff(),
              2 * unit_roundoff * jacobi.cwiseAbs().maxCoeff());
  }
}

TEST_F(VulkanFloat64, PcgAndMinresReachTheToleranceInOneRound) {
  const RowMajorSparse a = hemisphere_laplacian(20);
  const Eigen::MatrixXd b = a * random_block(static_cast<int>(a.rows()), 2, 5);
  const auto a_gpu = gpu_->upload(a);
  const auto b_gpu = gpu_->upload(b);
  detail::IterativeSettings settings;
  settings.relative_tolerance = 1e-11;  // Below anything fp32 could reach without refinement.
  for (const bool use_pcg : {true, false}) {
    auto x_gpu = gpu_->allocate(b.rows(), 2);
    const detail::SolveStats stats = use_pcg ? gpu_->pcg(*a_gpu, *b_gpu, *x_gpu, settings, {})
                                             : gpu_->minres(*a_gpu, *b_gpu, *x_gpu, settings, {});
    ASSERT_EQ(stats.status, Status::ok) << stats.message;
    const Eigen::MatrixXd residual = b - a * x_gpu->download();
    for (int c = 0; c < 2; ++c) EXPECT_LE(residual.col(c).norm(), 1e-11 * b.col(c).norm());
  }
}

TEST_F(VulkanFloat64, NormalProductMatchesEigen) {
  const RowMajorSparse b = random_sparse(500, 1200, 4, 9);
  Eigen::VectorXd d = random_block(1200, 1, 10).col(0);
  const auto product = gpu_->normal_product(b, d);
  const RowMajorSparse expected = detail::cpu_normal_product(b, d);
  const RowMajorSparse magnitude = detail::cpu_normal_product(b.cwiseAbs(), d.cwiseAbs());
  const RowMajorSparse actual = product->download();
  for (int row = 0; row < actual.rows(); ++row)
    for (RowMajorSparse::InnerIterator entry(actual, row); entry; ++entry)
      ASSERT_LE(std::abs(entry.value() - expected.coeff(row, entry.col())),
                vulkan::detail::normal_product_error_bound(12, DevicePrecision::float64) *
                    magnitude.coeff(row, entry.col()));
}

TEST_F(VulkanFloat64, CotangentAssemblyMatchesTheHostLaplacian) {
  const Mesh mesh = hemisphere(16);
  auto assembly = gpu_->triangle_assembly(mesh.faces, mesh.vertex_count());
  assembly->assemble_cotangent(mesh.vertices);
  const RowMajorSparse actual = assembly->download();
  const RowMajorSparse expected = laplacian(mesh, WeightScheme::cotangent);
  const double scale = expected.coeffs().cwiseAbs().maxCoeff();
  EXPECT_LE(RowMajorSparse(actual - expected).coeffs().cwiseAbs().maxCoeff(), 1e-12 * scale);
}

double relative_uv_difference(const Eigen::MatrixX2d& uv, const Eigen::MatrixX2d& reference) {
  const double extent =
      (reference.colwise().maxCoeff() - reference.colwise().minCoeff()).maxCoeff();
  return (uv - reference).cwiseAbs().maxCoeff() / extent;
}

SolverOptions float64_solver() {
  SolverOptions solver;
  solver.backend = BackendChoice::vulkan;
  solver.vulkan_context = float64_test_context();
  solver.device_precision = DevicePrecision::float64;
  solver.tolerance = 1e-12;
  return solver;
}

TEST_F(VulkanFloat64, ConformalAndLscmMapsMatchTheCpuToOneBillionth) {
  for (const Mesh& mesh : {hemisphere(14), planar_disk(12, 0.3)}) {
    FixedBoundaryOptions conformal;
    conformal.weights = WeightScheme::cotangent;
    conformal.normalization = UvNormalization::none;
    conformal.solver.backend = BackendChoice::cpu;
    const MapResult cpu = fixed_boundary_map(mesh, conformal);
    conformal.solver = float64_solver();
    const MapResult gpu = fixed_boundary_map(mesh, conformal);
    ASSERT_TRUE(gpu.report.ok()) << gpu.report.message;
    EXPECT_EQ(gpu.report.backend, BackendKind::vulkan);
    EXPECT_LE(relative_uv_difference(gpu.uv, cpu.uv), 1e-9);
    EXPECT_EQ(gpu.report.flipped_triangles, cpu.report.flipped_triangles);

    LscmOptions lscm_options;
    lscm_options.normalization = UvNormalization::none;
    lscm_options.solver.backend = BackendChoice::cpu;
    const MapResult lscm_cpu = lscm(mesh, lscm_options);
    lscm_options.solver = float64_solver();
    const MapResult lscm_gpu = lscm(mesh, lscm_options);
    ASSERT_TRUE(lscm_gpu.report.ok()) << lscm_gpu.report.message;
    EXPECT_LE(relative_uv_difference(lscm_gpu.uv, lscm_cpu.uv), 1e-9);
    EXPECT_EQ(lscm_gpu.report.flipped_triangles, lscm_cpu.report.flipped_triangles);
  }
}

}  // namespace
}  // namespace harmonia::testing
