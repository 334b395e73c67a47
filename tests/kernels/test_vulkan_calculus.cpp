// Per-triangle gradient, divergence and fragment Poisson right-hand side on the device
// (kernels/triangle_calculus.h) against their Eigen twins (harmonia::gradient_operator,
// divergence, fragment_poisson_rhs), on lavapipe with validation; several columns at once, 3D and
// planar positions, a corpus mesh (skipped when absent). Each entry is held to the declared
// per-triangle bound summed over what it gathers; a second run gives the same bits.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>

#include "harmonia/gradient.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "kernels/device_arrays.h"
#include "kernels/kernel_test_data.h"
#include "kernels/triangle_assembly.h"
#include "kernels/triangle_calculus.h"
#include "kernels/vulkan_backend.h"
#include "support/test_support.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using vulkan::detail::TriangleCalculus;
using vulkan::detail::VulkanBackend;
using vulkan::detail::VulkanVectors;

constexpr double unit_roundoff = 0x1p-24;

Eigen::Vector3d corner_point(const Eigen::MatrixXd& positions, int vertex) {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  point.head(positions.cols()) = positions.row(vertex).transpose();
  return point;
}

struct Triangle {
  Eigen::Vector3d hat[3];    // Hat-function gradients.
  Eigen::Vector3d half_cot;  // cot(theta_k) / 2 at corner k.
  double area = 0.0;
  double conditioning = 0.0;  // kappa^2 s.
};

Triangle triangle(const Eigen::MatrixXd& positions, const Eigen::MatrixX3i& faces, Eigen::Index f) {
  Triangle t;
  Eigen::Vector3d p[3];
  Eigen::MatrixXd corners(3, 3);
  for (int k = 0; k < 3; ++k) {
    p[k] = corner_point(positions, faces(f, k));
    corners.row(k) = p[k].transpose();
  }
  const Eigen::Vector3d normal = (p[1] - p[0]).cross(p[2] - p[0]);
  t.area = 0.5 * normal.norm();
  for (int k = 0; k < 3; ++k)
    t.hat[k] = normal.cross(p[(k + 2) % 3] - p[(k + 1) % 3]) / normal.squaredNorm();
  t.half_cot = cotangent_half_weights(p[0], p[1], p[2]);
  t.conditioning = vulkan::detail::triangle_stiffness_conditioning(corners, 1.0);
  return t;
}

class VulkanCalculus : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(vulkan_test_context());
  }

  static Eigen::MatrixXd run(const std::function<void(VulkanVectors&)>& kernel,
                             VulkanVectors& out) {
    kernel(out);
    const Eigen::MatrixXd first = out.download_device();
    kernel(out);
    const Eigen::MatrixXd second = out.download_device();
    EXPECT_EQ(0, std::memcmp(first.data(), second.data(), sizeof(double) * first.size()))
        << "same input, same bits";
    return first;
  }

  void expect_all_match(const Mesh& mesh, const Eigen::MatrixXd& positions, std::uint32_t seed) {
    const Eigen::MatrixX3i& faces = mesh.faces;
    const int vertex_count = static_cast<int>(positions.rows());
    const int face_count = static_cast<int>(faces.rows());
    auto calculus = gpu_->triangle_calculus(faces, positions);
    std::vector<Triangle> triangles;
    for (int f = 0; f < face_count; ++f) triangles.push_back(triangle(positions, faces, f));
    const int columns = 2;

    // Gradient: G u, rows 3 f + axis (planar positions: compare the first two axes, z is zero).
    const Eigen::MatrixXd values = random_block(vertex_count, columns, seed);
    const auto values_gpu = gpu_->upload(values);
    const auto gradients_gpu = gpu_->allocate(3 * face_count, columns);
    auto& gradients = static_cast<VulkanVectors&>(*gradients_gpu);
    const Eigen::MatrixXd gradient = run(
        [&](VulkanVectors& out) {
          calculus->gradient(static_cast<const VulkanVectors&>(*values_gpu), out);
        },
        gradients);
    const Eigen::SparseMatrix<double> g = gradient_operator(positions, faces);
    const Eigen::MatrixXd expected_gradient = g * values;
    const int dimension = static_cast<int>(positions.cols());
    for (int f = 0; f < face_count; ++f) {
      for (int c = 0; c < columns; ++c) {
        double magnitude = 0.0;
        for (int k = 0; k < 3; ++k)
          magnitude += triangles[f].hat[k].norm() * std::abs(values(faces(f, k), c));
        const double bound =
            vulkan::detail::triangle_term_error_bound(triangles[f].conditioning, magnitude);
        for (int axis = 0; axis < 3; ++axis) {
          const double expected =
              axis < dimension ? expected_gradient(dimension * f + axis, c) : 0.0;
          ASSERT_LE(std::abs(gradient(3 * f + axis, c) - expected), bound)
              << "face " << f << " axis " << axis << " column " << c;
        }
      }
    }

    // Divergence of a random per-triangle field, and the fragment right-hand side.
    const Eigen::MatrixXd field = random_block(3 * face_count, columns, seed + 1);
    const Eigen::MatrixXd fragments = random_block(3 * face_count, columns, seed + 2);
    const auto field_gpu = gpu_->upload(field);
    const auto fragments_gpu = gpu_->upload(fragments);
    const auto sums_gpu = gpu_->allocate(vertex_count, columns);
    auto& sums = static_cast<VulkanVectors&>(*sums_gpu);
    const Eigen::MatrixXd divergence_result = run(
        [&](VulkanVectors& out) {
          calculus->divergence(static_cast<const VulkanVectors&>(*field_gpu), out);
        },
        sums);
    const Eigen::MatrixXd rhs = run(
        [&](VulkanVectors& out) {
          calculus->fragment_poisson_rhs(static_cast<const VulkanVectors&>(*fragments_gpu), out);
        },
        sums);
    const Eigen::MatrixXd expected_rhs = fragment_poisson_rhs(positions, faces, fragments);
    for (int c = 0; c < columns; ++c) {
      Eigen::VectorXd host_field(dimension * face_count);
      for (int f = 0; f < face_count; ++f)
        for (int axis = 0; axis < dimension; ++axis)
          host_field[dimension * f + axis] = field(3 * f + axis, c);
      // (Planar positions: the device reads the z row of the field too, but the hat gradients'
      // z components are exactly zero.)
      const Eigen::VectorXd expected_divergence = divergence(positions, faces, host_field);
      for (int v = 0; v < vertex_count; ++v) {
        double divergence_bound = 0.0, divergence_magnitude = 0.0;
        double rhs_bound = 0.0, rhs_magnitude = 0.0;
        const auto first = calculus->vertex_offsets()[static_cast<std::size_t>(v)];
        const auto last = calculus->vertex_offsets()[static_cast<std::size_t>(v) + 1];
        for (auto entry = first; entry < last; ++entry) {
          const std::uint32_t corner = calculus->corners()[entry];
          const int f = static_cast<int>(corner / 3), k = static_cast<int>(corner % 3);
          const Triangle& t = triangles[static_cast<std::size_t>(f)];
          const double field_norm = field.block(3 * f, c, 3, 1).norm();
          const double divergence_term = t.area * t.hat[k].norm() * field_norm;
          divergence_bound +=
              vulkan::detail::triangle_term_error_bound(t.conditioning, divergence_term);
          divergence_magnitude += divergence_term;
          double rhs_term = 0.0;
          for (int step = 1; step < 3; ++step) {
            const int other = (k + step) % 3, third = (k + 3 - step) % 3;
            rhs_term += std::abs(t.half_cot[third]) *
                        (std::abs(fragments(3 * f + k, c)) + std::abs(fragments(3 * f + other, c)));
          }
          rhs_bound += vulkan::detail::triangle_term_error_bound(t.conditioning, rhs_term);
          rhs_magnitude += rhs_term;
        }
        const double gather = static_cast<double>(last - first) * unit_roundoff;
        ASSERT_LE(std::abs(divergence_result(v, c) - expected_divergence[v]),
                  divergence_bound + gather * divergence_magnitude)
            << "divergence at vertex " << v << " column " << c;
        ASSERT_LE(std::abs(rhs(v, c) - expected_rhs(v, c)), rhs_bound + gather * rhs_magnitude)
            << "fragment rhs at vertex " << v << " column " << c;
      }
    }
  }

  std::unique_ptr<VulkanBackend> gpu_;
};

