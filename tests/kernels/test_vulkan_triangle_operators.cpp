// The Vulkan backend's per-triangle operators (kernels/vulkan_triangle_operators.h) against the
// CPU backend's (the host functions), on lavapipe with validation: small corpus meshes (skipped
// when absent) and a procedural surface, each with the layout of its mean-value map on the circle
// (valid by Tutte's theorem). Every matrix has the host's pattern and each entry is within the
// fp32 bound declared next to the assembly kernel (kernels/triangle_assembly.h), summed over what
// it gathers; the tensors are within the bound of kernels/triangle_tensors.h; the fragment
// right-hand side within that of the corner kernels (kernels/triangle_calculus.h), also after the
// positions change.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "fallback/cpu_backend.h"
#include "harmonia/fixed_boundary_map.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "kernels/assembly_error_bounds.h"
#include "kernels/triangle_assembly.h"
#include "kernels/triangle_calculus.h"
#include "kernels/triangle_tensors.h"
#include "kernels/vulkan_backend.h"
#include "support/test_support.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using detail::RowMajorSparse;
using detail::TriangleOperators;

constexpr double unit_roundoff = 0x1p-24;

struct Surface {
  std::string name;
  Mesh mesh;
  Eigen::MatrixX2d uv;  // A valid layout: the mean-value map on the circle.
};

std::vector<Surface> surfaces() {
  std::vector<Mesh> meshes;
  std::vector<std::string> names;
  for (const char* name : {"woody", "snail", "camel_b"}) {
    const std::filesystem::path path = shared_data_dir() / "disk" / (std::string(name) + ".obj");
    if (!std::filesystem::exists(path)) continue;
    meshes.push_back(read_mesh(path));
    names.emplace_back(name);
  }
  meshes.push_back(hemisphere(10));
  names.emplace_back("hemisphere(10)");
  std::vector<Surface> result;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    FixedBoundaryOptions options;
    options.weights = WeightScheme::mean_value;
    options.normalization = UvNormalization::none;
    const MapResult layout = fixed_boundary_map(meshes[k], options);
    EXPECT_TRUE(layout.report.ok()) << names[k] << ": " << layout.report.message;
    result.push_back({names[k], meshes[k], layout.uv});
  }
  return result;
}

Eigen::MatrixXd corners_of(const Mesh& mesh, Eigen::Index f, const Eigen::MatrixXd& points) {
  Eigen::MatrixXd corners(3, points.cols());
  for (int k = 0; k < 3; ++k) corners.row(k) = points.row(mesh.faces(f, k));
  return corners;
}

// Same pattern as the CPU's (column-major, as the host functions return it), exactly symmetric,
// and every entry within its bound (`conditioning`: the stiffness conditioning of every face).
void expect_operator_within_bounds(const Eigen::SparseMatrix<double>& actual,
                                   const Eigen::SparseMatrix<double>& expected, const Mesh& mesh,
                                   const Eigen::VectorXd& conditioning, const std::string& what) {
  ASSERT_TRUE(actual.isCompressed()) << what;
  ASSERT_EQ(actual.nonZeros(), expected.nonZeros()) << what;
  ASSERT_EQ(0, std::memcmp(actual.outerIndexPtr(), expected.outerIndexPtr(),
                           sizeof(int) * static_cast<std::size_t>(actual.outerSize() + 1)))
      << what;
  ASSERT_EQ(0, std::memcmp(actual.innerIndexPtr(), expected.innerIndexPtr(),
                           sizeof(int) * static_cast<std::size_t>(actual.nonZeros())))
      << what;
  EXPECT_EQ((actual - Eigen::SparseMatrix<double>(actual.transpose())).norm(), 0.0) << what;
  // The bounds follow the device's row-major slots.
  const RowMajorSparse actual_rows = actual, expected_rows = expected;
  const Eigen::VectorXd bounds = entry_bounds(
      vulkan::detail::build_assembly_slot_map(mesh.faces, mesh.vertex_count()), conditioning,
      expected_rows);
  for (int row = 0; row < actual_rows.rows(); ++row)
    for (int slot = actual_rows.outerIndexPtr()[row]; slot < actual_rows.outerIndexPtr()[row + 1];
         ++slot)
      ASSERT_LE(std::abs(actual_rows.valuePtr()[slot] - expected_rows.valuePtr()[slot]),
                bounds[slot])
          << what << ": entry (" << row << ", " << actual_rows.innerIndexPtr()[slot] << ")";
}

