// Backend::normal_product on the Vulkan backend (kernels/normal_product_matrix.h) against the host
// default (host/backend/host_normal_product.cpp) on the same backend, used exactly as the ABF
// solvers use it: normal_product(B, d), then spmv / pcg / minres on matrix(), then update() with
// new B values and weights on the same pattern. Random B and a mesh-like B (the vertex-edge
// incidence of a mesh with its boundary vertices left out: B D B^T is a weighted Dirichlet
// Laplacian). On lavapipe with validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>

#include "harmonia/procedural.h"
#include "kernels/kernel_test_data.h"
#include "kernels/normal_product.h"
#include "kernels/vulkan_backend.h"
#include "support/conditioning.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using detail::Backend;
using detail::DeviceNormalProduct;
using detail::IterativeSettings;
using vulkan::detail::VulkanBackend;

Eigen::VectorXd positive_weights(Eigen::Index size, std::uint32_t seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> value(0.5, 4.0);
  Eigen::VectorXd weights(size);
  for (Eigen::Index k = 0; k < size; ++k) weights[k] = value(generator);
  return weights;
}

// Interior vertices x edges of a hemisphere: +1 / -1 at the two ends of every edge.
RowMajorSparse mesh_incidence(int rings) {
  const Mesh mesh = hemisphere(rings);
  const Eigen::MatrixX3i& faces = mesh.faces;
  std::vector<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  // An edge used by one face lies on the boundary; its vertices are left out.
  std::vector<int> uses(edges.size(), 0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      const auto at = std::lower_bound(edges.begin(), edges.end(),
                                       std::make_pair(std::min(a, b), std::max(a, b)));
      ++uses[static_cast<std::size_t>(at - edges.begin())];
    }
  std::vector<int> row_of(static_cast<std::size_t>(mesh.vertex_count()), 0);
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (uses[e] == 1) row_of[edges[e].first] = row_of[edges[e].second] = -1;
  int rows = 0;
  for (int& row : row_of) row = row < 0 ? -1 : rows++;
  std::vector<Eigen::Triplet<double>> triplets;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (row_of[edges[e].first] >= 0) triplets.emplace_back(row_of[edges[e].first], e, 1.0);
    if (row_of[edges[e].second] >= 0) triplets.emplace_back(row_of[edges[e].second], e, -1.0);
  }
  RowMajorSparse b(rows, static_cast<int>(edges.size()));
  b.setFromTriplets(triplets.begin(), triplets.end());
  b.makeCompressed();
  return b;
}

