// Tests of the Laplacian family (thesis chapter 4): kernel, symmetry, linear precision on a planar
// disk, positivity, the finite-element identity L = G^T diag(area) G, names, determinism, errors.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "harmonia/gradient.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "harmonia/types.h"

namespace harmonia {
namespace {

constexpr WeightScheme linear_precision_schemes[] = {
    WeightScheme::cotangent,     WeightScheme::mean_value,
    WeightScheme::linear_precision, WeightScheme::least_squares,
    WeightScheme::least_squares_positive, WeightScheme::shape_preserving};

// A hemisphere whose vertices are pushed around tangentially by a deterministic hash, so that many
// triangles become obtuse (negative cotangent weights appear) while none flips.
Mesh jittered_hemisphere(int rings, double amount) {
  Mesh mesh = hemisphere(rings);
  for (Eigen::Index v = 1; v < mesh.vertices.rows(); ++v) {
    const double a = std::sin(12.9898 * static_cast<double>(v)) * 43758.5453;
    const double b = std::sin(78.233 * static_cast<double>(v)) * 12543.1234;
    Eigen::Vector3d p = mesh.vertices.row(v);
    if (p.z() < 1e-12) continue;  // keep the equator on the plane z = 0
    p += amount / rings * Eigen::Vector3d(a - std::floor(a) - 0.5, b - std::floor(b) - 0.5, 0.0);
    mesh.vertices.row(v) = p.normalized();
  }
  return mesh;
}

std::vector<bool> boundary_flags(const Mesh& mesh) {
  // A vertex is on the boundary when one of its edges is used by a single face.
  std::vector<bool> flags(static_cast<std::size_t>(mesh.vertex_count()), false);
  Eigen::SparseMatrix<int> edge_use(mesh.vertex_count(), mesh.vertex_count());
  std::vector<Eigen::Triplet<int>> triplets;
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int i = mesh.faces(f, k), j = mesh.faces(f, (k + 1) % 3);
      triplets.emplace_back(std::min(i, j), std::max(i, j), 1);
    }
  edge_use.setFromTriplets(triplets.begin(), triplets.end());
  for (int col = 0; col < edge_use.outerSize(); ++col)
    for (Eigen::SparseMatrix<int>::InnerIterator it(edge_use, col); it; ++it)
      if (it.value() == 1) flags[static_cast<std::size_t>(it.row())] = flags[static_cast<std::size_t>(it.col())] = true;
  return flags;
}

double max_abs(const Eigen::SparseMatrix<double>& matrix) {
  double largest = 0.0;
  for (int col = 0; col < matrix.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, col); it; ++it)
      largest = std::max(largest, std::abs(it.value()));
  return largest;
}

TEST(Laplacian, ConstantsAreInTheKernelForEveryScheme) {
  const Mesh mesh = jittered_hemisphere(6, 0.6);
  for (const WeightScheme scheme : all_weight_schemes()) {
    const Eigen::SparseMatrix<double> L = laplacian(mesh, scheme);
    ASSERT_EQ(L.rows(), mesh.vertex_count());
    ASSERT_EQ(L.cols(), mesh.vertex_count());
    const Eigen::VectorXd applied = L * Eigen::VectorXd::Ones(mesh.vertex_count());
    EXPECT_LT(applied.cwiseAbs().maxCoeff(), 1e-12 * max_abs(L)) << to_string(scheme);
    // Every vertex has a row: a strictly positive diagonal (all vertices are used by faces).
    EXPECT_GT(L.diagonal().minCoeff(), 0.0) << to_string(scheme);
  }
}

TEST(Laplacian, SymmetricSchemesAreSymmetricAndOthersAreNot) {
  const Mesh mesh = jittered_hemisphere(6, 0.6);
  for (const WeightScheme scheme : all_weight_schemes()) {
    const Eigen::SparseMatrix<double> L = laplacian(mesh, scheme);
    const Eigen::SparseMatrix<double> transposed = L.transpose();
    const double asymmetry = max_abs(L - transposed) / max_abs(L);
    if (is_symmetric(scheme)) {
      EXPECT_EQ(asymmetry, 0.0) << to_string(scheme);
    } else {
      EXPECT_GT(asymmetry, 1e-6) << to_string(scheme);
    }
  }
}