class VulkanTriangleOperators : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
    gpu_ = std::make_unique<vulkan::detail::VulkanBackend>(vulkan_test_context());
  }

  std::unique_ptr<vulkan::detail::VulkanBackend> gpu_;
  detail::CpuBackend cpu_;
};

TEST_F(VulkanTriangleOperators, CotangentLaplacian) {
  for (const Surface& surface : surfaces()) {
    const Mesh& mesh = surface.mesh;
    const auto on_gpu = gpu_->triangle_operators(mesh.faces, mesh.vertex_count());
    const auto on_cpu = cpu_.triangle_operators(mesh.faces, mesh.vertex_count());
    Eigen::VectorXd conditioning(mesh.faces.rows());
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      conditioning[f] = vulkan::detail::triangle_stiffness_conditioning(
          corners_of(mesh, f, mesh.vertices), 1.0);
    expect_operator_within_bounds(on_gpu->cotangent(mesh.vertices),
                                  on_cpu->cotangent(mesh.vertices), mesh, conditioning,
                                  surface.name + " cotangent");
  }
}

TEST_F(VulkanTriangleOperators, TensorCotangentUnderTheQuasiHarmonicTensorsOfTheLayout) {
  for (const Surface& surface : surfaces()) {
    const Mesh& mesh = surface.mesh;
    const TriangleTensors tensors = quasi_harmonic_tensors(mesh, surface.uv);
    const auto on_gpu = gpu_->triangle_operators(mesh.faces, mesh.vertex_count());
    const auto on_cpu = cpu_.triangle_operators(mesh.faces, mesh.vertex_count());
    Eigen::VectorXd conditioning(mesh.faces.rows());
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      conditioning[f] = vulkan::detail::triangle_stiffness_conditioning(
          corners_of(mesh, f, surface.uv), tensors.row(f).norm());
    expect_operator_within_bounds(on_gpu->tensor_cotangent(surface.uv, tensors),
                                  on_cpu->tensor_cotangent(surface.uv, tensors), mesh,
                                  conditioning, surface.name + " tensor-cotangent");
  }
}

// The device's tensors against the CPU's within the declared bound; then its operator against the
// CPU operator of those very (widened fp32) tensors.
TEST_F(VulkanTriangleOperators, QuasiHarmonicTensorsAndOperatorOfTheLayout) {
  for (const Surface& surface : surfaces()) {
    const Mesh& mesh = surface.mesh;
    const auto on_gpu = gpu_->triangle_operators(mesh.faces, mesh.vertex_count());
    const auto on_cpu = cpu_.triangle_operators(mesh.faces, mesh.vertex_count());
    const detail::QuasiHarmonicOperator actual = on_gpu->quasi_harmonic(mesh.vertices, surface.uv);
    const detail::QuasiHarmonicOperator expected =
        on_cpu->quasi_harmonic(mesh.vertices, surface.uv);
    const TriangleTensors forms = first_fundamental_forms(mesh, surface.uv);
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
      const double bound = vulkan::detail::triangle_tensor_error_bound(
          vulkan::detail::triangle_tensor_conditioning(
              corners_of(mesh, f, mesh.vertices), corners_of(mesh, f, surface.uv),
              forms.row(f).transpose(), expected.tensors.row(f).transpose()));
      for (int entry = 0; entry < 4; ++entry)
        ASSERT_LE(std::abs(actual.tensors(f, entry) - expected.tensors(f, entry)), bound)
            << surface.name << ": face " << f << " entry " << entry;
    }
    Eigen::VectorXd conditioning(mesh.faces.rows());
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      conditioning[f] = vulkan::detail::triangle_stiffness_conditioning(
          corners_of(mesh, f, surface.uv), actual.tensors.row(f).norm());
    expect_operator_within_bounds(actual.matrix,
                                  on_cpu->tensor_cotangent(surface.uv, actual.tensors), mesh,
                                  conditioning, surface.name + " quasi-harmonic operator");
  }
}