class VulkanBackendNormalProduct : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(vulkan_test_context());
  }

  // Device product against the host default, then solves on matrix() against Eigen.
  void check(const RowMajorSparse& b, const Eigen::VectorXd& d, bool positive_definite) {
    const std::unique_ptr<DeviceNormalProduct> device = gpu_->normal_product(b, d);
    const std::unique_ptr<DeviceNormalProduct> host = gpu_->Backend::normal_product(b, d);
    const RowMajorSparse expected = host->download();
    const RowMajorSparse actual = device->download();
    ASSERT_EQ(actual.nonZeros(), expected.nonZeros()) << "the same fixed pattern";
    const RowMajorSparse magnitude = RowMajorSparse(b.cwiseAbs()) * d.cwiseAbs().asDiagonal() *
                                     RowMajorSparse(b.cwiseAbs().transpose());
    int longest = 0;
    for (int row = 0; row < b.rows(); ++row)
      longest = std::max(longest, b.outerIndexPtr()[row + 1] - b.outerIndexPtr()[row]);
    for (int row = 0; row < actual.rows(); ++row)
      for (RowMajorSparse::InnerIterator entry(actual, row); entry; ++entry)
        ASSERT_LE(
            std::abs(entry.value() - expected.coeff(row, entry.col())),
            vulkan::detail::normal_product_error_bound(longest) * magnitude.coeff(row, entry.col()))
            << "M(" << row << ", " << entry.col() << ")";

    // spmv on the kernel-written matrix.
    const Eigen::MatrixXd x = random_block(static_cast<int>(b.rows()), 2, 7);
    const auto x_gpu = gpu_->upload(x);
    auto y_gpu = gpu_->allocate(x.rows(), 2);
    gpu_->spmv(device->matrix(), *x_gpu, *y_gpu);
    const Eigen::MatrixXd y_expected = expected * x;
    const Eigen::MatrixXd y_bound = magnitude * x.cwiseAbs();
    EXPECT_LE(((y_gpu->download() - y_expected).cwiseAbs() - 1e-5 * y_bound).maxCoeff(), 0.0);

    // Solves on matrix(): the residual in double of the exact M (refinement) meets the tolerance.
    IterativeSettings settings;
    settings.relative_tolerance = 1e-9;
    const Eigen::MatrixXd rhs = expected * random_block(static_cast<int>(b.rows()), 2, 11);
    const auto rhs_gpu = gpu_->upload(rhs);
    for (const bool use_pcg : {true, false}) {
      if (use_pcg && !positive_definite) continue;
      auto solution = gpu_->allocate(rhs.rows(), 2);
      const detail::SolveStats stats =
          use_pcg ? gpu_->pcg(device->matrix(), *rhs_gpu, *solution, settings, {})
                  : gpu_->minres(device->matrix(), *rhs_gpu, *solution, settings, {});
      ASSERT_EQ(stats.status, Status::ok) << (use_pcg ? "pcg: " : "minres: ") << stats.message;
      const Eigen::MatrixXd x_solved = solution->download();
      const Eigen::MatrixXd residual = rhs - expected * x_solved;
      // The solver met 1e-9 on its own evaluation of the residual; this one rounds differently,
      // by at most residual_rounding (relative to |rhs|).
      const double allowed = 1e-9 + testing::residual_rounding(expected, x_solved, rhs);
      for (int c = 0; c < 2; ++c)
        EXPECT_LE(residual.col(c).norm(), allowed * rhs.col(c).norm())
            << (use_pcg ? "pcg" : "minres") << " column " << c;
    }

    // update(): new values on the same pattern, the device matrix follows without re-upload.
    Eigen::VectorXd b_values = Eigen::Map<const Eigen::VectorXd>(b.valuePtr(), b.nonZeros());
    b_values *= 1.5;
    const Eigen::VectorXd d2 = positive_weights(b.cols(), 99);
    device->update(b_values, d2);
    host->update(b_values, d2);
    const RowMajorSparse updated = device->download();
    const RowMajorSparse updated_expected = host->download();
    const double scale = updated_expected.coeffs().cwiseAbs().maxCoeff();
    EXPECT_LE(RowMajorSparse(updated - updated_expected).coeffs().cwiseAbs().maxCoeff(),
              1e-5 * scale);
    gpu_->spmv(device->matrix(), *x_gpu, *y_gpu);
    const Eigen::MatrixXd y2 = updated_expected * x;
    EXPECT_LE((y_gpu->download() - y2).cwiseAbs().maxCoeff(),
              1e-5 * (updated_expected.cwiseAbs() * x.cwiseAbs()).maxCoeff());
    auto solution = gpu_->allocate(rhs.rows(), 2);
    const Eigen::MatrixXd rhs2 = updated_expected * random_block(static_cast<int>(b.rows()), 2, 5);
    const auto rhs2_gpu = gpu_->upload(rhs2);
    const detail::SolveStats stats =
        gpu_->minres(device->matrix(), *rhs2_gpu, *solution, settings, {});
    ASSERT_EQ(stats.status, Status::ok) << stats.message;
    EXPECT_LE((rhs2 - updated_expected * solution->download()).norm(), 1e-9 * rhs2.norm() * 1.5)
        << "the refinement saw the updated M in double";
  }

  std::unique_ptr<VulkanBackend> gpu_;
};

TEST_F(VulkanBackendNormalProduct, RandomFullRankBMatchesTheHostDefault) {
  // B = [I | random]: full row rank, so B D B^T is positive definite for d > 0.
  for (const auto& [rows, extra, seed] :
       {std::tuple{1, 1, 1u}, std::tuple{17, 40, 2u}, std::tuple{300, 900, 3u}}) {
    RowMajorSparse random = random_sparse(rows, extra, 3, seed);
    std::vector<Eigen::Triplet<double>> triplets;
    for (int r = 0; r < rows; ++r) triplets.emplace_back(r, r, 2.0);
    for (int r = 0; r < rows; ++r)
      for (RowMajorSparse::InnerIterator entry(random, r); entry; ++entry)
        triplets.emplace_back(r, rows + entry.col(), entry.value());
    RowMajorSparse b(rows, rows + extra);
    b.setFromTriplets(triplets.begin(), triplets.end());
    b.makeCompressed();
    check(b, positive_weights(b.cols(), seed), true);
  }
}

TEST_F(VulkanBackendNormalProduct, MeshIncidenceGivesAWeightedDirichletLaplacian) {
  const RowMajorSparse b = mesh_incidence(12);
  ASSERT_GT(b.rows(), 50);
  check(b, positive_weights(b.cols(), 5), true);
}

TEST_F(VulkanBackendNormalProduct, MixedSignWeightsGiveAnIndefiniteMatrixForMinres) {
  RowMajorSparse b(40, 40);
  std::vector<Eigen::Triplet<double>> triplets;
  for (int r = 0; r < 40; ++r) {
    triplets.emplace_back(r, r, 1.0);
    if (r + 1 < 40) triplets.emplace_back(r, r + 1, 0.25);
  }
  b.setFromTriplets(triplets.begin(), triplets.end());
  b.makeCompressed();
  Eigen::VectorXd d = positive_weights(40, 8);
  for (int k = 0; k < 40; k += 3) d[k] = -d[k];
  check(b, d, false);
}

}  // namespace
}  // namespace harmonia::testing
