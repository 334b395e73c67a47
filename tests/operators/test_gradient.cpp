// Tests of the P1 gradient, the divergence and the fragment Poisson right-hand side (thesis 6.2.2).

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Dense>

#include "harmonia/gradient.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"

namespace harmonia {
namespace {

Eigen::MatrixXd corner_coordinates(const Eigen::MatrixXd& values, const Eigen::MatrixX3i& faces) {
  Eigen::MatrixXd fragments(3 * faces.rows(), values.cols());
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) fragments.row(3 * f + k) = values.row(faces(f, k));
  return fragments;
}

TEST(Gradient, AreasOfKnownTriangles) {
  Eigen::MatrixXd planar(4, 2);
  planar << 0, 0, 2, 0, 0, 3, 2, 3;
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 1, 3, 2;
  const Eigen::VectorXd areas = triangle_areas(planar, faces);
  EXPECT_DOUBLE_EQ(areas[0], 3.0);
  EXPECT_DOUBLE_EQ(areas[1], 3.0);
  // Clockwise in 2D still has a positive (unsigned) area.
  Eigen::MatrixX3i reversed(1, 3);
  reversed << 0, 2, 1;
  EXPECT_DOUBLE_EQ(triangle_areas(planar, reversed)[0], 3.0);
  Eigen::MatrixXd spatial(3, 3);
  spatial << 0, 0, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_DOUBLE_EQ(triangle_areas(spatial, faces.topRows(1))[0], 0.5);
}

TEST(Gradient, LinearFunctionsHaveTheirExactGradient) {
  const Mesh disk = planar_disk(5, 1.0);
  const Eigen::MatrixXd planar = disk.vertices.leftCols<2>();
  const Eigen::SparseMatrix<double> G2 = gradient_operator(planar, disk.faces);
  ASSERT_EQ(G2.rows(), 2 * disk.face_count());
  const Eigen::VectorXd linear = 3.0 * planar.col(0) - 2.0 * planar.col(1) + Eigen::VectorXd::Constant(planar.rows(), 7.0);
  const Eigen::VectorXd gradients = G2 * linear;
  for (int f = 0; f < disk.face_count(); ++f) {
    EXPECT_NEAR(gradients[2 * f], 3.0, 1e-12);
    EXPECT_NEAR(gradients[2 * f + 1], -2.0, 1e-12);
  }
  // On a curved surface the P1 gradient of a linear function a . p is a projected on each face.
  const Mesh cap = hemisphere(4);
  const Eigen::Vector3d a(0.3, -1.2, 2.0);
  const Eigen::SparseMatrix<double> G3 = gradient_operator(cap.vertices, cap.faces);
  const Eigen::VectorXd g3 = G3 * (cap.vertices * a);
  for (int f = 0; f < cap.face_count(); ++f) {
    const Eigen::Vector3d p0 = cap.vertices.row(cap.faces(f, 0)), p1 = cap.vertices.row(cap.faces(f, 1)),
                          p2 = cap.vertices.row(cap.faces(f, 2));
    const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0).normalized();
    const Eigen::Vector3d projected = a - a.dot(normal) * normal;
    EXPECT_LT((g3.segment<3>(3 * f) - projected).norm(), 1e-12);
  }
}

TEST(Gradient, PlanarThreeColumnInputMatchesTwoColumns) {
  const Mesh disk = planar_disk(3, 1.0);
  const Eigen::SparseMatrix<double> G2 = gradient_operator(disk.vertices.leftCols<2>(), disk.faces);
  const Eigen::SparseMatrix<double> G3 = gradient_operator(disk.vertices, disk.faces);
  const Eigen::VectorXd values = disk.vertices.col(0).array().square() + disk.vertices.col(1).array();
  const Eigen::VectorXd g2 = G2 * values, g3 = G3 * values;
  for (int f = 0; f < disk.face_count(); ++f) {
    EXPECT_NEAR(g3[3 * f], g2[2 * f], 1e-13);
    EXPECT_NEAR(g3[3 * f + 1], g2[2 * f + 1], 1e-13);
    EXPECT_NEAR(g3[3 * f + 2], 0.0, 1e-13);
  }
}

