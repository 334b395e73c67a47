// Per-triangle assembly on the device (kernels/triangle_assembly.h) against its Eigen twins
// (fallback/triangle_assembly.h: the host cotangent Laplacian and tensor-cotangent operator), on
// lavapipe with validation: procedural meshes, a corpus mesh (skipped when absent), random SPD
// tensors and the quasi-harmonic tensors of a map. Each entry is held to the fp32 bound declared
// next to the kernel, summed over the triangles that contribute to it; the pattern is the host's;
// a second run gives the same bits; a bad face index is refused with its number.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>

#include "fallback/triangle_assembly.h"
#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "kernels/assembly_error_bounds.h"
#include "kernels/triangle_assembly.h"
#include "kernels/triangle_tensors.h"
#include "kernels/vulkan_backend.h"
#include "support/test_support.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using detail::RowMajorSparse;
using vulkan::detail::AssemblySlotMap;
using vulkan::detail::TriangleAssembly;
using vulkan::detail::VulkanBackend;

class VulkanAssembly : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(vulkan_test_context());
  }

  // Same pattern as the twin, every entry within its bound, and the same bits on a second run.
  void expect_matches(TriangleAssembly& assembly, const RowMajorSparse& expected,
                      const Eigen::VectorXd& conditioning, const std::function<void()>& rerun) {
    const RowMajorSparse actual = assembly.download();
    ASSERT_EQ(actual.nonZeros(), expected.nonZeros());
    ASSERT_EQ(0, std::memcmp(actual.outerIndexPtr(), expected.outerIndexPtr(),
                             sizeof(int) * static_cast<std::size_t>(actual.rows() + 1)));
    ASSERT_EQ(0, std::memcmp(actual.innerIndexPtr(), expected.innerIndexPtr(),
                             sizeof(int) * static_cast<std::size_t>(actual.nonZeros())));
    const Eigen::VectorXd bounds = entry_bounds(assembly.slot_map(), conditioning, expected);
    for (int row = 0; row < actual.rows(); ++row) {
      for (int slot = actual.outerIndexPtr()[row]; slot < actual.outerIndexPtr()[row + 1]; ++slot) {
        ASSERT_LE(std::abs(actual.valuePtr()[slot] - expected.valuePtr()[slot]), bounds[slot])
            << "entry (" << row << ", " << actual.innerIndexPtr()[slot] << ") of " << actual.rows()
            << ": " << actual.valuePtr()[slot] << " vs " << expected.valuePtr()[slot];
      }
    }
    // Entries (i, j) and (j, i) sum the same list in the same order: exactly symmetric.
    const RowMajorSparse transposed = actual.transpose();
    EXPECT_EQ((actual - transposed).norm(), 0.0) << "each pair is written once for both sides";
    rerun();
    const RowMajorSparse again = assembly.download();
    EXPECT_EQ(0, std::memcmp(actual.valuePtr(), again.valuePtr(),
                             sizeof(double) * static_cast<std::size_t>(actual.nonZeros())));
  }

  void expect_cotangent_matches(const Mesh& mesh) {
    auto assembly = gpu_->triangle_assembly(mesh.faces, mesh.vertex_count());
    assembly->assemble_cotangent(mesh.vertices);
    Eigen::VectorXd conditioning(mesh.faces.rows());
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
      Eigen::MatrixXd corners(3, 3);
      for (int k = 0; k < 3; ++k) corners.row(k) = mesh.vertices.row(mesh.faces(f, k));
      conditioning[f] = vulkan::detail::triangle_stiffness_conditioning(corners, 1.0);
    }
    expect_matches(*assembly, detail::cpu_cotangent_assembly(mesh), conditioning,
                   [&] { assembly->assemble_cotangent(mesh.vertices); });
  }

  void expect_tensor_matches(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                             const TriangleTensors& tensors) {
    auto assembly = gpu_->triangle_assembly(mesh.faces, mesh.vertex_count());
    assembly->assemble_tensor(uv, tensors);
    Eigen::VectorXd conditioning(mesh.faces.rows());
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
      Eigen::MatrixXd corners(3, 2);
      for (int k = 0; k < 3; ++k) corners.row(k) = uv.row(mesh.faces(f, k));
      conditioning[f] =
          vulkan::detail::triangle_stiffness_conditioning(corners, tensors.row(f).norm());
    }
    expect_matches(*assembly, detail::cpu_tensor_assembly(uv, mesh.faces, tensors), conditioning,
                   [&] { assembly->assemble_tensor(uv, tensors); });
  }

  std::unique_ptr<VulkanBackend> gpu_;
};

