// The CPU backend's per-triangle operators (fallback/cpu_triangle_operators.h) are the host
// functions: the same bits as harmonia::laplacian, tensor_cotangent_laplacian and
// quasi_harmonic_tensors, so that a map assembling through the backend interface computes on the
// CPU exactly what it computed before; the fragment right-hand side is
// harmonia::fragment_poisson_rhs up to the order of its sums.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "fallback/cpu_backend.h"
#include "harmonia/gradient.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "harmonia/types.h"
#include "support/test_support.h"

namespace harmonia::testing {
namespace {

void expect_same_bits(const Eigen::SparseMatrix<double>& actual,
                      const Eigen::SparseMatrix<double>& expected, const char* what) {
  ASSERT_TRUE(actual.isCompressed()) << what;
  ASSERT_EQ(actual.nonZeros(), expected.nonZeros()) << what;
  EXPECT_EQ(0, std::memcmp(actual.outerIndexPtr(), expected.outerIndexPtr(),
                           sizeof(int) * static_cast<std::size_t>(actual.outerSize() + 1)))
      << what;
  EXPECT_EQ(0, std::memcmp(actual.innerIndexPtr(), expected.innerIndexPtr(),
                           sizeof(int) * static_cast<std::size_t>(actual.nonZeros())))
      << what;
  EXPECT_EQ(0, std::memcmp(actual.valuePtr(), expected.valuePtr(),
                           sizeof(double) * static_cast<std::size_t>(actual.nonZeros())))
      << what;
}

TEST(CpuTriangleOperators, AreTheHostFunctions) {
  const Mesh surface = demo_surface(12);
  const Eigen::MatrixX2d uv = surface.vertices.leftCols<2>();  // Projection of a height field.
  detail::CpuBackend cpu;
  const auto operators = cpu.triangle_operators(surface.faces, surface.vertex_count());
  expect_same_bits(operators->cotangent(surface.vertices),
                   laplacian(surface, WeightScheme::cotangent), "cotangent");
  const TriangleTensors tensors = quasi_harmonic_tensors(surface, uv);
  expect_same_bits(operators->tensor_cotangent(uv, tensors),
                   tensor_cotangent_laplacian(uv, surface.faces, tensors), "tensor-cotangent");
  const detail::QuasiHarmonicOperator quasi_harmonic = operators->quasi_harmonic(surface.vertices, uv);
  EXPECT_EQ(0, std::memcmp(quasi_harmonic.tensors.data(), tensors.data(),
                           sizeof(double) * static_cast<std::size_t>(tensors.size())));
  expect_same_bits(quasi_harmonic.matrix, tensor_cotangent_laplacian(uv, surface.faces, tensors),
                   "quasi-harmonic");
}

// Both sum the same terms, cot / 2 times a difference of a face's fragment corners, in another
// order: per vertex at most 2 n u times the sum of the |terms|, for n terms and u = 2^-53.
TEST(CpuTriangleOperators, TheFragmentRightHandSideIsTheHostOne) {
  const Mesh surface = hemisphere(9);
  std::mt19937 generator(13);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd fragments(3 * surface.face_count(), 2);
  for (Eigen::Index k = 0; k < fragments.size(); ++k) fragments.data()[k] = value(generator);
  detail::CpuBackend cpu;
  const auto operators = cpu.triangle_operators(surface.faces, surface.vertex_count());
  const Eigen::MatrixXd actual = operators->fragment_poisson_rhs(surface.vertices, fragments);
  const Eigen::MatrixXd expected = fragment_poisson_rhs(surface.vertices, surface.faces, fragments);
  Eigen::MatrixXd magnitude = Eigen::MatrixXd::Zero(surface.vertex_count(), 2);
  Eigen::VectorXd term_count = Eigen::VectorXd::Zero(surface.vertex_count());
  for (int f = 0; f < surface.face_count(); ++f) {
    const Eigen::Vector3d half_cot = cotangent_half_weights(
        surface.vertices.row(surface.faces(f, 0)), surface.vertices.row(surface.faces(f, 1)),
        surface.vertices.row(surface.faces(f, 2)));
    for (int k = 0; k < 3; ++k) {
      // The edge (a, b) opposite corner k hands a term to both of its ends.
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      for (const int end : {a, b}) {
        term_count[surface.faces(f, end)] += 1.0;
        for (int c = 0; c < 2; ++c)
          magnitude(surface.faces(f, end), c) +=
              std::abs(half_cot[k] * (fragments(3 * f + a, c) - fragments(3 * f + b, c)));
      }
    }
  }
  for (int v = 0; v < surface.vertex_count(); ++v)
    for (int c = 0; c < 2; ++c)
      ASSERT_LE(std::abs(actual(v, c) - expected(v, c)),
                2.0 * term_count[v] * 0x1p-53 * magnitude(v, c))
          << "vertex " << v << " column " << c;
}

TEST(CpuTriangleOperators, ABadFaceIndexIsNamed) {
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 2, 1, 7;
  detail::CpuBackend cpu;
  try {
    (void)cpu.triangle_operators(faces, 4);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("face 1"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace harmonia::testing