TEST(Laplacian, LinearFunctionsAreReproducedOnAPlanarDiskExceptByUniformWeights) {
  const Mesh disk = planar_disk(8, 1.0);
  const std::vector<bool> boundary = boundary_flags(disk);
  const Eigen::VectorXd x = disk.vertices.col(0), y = disk.vertices.col(1);
  const auto worst_interior = [&](const Eigen::VectorXd& values) {
    double worst = 0.0;
    for (int v = 0; v < disk.vertex_count(); ++v)
      if (!boundary[static_cast<std::size_t>(v)]) worst = std::max(worst, std::abs(values[v]));
    return worst;
  };
  for (const WeightScheme scheme : linear_precision_schemes) {
    const Eigen::SparseMatrix<double> L = laplacian(disk, scheme);
    EXPECT_LT(worst_interior(L * x), 1e-10) << to_string(scheme);
    EXPECT_LT(worst_interior(L * y), 1e-10) << to_string(scheme);
  }
  // The finite-difference weights are not linear-precision on a jittered grid: a clear failure.
  const Eigen::SparseMatrix<double> uniform = laplacian(disk, WeightScheme::uniform);
  EXPECT_GT(worst_interior(uniform * x) + worst_interior(uniform * y), 1e-3);
  // Chord weights neither (the angles are not regular).
  const Eigen::SparseMatrix<double> chord = laplacian(disk, WeightScheme::chord_length);
  EXPECT_GT(worst_interior(chord * x) + worst_interior(chord * y), 1e-3);
}

TEST(Laplacian, PositiveSchemesHavePositiveWeightsWhereCotangentDoesNot) {
  const Mesh mesh = jittered_hemisphere(7, 0.9);
  // The mesh must really have obtuse pairs: some cotangent weight is negative.
  const Eigen::SparseMatrix<double> cotangent = laplacian(mesh, WeightScheme::cotangent);
  int negative_cotangent = 0;
  for (int col = 0; col < cotangent.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(cotangent, col); it; ++it)
      if (it.row() != it.col() && -it.value() < 0.0) ++negative_cotangent;
  ASSERT_GT(negative_cotangent, 0);

  for (const WeightScheme scheme : all_weight_schemes()) {
    if (!has_positive_weights(scheme)) continue;
    const Eigen::SparseMatrix<double> L = laplacian(mesh, scheme);
    int off_diagonal = 0;
    for (int col = 0; col < L.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(L, col); it; ++it) {
        if (it.row() == it.col()) continue;
        ++off_diagonal;
        EXPECT_GT(-it.value(), 0.0) << to_string(scheme) << " w(" << it.row() << "," << it.col() << ")";
      }
    EXPECT_EQ(off_diagonal, 2 * (mesh.vertex_count() + mesh.face_count() - 1));  // 2E, disk: E = V+F-1
  }
}

TEST(Laplacian, CotangentEqualsGradientTransposeAreaGradient) {
  for (const Mesh& mesh : {jittered_hemisphere(6, 0.8), planar_disk(5, 1.0), demo_surface(6)}) {
    const Eigen::SparseMatrix<double> L = laplacian(mesh, WeightScheme::cotangent);
    const Eigen::SparseMatrix<double> G = gradient_operator(mesh.vertices, mesh.faces);
    const Eigen::VectorXd areas = triangle_areas(mesh.vertices, mesh.faces);
    Eigen::VectorXd repeated(3 * areas.size());
    for (Eigen::Index f = 0; f < areas.size(); ++f) repeated.segment<3>(3 * f).setConstant(areas[f]);
    const Eigen::SparseMatrix<double> finite_element = G.transpose() * repeated.asDiagonal() * G;
    EXPECT_LT(max_abs(L - finite_element), 1e-12 * max_abs(L));
  }
}

TEST(Laplacian, UniformAndChordWeightsAreTheDefinitions) {
  const Mesh mesh = jittered_hemisphere(4, 0.5);
  const Eigen::SparseMatrix<double> uniform = laplacian(mesh, WeightScheme::uniform);
  const Eigen::SparseMatrix<double> chord = laplacian(mesh, WeightScheme::chord_length);
  // Pole: vertex 0 has the six first-ring vertices 1..6 as neighbours.
  EXPECT_EQ(uniform.coeff(0, 0), 6.0);
  for (int j = 1; j <= 6; ++j) {
    EXPECT_EQ(uniform.coeff(0, j), -1.0);
    const double length = (mesh.vertices.row(0) - mesh.vertices.row(j)).norm();
    EXPECT_DOUBLE_EQ(chord.coeff(0, j), -1.0 / length);
  }
}