TEST_F(VulkanCalculus, OnProceduralSurfaces) {
  const Mesh surface = demo_surface(13);
  expect_all_match(surface, surface.vertices, 3);
  const Mesh cap = hemisphere(7);
  expect_all_match(cap, cap.vertices, 5);
}

TEST_F(VulkanCalculus, OnPlanarPositions) {
  const Mesh disk = planar_disk(9, 0.3);
  expect_all_match(disk, disk.vertices.leftCols<2>(), 7);
}

TEST_F(VulkanCalculus, OnACorpusMesh) {
  const auto path = shared_data_dir() / "disk" / "camelhead.obj";
  if (!std::filesystem::exists(path)) HARMONIA_SKIP_WITHOUT_CORPUS("corpus mesh absent: " << path);
  const Mesh mesh = read_mesh(path);
  expect_all_match(mesh, mesh.vertices, 11);
}

TEST_F(VulkanCalculus, TheFragmentsOfAFunctionGiveItsLaplacian) {
  // Unfragmented targets (each corner carries its vertex's value) give b = L x exactly in exact
  // arithmetic: the right-hand side of the Poisson problem whose solution is x itself.
  const Mesh surface = demo_surface(9);
  const Eigen::MatrixXd x = random_block(surface.vertex_count(), 2, 23);
  Eigen::MatrixXd fragments(3 * surface.faces.rows(), 2);
  for (Eigen::Index f = 0; f < surface.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) fragments.row(3 * f + k) = x.row(surface.faces(f, k));
  auto calculus = gpu_->triangle_calculus(surface.faces, surface.vertices);
  const auto fragments_gpu = gpu_->upload(fragments);
  const auto rhs_gpu = gpu_->allocate(surface.vertex_count(), 2);
  calculus->fragment_poisson_rhs(static_cast<const VulkanVectors&>(*fragments_gpu),
                                 static_cast<VulkanVectors&>(*rhs_gpu));
  const Eigen::MatrixXd rhs = static_cast<VulkanVectors&>(*rhs_gpu).download_device();
  const Eigen::MatrixXd expected = laplacian(surface, WeightScheme::cotangent) * x;
  EXPECT_LT((rhs - expected).cwiseAbs().maxCoeff(), 1e-4 * expected.cwiseAbs().maxCoeff());
}

TEST_F(VulkanCalculus, MismatchedBlocksAreRefused) {
  const Mesh surface = demo_surface(5);
  auto calculus = gpu_->triangle_calculus(surface.faces, surface.vertices);
  const auto values = gpu_->allocate(surface.vertex_count() + 1, 1);
  const auto gradients = gpu_->allocate(3 * static_cast<int>(surface.faces.rows()), 1);
  EXPECT_THROW(calculus->gradient(static_cast<const VulkanVectors&>(*values),
                                  static_cast<VulkanVectors&>(*gradients)),
               std::invalid_argument);
}

}  // namespace
}  // namespace harmonia::testing