// Fragments as the free-boundary map makes them: each face's layout triangle turned by its own
// angle and stretched. Each vertex's value is held to the per-corner bound summed over its
// corners plus the gather's rounding; a second surface through the same operators checks that new
// positions are used.
TEST_F(VulkanTriangleOperators, FragmentPoissonRightHandSide) {
  for (const Surface& surface : surfaces()) {
    const Mesh& mesh = surface.mesh;
    const auto face_count = static_cast<int>(mesh.faces.rows());
    std::mt19937 generator(29);
    std::uniform_real_distribution<double> angle(-3.0, 3.0), stretch(0.5, 2.0);
    Eigen::MatrixXd fragments(3 * face_count, 2);
    for (int f = 0; f < face_count; ++f) {
      const double c = std::cos(angle(generator)), s = std::sin(angle(generator));
      Eigen::Matrix2d shape;
      shape << c, -s, s, c;
      shape *= stretch(generator);
      for (int k = 0; k < 3; ++k)
        fragments.row(3 * f + k) = (shape * surface.uv.row(mesh.faces(f, k)).transpose()).transpose();
    }
    Eigen::MatrixX3d bent = mesh.vertices;
    bent.col(2) += 0.3 * bent.col(0).cwiseProduct(bent.col(1));
    const auto on_gpu = gpu_->triangle_operators(mesh.faces, mesh.vertex_count());
    const auto on_cpu = cpu_.triangle_operators(mesh.faces, mesh.vertex_count());
    for (const Eigen::MatrixX3d& positions : {mesh.vertices, bent}) {
      const Eigen::MatrixXd actual = on_gpu->fragment_poisson_rhs(positions, fragments);
      const Eigen::MatrixXd expected = on_cpu->fragment_poisson_rhs(positions, fragments);
      ASSERT_EQ(actual.rows(), mesh.vertex_count());
      ASSERT_EQ(actual.cols(), 2);
      Eigen::MatrixXd bound = Eigen::MatrixXd::Zero(mesh.vertex_count(), 2);
      Eigen::MatrixXd magnitude = Eigen::MatrixXd::Zero(mesh.vertex_count(), 2);
      Eigen::VectorXi corner_count = Eigen::VectorXi::Zero(mesh.vertex_count());
      for (int f = 0; f < face_count; ++f) {
        const Eigen::MatrixXd corners = corners_of(mesh, f, positions);
        const double conditioning = vulkan::detail::triangle_stiffness_conditioning(corners, 1.0);
        const Eigen::Vector3d half_cot = cotangent_half_weights(
            corners.row(0).transpose(), corners.row(1).transpose(), corners.row(2).transpose());
        for (int k = 0; k < 3; ++k) {
          const int v = mesh.faces(f, k);
          ++corner_count[v];
          for (int c = 0; c < 2; ++c) {
            // Corner k's term: cot / 2 at the third corner times the difference with each other.
            double term = 0.0;
            for (int step = 1; step < 3; ++step) {
              const int other = (k + step) % 3, third = (k + 3 - step) % 3;
              term += std::abs(half_cot[third]) * (std::abs(fragments(3 * f + k, c)) +
                                                   std::abs(fragments(3 * f + other, c)));
            }
            bound(v, c) += vulkan::detail::triangle_term_error_bound(conditioning, term);
            magnitude(v, c) += term;
          }
        }
      }
      for (int v = 0; v < mesh.vertex_count(); ++v)
        for (int c = 0; c < 2; ++c)
          ASSERT_LE(std::abs(actual(v, c) - expected(v, c)),
                    bound(v, c) + corner_count[v] * unit_roundoff * magnitude(v, c))
              << surface.name << ": vertex " << v << " column " << c;
    }
  }
}

TEST_F(VulkanTriangleOperators, ABadFaceIndexIsNamedByBothBackends) {
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 2, 1, 7;
  for (detail::Backend* backend : {static_cast<detail::Backend*>(gpu_.get()),
                                   static_cast<detail::Backend*>(&cpu_)}) {
    try {
      (void)backend->triangle_operators(faces, 4);
      ADD_FAILURE() << backend->description() << ": no error";
    } catch (const Error& error) {
      EXPECT_EQ(error.status(), Status::invalid_input);
      EXPECT_NE(std::string(error.what()).find("face 1"), std::string::npos) << error.what();
    }
  }
}

}  // namespace
}  // namespace harmonia::testing