TEST(Laplacian, MeanValueWeightsMatchTheTangentFormula) {
  const Mesh mesh = jittered_hemisphere(4, 0.5);
  const Eigen::SparseMatrix<double> L = laplacian(mesh, WeightScheme::mean_value);
  // Edge (0, 1) of the pole: the two triangles beside it are (0, 6, 1)... found by search.
  const int i = 0, j = 1;
  double expected = 0.0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.faces(f, k) != i) continue;
      const int a = mesh.faces(f, (k + 1) % 3), b = mesh.faces(f, (k + 2) % 3);
      if (a != j && b != j) continue;
      const Eigen::Vector3d u = mesh.vertices.row(a) - mesh.vertices.row(i);
      const Eigen::Vector3d v = mesh.vertices.row(b) - mesh.vertices.row(i);
      const double angle = std::acos(u.normalized().dot(v.normalized()));
      expected += std::tan(angle / 2.0) / (mesh.vertices.row(j) - mesh.vertices.row(i)).norm();
    }
  }
  EXPECT_NEAR(-L.coeff(i, j), expected, 1e-12 * expected);
}

TEST(Laplacian, CotangentHalfWeightsOfARightIsoscelesTriangle) {
  // Angles 90, 45, 45 degrees: cotangents 0, 1, 1.
  const Eigen::Vector3d w = cotangent_half_weights({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  EXPECT_NEAR(w[0], 0.0, 1e-15);
  EXPECT_NEAR(w[1], 0.5, 1e-15);
  EXPECT_NEAR(w[2], 0.5, 1e-15);
  // Equilateral: cot 60 / 2 at each corner.
  const Eigen::Vector3d e = cotangent_half_weights({0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0});
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(e[k], 0.5 / std::sqrt(3.0), 1e-15);
  // Degenerate: zero weights, not infinities.
  EXPECT_EQ(cotangent_half_weights({0, 0, 0}, {1, 0, 0}, {2, 0, 0}), Eigen::Vector3d::Zero());
}

// How the weights of a row go with the model's length: as length^degree (the test below says why).
int row_degree(WeightScheme scheme, bool boundary_vertex) {
  switch (scheme) {
    case WeightScheme::uniform:
    case WeightScheme::cotangent:
    case WeightScheme::linear_precision: return 0;
    case WeightScheme::chord_length:
    case WeightScheme::mean_value: return -1;
    case WeightScheme::least_squares: return -2;
    case WeightScheme::least_squares_positive: return boundary_vertex ? -1 : -2;
    case WeightScheme::shape_preserving: return boundary_vertex ? -1 : 0;
  }
  return 0;
}

// Every scheme works at every scale of the model: the weights at 2^-330 (about 1e-100), 2^330, 2^-500
// and 2^500 units are the unit-size ones times scale^degree exactly (power-of-two scaling), where a
// row's degree is how its weights go with length: 0 (uniform, cotangent, linear precision, shape
// preserving), -1 (chord, mean value, and the mean value rows that the positive ring schemes fall
// back to at boundary vertices), -2 (least squares, 4.58-4.59). At 1e-100 the cotangents' |u x v|
// used to underflow to 0 and the ring schemes' flattened rings to degenerate.
TEST(Laplacian, EverySchemeGivesTheSameWeightsAtEveryScale) {
  const Mesh unit = planar_disk(6, 0.3);
  Mesh bent = hemisphere(6);
  for (const Mesh& mesh : {unit, bent}) {
    std::vector<bool> on_boundary(static_cast<std::size_t>(mesh.vertex_count()), false);
    for (const std::vector<int>& loop : boundary_loops(mesh)) {
      for (const int vertex : loop) on_boundary[static_cast<std::size_t>(vertex)] = true;
    }
    for (const int exponent : {-330, 330, -500, 500}) {
      Mesh scaled = mesh;
      scaled.vertices *= std::ldexp(1.0, exponent);
      for (const WeightScheme scheme : all_weight_schemes()) {
        const Eigen::MatrixXd unit_weights = Eigen::MatrixXd(laplacian(mesh, scheme));
        const Eigen::MatrixXd weights = Eigen::MatrixXd(laplacian(scaled, scheme));
        Eigen::MatrixXd expected = unit_weights;
        for (Eigen::Index row = 0; row < expected.rows(); ++row) {
          const int degree =
              row_degree(scheme, on_boundary[static_cast<std::size_t>(row)]);
          expected.row(row) *= std::ldexp(1.0, exponent * degree);
        }
        EXPECT_TRUE(weights == expected)
            << to_string(scheme) << " at 2^" << exponent << ": largest difference "
            << (weights - expected).cwiseAbs().maxCoeff() << " of " << expected.cwiseAbs().maxCoeff();
      }
    }
  }
}

TEST(Laplacian, NamesRoundTrip) {
  for (const WeightScheme scheme : all_weight_schemes()) {
    const auto parsed = weight_scheme_from_string(to_string(scheme));
    ASSERT_TRUE(parsed.has_value());
    EXPECT_EQ(*parsed, scheme);
  }
  EXPECT_EQ(to_string(WeightScheme::chord_length), "chord");
  EXPECT_EQ(to_string(WeightScheme::least_squares_positive), "least-squares-positive");
  EXPECT_FALSE(weight_scheme_from_string("cot").has_value());
  EXPECT_TRUE(has_positive_weights(WeightScheme::mean_value));
  EXPECT_FALSE(has_positive_weights(WeightScheme::cotangent));
  EXPECT_TRUE(is_symmetric(WeightScheme::cotangent));
  EXPECT_FALSE(is_symmetric(WeightScheme::shape_preserving));
}

TEST(Laplacian, DeterministicBits) {
  const Mesh mesh = demo_surface(12);
  for (const WeightScheme scheme : all_weight_schemes()) {
    const Eigen::SparseMatrix<double> first = laplacian(mesh, scheme);
    const Eigen::SparseMatrix<double> second = laplacian(mesh, scheme);
    ASSERT_EQ(first.nonZeros(), second.nonZeros());
    for (Eigen::Index k = 0; k < first.nonZeros(); ++k) {
      ASSERT_EQ(first.valuePtr()[k], second.valuePtr()[k]) << to_string(scheme);
      ASSERT_EQ(first.innerIndexPtr()[k], second.innerIndexPtr()[k]);
    }
  }
}

TEST(Laplacian, ClosedOctahedronHasEqualPositiveWeightsInEveryScheme) {
  // Every vertex is interior with valence 4 (least squares below valence 5, the positive program
  // with few unknowns); by symmetry every neighbour of a vertex must get the same weight.
  Mesh octahedron;
  octahedron.vertices.resize(6, 3);
  octahedron.vertices << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  octahedron.faces.resize(8, 3);
  octahedron.faces << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  for (const WeightScheme scheme : all_weight_schemes()) {
    const Eigen::MatrixXd L(laplacian(octahedron, scheme));
    ASSERT_TRUE(L.allFinite()) << to_string(scheme);
    EXPECT_LT((L * Eigen::VectorXd::Ones(6)).cwiseAbs().maxCoeff(), 1e-12 * L.cwiseAbs().maxCoeff());
    for (int v = 0; v < 6; ++v) {
      const int opposite = v ^ 1;  // vertices 2k and 2k+1 are antipodal, not neighbours
      EXPECT_EQ(L(v, opposite), 0.0);
      const double first = -L(v, v == 0 || v == 1 ? 2 : 0);
      EXPECT_GT(first, 0.0) << to_string(scheme);
      for (int j = 0; j < 6; ++j) {
        if (j != v && j != opposite) {
          EXPECT_NEAR(-L(v, j), first, 1e-12 * first) << to_string(scheme);
        }
      }
    }
  }
}

TEST(Laplacian, BadIndicesAndCoordinatesAreNamed) {
  Mesh mesh = planar_disk(2);
  mesh.faces(3, 1) = 999;
  try {
    (void)laplacian(mesh, WeightScheme::cotangent);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("face 3"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("999"), std::string::npos) << error.what();
  }
  Mesh nan_mesh = planar_disk(2);
  nan_mesh.vertices(5, 2) = std::nan("");
  try {
    (void)laplacian(nan_mesh, WeightScheme::uniform);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("vertex 5"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace harmonia