TEST_F(VulkanAssembly, SlotMapListsEachTrianglePairOnBothSidesInFaceOrder) {
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 2, 1, 3;
  const AssemblySlotMap map = vulkan::detail::build_assembly_slot_map(faces, 5);
  // Rows: 0 {0,1,2}, 1 {0,1,2,3}, 2 {0,1,2,3}, 3 {1,2,3}, 4 {4} (unused vertex: diagonal only).
  ASSERT_EQ(map.pattern.nonZeros(), 15);
  const auto contributions_of = [&](int row, int col) {
    const int* begin = map.pattern.innerIndexPtr() + map.pattern.outerIndexPtr()[row];
    const int* end = map.pattern.innerIndexPtr() + map.pattern.outerIndexPtr()[row + 1];
    const auto slot = std::lower_bound(begin, end, col) - map.pattern.innerIndexPtr();
    return std::vector<std::uint32_t>(
        map.slot_contributions.begin() + map.slot_offsets[static_cast<std::size_t>(slot)],
        map.slot_contributions.begin() + map.slot_offsets[static_cast<std::size_t>(slot) + 1]);
  };
  // Edge 1-2 is shared: pair (1, 2) of face 0 (index 1) and pair (2, 1) of face 1 (index 3).
  EXPECT_EQ(contributions_of(1, 2), (std::vector<std::uint32_t>{1, 3}));
  EXPECT_EQ(contributions_of(2, 1), (std::vector<std::uint32_t>{1, 3}));
  EXPECT_EQ(contributions_of(0, 2), (std::vector<std::uint32_t>{2}));
  EXPECT_EQ(contributions_of(3, 2), (std::vector<std::uint32_t>{5}));
  EXPECT_TRUE(contributions_of(1, 1).empty()) << "diagonals are recomputed from the row";
  EXPECT_TRUE(contributions_of(4, 4).empty());
}

TEST_F(VulkanAssembly, CotangentOnProceduralMeshes) {
  expect_cotangent_matches(hemisphere(9));
  expect_cotangent_matches(demo_surface(17));
  expect_cotangent_matches(developable_strip(13, 5, 3.0, 1.0, 0.8));
  expect_cotangent_matches(planar_disk(1));  // Tiny: 7 vertices.
}

TEST_F(VulkanAssembly, CotangentOnACorpusMesh) {
  const auto path = shared_data_dir() / "disk" / "camelhead.obj";
  if (!std::filesystem::exists(path)) HARMONIA_SKIP_WITHOUT_CORPUS("corpus mesh absent: " << path);
  expect_cotangent_matches(read_mesh(path));
}

TEST_F(VulkanAssembly, TensorWithRandomSpdTensors) {
  const Mesh disk = planar_disk(11, 0.3);
  const Eigen::MatrixX2d uv = disk.vertices.leftCols<2>();
  std::mt19937 generator(17);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  TriangleTensors tensors(disk.faces.rows(), 4);
  for (Eigen::Index f = 0; f < tensors.rows(); ++f) {
    Eigen::Matrix2d root;
    root << entry(generator), entry(generator), entry(generator), entry(generator);
    const Eigen::Matrix2d spd = root * root.transpose() + 0.1 * Eigen::Matrix2d::Identity();
    // A non-symmetric part too: only the symmetric part may count.
    tensors.row(f) << spd(0, 0), spd(0, 1) + 0.25, spd(1, 0) - 0.25, spd(1, 1);
  }
  expect_tensor_matches(disk, uv, tensors);
}

TEST_F(VulkanAssembly, TensorWithQuasiHarmonicTensorsOfAHeightField) {
  const Mesh surface = demo_surface(15);
  const Eigen::MatrixX2d uv = surface.vertices.leftCols<2>();  // Projection of a height field.
  expect_tensor_matches(surface, uv, quasi_harmonic_tensors(surface, uv));
}

// Device tensors against quasi_harmonic_tensors within the declared bound; then the operator the
// same submission assembled against the host operator of those very (widened fp32) tensors.
void expect_quasi_harmonic_matches(VulkanBackend& gpu, const Mesh& mesh,
                                   const Eigen::MatrixX2d& uv) {
  auto assembly = gpu.triangle_assembly(mesh.faces, mesh.vertex_count());
  assembly->assemble_quasi_harmonic(mesh.vertices, uv);
  const TriangleTensors actual = assembly->download_tensors();
  const TriangleTensors expected = quasi_harmonic_tensors(mesh, uv);
  const TriangleTensors forms = first_fundamental_forms(mesh, uv);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    Eigen::Matrix3d corners;
    Eigen::Matrix<double, 3, 2> corners_uv;
    for (int k = 0; k < 3; ++k) {
      corners.row(k) = mesh.vertices.row(mesh.faces(f, k));
      corners_uv.row(k) = uv.row(mesh.faces(f, k));
    }
    const double bound =
        vulkan::detail::triangle_tensor_error_bound(vulkan::detail::triangle_tensor_conditioning(
            corners, corners_uv, forms.row(f).transpose(), expected.row(f).transpose()));
    for (int entry = 0; entry < 4; ++entry)
      ASSERT_LE(std::abs(actual(f, entry) - expected(f, entry)), bound)
          << "face " << f << " entry " << entry << ": " << actual.row(f) << " vs "
          << expected.row(f);
  }
  const RowMajorSparse operator_actual = assembly->download();
  const RowMajorSparse operator_expected = detail::cpu_tensor_assembly(uv, mesh.faces, actual);
  ASSERT_EQ(operator_actual.nonZeros(), operator_expected.nonZeros());
  Eigen::VectorXd conditioning(mesh.faces.rows());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    Eigen::MatrixXd corners(3, 2);
    for (int k = 0; k < 3; ++k) corners.row(k) = uv.row(mesh.faces(f, k));
    conditioning[f] =
        vulkan::detail::triangle_stiffness_conditioning(corners, actual.row(f).norm());
  }
  const Eigen::VectorXd bounds =
      entry_bounds(assembly->slot_map(), conditioning, operator_expected);
  for (Eigen::Index slot = 0; slot < operator_actual.nonZeros(); ++slot)
    ASSERT_LE(std::abs(operator_actual.valuePtr()[slot] - operator_expected.valuePtr()[slot]),
              bounds[slot])
        << "slot " << slot;
}