TEST(Gradient, DivergenceOfTheGradientIsTheCotangentLaplacian) {
  const Mesh surface = demo_surface(8);
  const Eigen::MatrixXd positions = surface.vertices;
  const Eigen::SparseMatrix<double> G = gradient_operator(positions, surface.faces);
  const Eigen::VectorXd u = positions.col(0).array().sin() * positions.col(2).array();
  const Eigen::VectorXd via_divergence = divergence(positions, surface.faces, G * u);
  const Eigen::VectorXd via_laplacian = laplacian(surface, WeightScheme::cotangent) * u;
  EXPECT_LT((via_divergence - via_laplacian).cwiseAbs().maxCoeff(), 1e-12 * via_laplacian.cwiseAbs().maxCoeff());
  // divergence = G^T diag(area) field for an arbitrary field, too.
  Eigen::VectorXd field(G.rows());
  for (Eigen::Index k = 0; k < field.size(); ++k) field[k] = std::cos(0.1 * static_cast<double>(k));
  const Eigen::VectorXd areas = triangle_areas(positions, surface.faces);
  Eigen::VectorXd weighted = field;
  for (Eigen::Index f = 0; f < areas.size(); ++f) weighted.segment<3>(3 * f) *= areas[f];
  EXPECT_LT((divergence(positions, surface.faces, field) - G.transpose() * weighted).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(FragmentPoissonRhs, UnfragmentedLayoutGivesTheLaplacianOfTheLayout) {
  const Mesh surface = demo_surface(8);
  const Eigen::MatrixXd uv = surface.vertices.leftCols<2>() * 0.7;
  const Eigen::MatrixXd rhs = fragment_poisson_rhs(surface.vertices, surface.faces, corner_coordinates(uv, surface.faces));
  const Eigen::MatrixXd expected = laplacian(surface, WeightScheme::cotangent) * uv;
  EXPECT_LT((rhs - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
}

TEST(FragmentPoissonRhs, IndependentTranslationsOfFragmentsChangeNothing) {
  // Each triangle's stiffness annihilates constants, so moving every fragment by its own offset
  // leaves the right-hand side unchanged; a rotation of one fragment does change it.
  const Mesh disk = planar_disk(4, 1.0);
  const Eigen::MatrixXd uv = disk.vertices.leftCols<2>();
  Eigen::MatrixXd fragments = corner_coordinates(uv, disk.faces);
  const Eigen::MatrixXd reference = fragment_poisson_rhs(disk.vertices, disk.faces, fragments);
  for (Eigen::Index f = 0; f < disk.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) fragments.row(3 * f + k) += Eigen::RowVector2d(0.3 * f, -0.1 * f * f);
  const Eigen::MatrixXd translated = fragment_poisson_rhs(disk.vertices, disk.faces, fragments);
  EXPECT_LT((translated - reference).cwiseAbs().maxCoeff(), 1e-9);
  for (int k = 0; k < 3; ++k) fragments.row(k) = Eigen::RowVector2d(-fragments(k, 1), fragments(k, 0));
  EXPECT_GT((fragment_poisson_rhs(disk.vertices, disk.faces, fragments) - reference).cwiseAbs().maxCoeff(), 1e-3);
}

// At every scale of the model (2^-330, about 1e-100, and 2^330) the areas, the gradient operator and
// the divergence are the unit-size ones times the scale's power (2, -1 and 1), exactly: each face is
// computed scaled by a power of two into the safe range. The squared normal used to underflow to 0
// at 1e-100 (zero gradients) and overflow at 1e100.
TEST(Gradient, AreasGradientsAndDivergenceAtEveryScale) {
  const Mesh mesh = hemisphere(6);
  const Eigen::VectorXd field = Eigen::VectorXd::LinSpaced(3 * mesh.face_count(), -1.0, 2.0);
  const Eigen::VectorXd areas = triangle_areas(mesh.vertices, mesh.faces);
  const Eigen::MatrixXd gradients = Eigen::MatrixXd(gradient_operator(mesh.vertices, mesh.faces));
  const Eigen::VectorXd divergences = divergence(mesh.vertices, mesh.faces, field);
  for (const int exponent : {-330, 330}) {
    const double scale = std::ldexp(1.0, exponent);
    const Eigen::MatrixXd scaled = mesh.vertices * scale;
    EXPECT_TRUE(triangle_areas(scaled, mesh.faces) == Eigen::VectorXd(areas * scale * scale))
        << "2^" << exponent;
    EXPECT_TRUE(Eigen::MatrixXd(gradient_operator(scaled, mesh.faces)) == gradients / scale)
        << "2^" << exponent;
    EXPECT_TRUE(divergence(scaled, mesh.faces, field) == Eigen::VectorXd(divergences * scale))
        << "2^" << exponent;
  }
}

TEST(Gradient, BadShapesAreNamed) {
  const Mesh disk = planar_disk(2);
  try {
    (void)gradient_operator(Eigen::MatrixXd::Zero(disk.vertex_count(), 4), disk.faces);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("2 or 3 columns"), std::string::npos) << error.what();
  }
  try {
    (void)fragment_poisson_rhs(disk.vertices, disk.faces, Eigen::MatrixXd::Zero(5, 2));
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("fragments has 5 rows"), std::string::npos) << error.what();
  }
  Eigen::MatrixX3i bad = disk.faces;
  bad(2, 0) = -1;
  EXPECT_THROW((void)triangle_areas(disk.vertices, bad), Error);
}

}  // namespace
}  // namespace harmonia