TEST_F(VulkanAssembly, QuasiHarmonicTensorsOfAHeightFieldProjection) {
  const Mesh surface = demo_surface(15);
  expect_quasi_harmonic_matches(*gpu_, surface, surface.vertices.leftCols<2>());
  const Mesh cap = hemisphere(8);  // Steep triangles near the equator: large cond(I).
  expect_quasi_harmonic_matches(*gpu_, cap, cap.vertices.leftCols<2>());
}

TEST_F(VulkanAssembly, QuasiHarmonicTensorsOfAnIsometryAreTheIdentity) {
  // A strip rolled onto a cylinder, its grid columns one angle step apart: each 3D triangle spans
  // a chord 2 r sin(step / 2) across and the full height, so laying the columns out at that chord
  // spacing gives a flat triangle congruent to it. J is then an isometry and C = Id.
  const int nu = 9, nv = 4;
  const double radius = 0.7;
  const Mesh strip = developable_strip(nu, nv, 2.0, 1.0, radius);
  std::vector<double> angles;
  for (int v = 0; v < strip.vertex_count(); ++v)
    angles.push_back(std::atan2(strip.vertices(v, 0), radius - strip.vertices(v, 2)));
  std::vector<double> distinct = angles;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end(),
                             [](double a, double b) { return std::abs(a - b) < 1e-9; }),
                 distinct.end());
  const double step = distinct[1] - distinct[0];
  const double chord = 2.0 * radius * std::sin(0.5 * step);
  Eigen::MatrixX2d flat(strip.vertex_count(), 2);
  for (int v = 0; v < strip.vertex_count(); ++v)
    flat.row(v) << chord * std::round((angles[static_cast<std::size_t>(v)] - distinct[0]) / step),
        strip.vertices(v, 1);
  expect_quasi_harmonic_matches(*gpu_, strip, flat);
  auto assembly = gpu_->triangle_assembly(strip.faces, strip.vertex_count());
  assembly->assemble_quasi_harmonic(strip.vertices, flat);
  const TriangleTensors tensors = assembly->download_tensors();
  for (Eigen::Index f = 0; f < tensors.rows(); ++f)
    EXPECT_LT((tensors.row(f) - Eigen::RowVector4d(1, 0, 0, 1)).norm(), 1e-4) << "face " << f;
}

TEST_F(VulkanAssembly, AZeroAreaUvTriangleGetsTheInfiniteMarkerAndContributesNothing) {
  Mesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 1;
  mesh.faces.resize(2, 3);
  mesh.faces << 0, 1, 2, 1, 3, 2;
  Eigen::MatrixX2d uv(4, 2);
  uv << 0, 0, 1, 0, 0, 1, 0.5, 0.5;  // Face 1 collapses onto the segment 1-2.
  auto assembly = gpu_->triangle_assembly(mesh.faces, mesh.vertex_count());
  assembly->assemble_quasi_harmonic(mesh.vertices, uv);
  const TriangleTensors tensors = assembly->download_tensors();
  EXPECT_TRUE(tensors.row(0).allFinite());
  for (int entry = 0; entry < 4; ++entry) EXPECT_TRUE(std::isinf(tensors(1, entry)));
  const RowMajorSparse assembled = assembly->download();
  EXPECT_EQ(assembled.coeff(3, 3), 0.0) << "vertex 3 only touches the collapsed face";
  EXPECT_TRUE(Eigen::MatrixXd(assembled).allFinite());
}

TEST_F(VulkanAssembly, ABadFaceIndexIsNamed) {
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 2, 1, 7;
  try {
    (void)gpu_->triangle_assembly(faces, 4);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("face 1"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace harmonia::testing
