// Tests of the quasi-harmonic operator (thesis chapter 5): the closed-form SPD square root, the
// metric tensors of isometric and stretched maps, the tensor-cotangent operator (5.10) against the
// cotangent Laplacian and against the energy computed from gradients, and the tensor mean-value
// operator (5.4) against mean value weights and against a numerical quadrature of its integral.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "harmonia/gradient.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "harmonia/types.h"

namespace harmonia {
namespace {

double max_abs(const Eigen::SparseMatrix<double>& matrix) {
  double largest = 0.0;
  for (int col = 0; col < matrix.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, col); it; ++it)
      largest = std::max(largest, std::abs(it.value()));
  return largest;
}

Eigen::Matrix3d rotation_3d() {
  return (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()) *
          Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// A planar layout: the mesh's own (x, y) coordinates under a linear map `transform`.
Eigen::MatrixX2d layout(const Mesh& planar, const Eigen::Matrix2d& transform) {
  return planar.vertices.leftCols<2>() * transform.transpose();
}

Mesh as_planar_mesh(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& faces) {
  Mesh mesh;
  mesh.vertices = Eigen::MatrixX3d::Zero(uv.rows(), 3);
  mesh.vertices.leftCols<2>() = uv;
  mesh.faces = faces;
  return mesh;
}

// Deterministic SPD tensors with strong anisotropy and every orientation.
TriangleTensors varied_tensors(Eigen::Index count) {
  TriangleTensors tensors(count, 4);
  for (Eigen::Index f = 0; f < count; ++f) {
    const double angle = 0.37 * static_cast<double>(f);
    const double stretch = 1.0 + 4.0 * (0.5 + 0.5 * std::sin(1.3 * static_cast<double>(f)));
    const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(angle).toRotationMatrix();
    const Eigen::Matrix2d tensor =
        (0.5 + 0.1 * static_cast<double>(f % 7)) * rotation * Eigen::Vector2d(stretch, 1.0).asDiagonal() *
        rotation.transpose();
    tensors.row(f) << tensor(0, 0), tensor(0, 1), tensor(1, 0), tensor(1, 1);
  }
  return tensors;
}

TEST(SpdSqrt, SquaresBackToTheInput) {
  const Eigen::Matrix2d cases[] = {
      (Eigen::Matrix2d() << 4, 0, 0, 9).finished(),
      (Eigen::Matrix2d() << 2, 1, 1, 3).finished(),
      (Eigen::Matrix2d() << 1e4, -3, -3, 1e-3).finished(),
      Eigen::Matrix2d::Identity()};
  for (const Eigen::Matrix2d& m : cases) {
    const Eigen::Matrix2d root = spd_sqrt(m);
    EXPECT_LT((root * root - m).norm(), 1e-12 * m.norm());
    EXPECT_NEAR(root(0, 1), root(1, 0), 1e-15 * root.norm());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(root);
    EXPECT_GT(eigen.eigenvalues().minCoeff(), 0.0);  // the SPD root, not another one
  }
  const Eigen::Matrix2d diagonal = spd_sqrt((Eigen::Matrix2d() << 4, 0, 0, 9).finished());
  EXPECT_NEAR(diagonal(0, 0), 2.0, 1e-15);
  EXPECT_NEAR(diagonal(1, 1), 3.0, 1e-15);
}

TEST(QuasiHarmonicTensors, IsometricMapGivesIdentity) {
  const Mesh planar = planar_disk(5, 1.0);
  Mesh moved = planar;
  moved.vertices = (planar.vertices * rotation_3d().transpose()).rowwise() + Eigen::RowVector3d(1, -2, 3);
  const Eigen::MatrixX2d uv =
      layout(planar, Eigen::Rotation2Dd(1.1).toRotationMatrix()).rowwise() + Eigen::RowVector2d(5, 7);
  const TriangleTensors forms = first_fundamental_forms(moved, uv);
  const TriangleTensors tensors = quasi_harmonic_tensors(moved, uv);
  for (Eigen::Index f = 0; f < tensors.rows(); ++f) {
    EXPECT_LT((forms.row(f) - Eigen::RowVector4d(1, 0, 0, 1)).norm(), 1e-12) << f;
    EXPECT_LT((tensors.row(f) - Eigen::RowVector4d(1, 0, 0, 1)).norm(), 1e-12) << f;
  }
}

TEST(QuasiHarmonicTensors, LinearMapGivesTheInverseRootOfItsMetric) {
  const Mesh planar = planar_disk(4, 1.0);
  // uv = A x: the Jacobian of uv -> 3D is A^-1, so I = A^-T A^-1 and C = (sqrt I)^-1.
  const Eigen::Matrix2d halve_u = (Eigen::Matrix2d() << 0.5, 0, 0, 1).finished();
  const TriangleTensors tensors = quasi_harmonic_tensors(planar, layout(planar, halve_u));
  for (Eigen::Index f = 0; f < tensors.rows(); ++f)
    EXPECT_LT((tensors.row(f) - Eigen::RowVector4d(0.5, 0, 0, 1)).norm(), 1e-12);

  const Eigen::Matrix2d shear = (Eigen::Matrix2d() << 1.5, 0.7, -0.2, 0.8).finished();
  const TriangleTensors forms = first_fundamental_forms(planar, layout(planar, shear));
  const TriangleTensors sheared = quasi_harmonic_tensors(planar, layout(planar, shear));
  const Eigen::Matrix2d metric = (shear.inverse().transpose() * shear.inverse()).eval();
  for (Eigen::Index f = 0; f < forms.rows(); ++f) {
    Eigen::Matrix2d form, tensor;
    form << forms(f, 0), forms(f, 1), forms(f, 2), forms(f, 3);
    tensor << sheared(f, 0), sheared(f, 1), sheared(f, 2), sheared(f, 3);
    EXPECT_LT((form - metric).norm(), 1e-12);
    // C^-1 squared is the metric: (C^-1)^2 = I.
    EXPECT_LT((tensor.inverse() * tensor.inverse() - metric).norm(), 1e-12);
  }
}

TEST(QuasiHarmonicTensors, ZeroAreaUvTriangleIsMarkedNonFinite) {
  const Mesh planar = planar_disk(2);
  Eigen::MatrixX2d uv = planar.vertices.leftCols<2>();
  const Eigen::Vector3i face = planar.faces.row(0);
  uv.row(face[2]) = 0.5 * (uv.row(face[0]) + uv.row(face[1]));  // collapse face 0 onto a line
  const TriangleTensors tensors = quasi_harmonic_tensors(planar, uv);
  EXPECT_FALSE(tensors.row(0).allFinite());
  EXPECT_TRUE(tensors.row(1).allFinite() || (planar.faces.row(1).array() == face[2]).any());
}

TEST(TensorCotangent, IdentityTensorsGiveTheCotangentLaplacianOfTheLayout) {
  const Mesh planar = planar_disk(6, 1.0);
  const Eigen::Matrix2d distortion = (Eigen::Matrix2d() << 1.0, 0.9, 0.0, 0.4).finished();
  for (const Eigen::MatrixX2d& uv : {Eigen::MatrixX2d(planar.vertices.leftCols<2>()), layout(planar, distortion)}) {
    const Eigen::SparseMatrix<double> tensor_operator = tensor_cotangent_laplacian(
        uv, planar.faces, scalar_tensors(Eigen::VectorXd::Ones(planar.face_count())));
    const Eigen::SparseMatrix<double> cotangent =
        laplacian(as_planar_mesh(uv, planar.faces), WeightScheme::cotangent);
    EXPECT_LT(max_abs(tensor_operator - cotangent), 1e-12 * max_abs(cotangent));
  }
}

TEST(TensorCotangent, EnergyMatchesTheGradientIntegralAndOperatorIsSymmetricPsd) {
  const Mesh planar = planar_disk(4, 1.0);
  const Eigen::MatrixX2d uv = planar.vertices.leftCols<2>();
  const TriangleTensors tensors = varied_tensors(planar.face_count());
  const Eigen::SparseMatrix<double> L = tensor_cotangent_laplacian(uv, planar.faces, tensors);
  EXPECT_EQ(max_abs(L - Eigen::SparseMatrix<double>(L.transpose())), 0.0);
  EXPECT_LT((L * Eigen::VectorXd::Ones(L.rows())).cwiseAbs().maxCoeff(), 1e-12 * max_abs(L));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen{Eigen::MatrixXd(L)};
  EXPECT_GT(eigen.eigenvalues().minCoeff(), -1e-12 * max_abs(L));

  // Independent: f^T L f = sum_T area_T (grad f)^T C_T grad f, gradients from gradient_operator.
  const Eigen::SparseMatrix<double> G = gradient_operator(uv, planar.faces);
  const Eigen::VectorXd areas = triangle_areas(uv, planar.faces);
  Eigen::VectorXd f(uv.rows());
  for (Eigen::Index v = 0; v < f.size(); ++v) f[v] = std::sin(3.0 * uv(v, 0)) + uv(v, 1) * uv(v, 0);
  const Eigen::VectorXd gradients = G * f;
  double energy = 0.0;
  for (Eigen::Index t = 0; t < areas.size(); ++t) {
    Eigen::Matrix2d tensor;
    tensor << tensors(t, 0), tensors(t, 1), tensors(t, 2), tensors(t, 3);
    const Eigen::Vector2d g = gradients.segment<2>(2 * t);
    energy += areas[t] * g.dot(tensor * g);
  }
  EXPECT_NEAR(f.dot(L * f), energy, 1e-12 * energy);
}

TEST(TensorCotangent, ScalarTensorsScaleEachTriangle) {
  const Mesh planar = planar_disk(3, 1.0);
  const Eigen::MatrixX2d uv = planar.vertices.leftCols<2>();
  const Eigen::SparseMatrix<double> scaled =
      tensor_cotangent_laplacian(uv, planar.faces, scalar_tensors(Eigen::VectorXd::Constant(planar.face_count(), 2.5)));
  const Eigen::SparseMatrix<double> cotangent = laplacian(planar, WeightScheme::cotangent);
  EXPECT_LT(max_abs(scaled - 2.5 * cotangent), 1e-12 * max_abs(scaled));
  const TriangleTensors tensors = scalar_tensors(Eigen::Vector2d(3.0, 4.0));
  EXPECT_EQ(tensors.row(1), Eigen::RowVector4d(4, 0, 0, 4));
}

TEST(TensorMeanValue, IdentityTensorsGiveMeanValueWeightsOfTheLayout) {
  const Mesh planar = planar_disk(6, 1.0);
  const Eigen::Matrix2d distortion = (Eigen::Matrix2d() << 1.0, 0.9, 0.0, 0.4).finished();
  const Eigen::MatrixX2d uv = layout(planar, distortion);
  const Eigen::SparseMatrix<double> tensor_operator = tensor_mean_value_laplacian(
      uv, planar.faces, scalar_tensors(Eigen::VectorXd::Ones(planar.face_count())));
  const Eigen::SparseMatrix<double> mean_value =
      laplacian(as_planar_mesh(uv, planar.faces), WeightScheme::mean_value);
  EXPECT_LT(max_abs(tensor_operator - mean_value), 1e-12 * max_abs(mean_value));
}

TEST(TensorMeanValue, WeightsArePositiveForAnisotropicTensorsAndObtuseTriangles) {
  const Mesh planar = planar_disk(6, 1.0);
  const Eigen::Matrix2d distortion = (Eigen::Matrix2d() << 1.0, 1.4, 0.0, 0.3).finished();
  const Eigen::MatrixX2d uv = layout(planar, distortion);  // many obtuse triangles
  const TriangleTensors tensors = varied_tensors(planar.face_count());
  const Eigen::SparseMatrix<double> L = tensor_mean_value_laplacian(uv, planar.faces, tensors);
  const Eigen::SparseMatrix<double> cotangent = tensor_cotangent_laplacian(uv, planar.faces, tensors);
  int negative_cotangent = 0, off_diagonal = 0;
  for (int col = 0; col < L.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, col); it; ++it) {
      if (it.row() == it.col()) continue;
      ++off_diagonal;
      EXPECT_GT(-it.value(), 0.0) << it.row() << "," << it.col();
    }
    for (Eigen::SparseMatrix<double>::InnerIterator it(cotangent, col); it; ++it)
      if (it.row() != it.col() && it.value() > 0.0) ++negative_cotangent;
  }
  EXPECT_GT(off_diagonal, 0);
  EXPECT_GT(negative_cotangent, 0);  // the tensor-cotangent weights of this input are not all positive
  EXPECT_LT((L * Eigen::VectorXd::Ones(L.rows())).cwiseAbs().maxCoeff(), 1e-12 * max_abs(L));
}

TEST(TensorMeanValue, ClosedFormMatchesQuadratureOfTheCircleIntegral) {
  // One triangle; the weight of neighbour j at centre i is
  //   1 / (r_j sin g) * integral over the wedge of sin(angle from the far spoke) * n^T C n,
  // evaluated here by composite Simpson quadrature in the global frame.
  Eigen::MatrixX2d uv(3, 2);
  uv << 0.2, -0.1, 1.7, 0.3, -0.4, 1.1;
  Eigen::MatrixX3i faces(1, 3);
  faces << 0, 1, 2;
  TriangleTensors tensors(1, 4);
  tensors << 2.0, 0.6, 0.6, 0.7;
  const Eigen::SparseMatrix<double> L = tensor_mean_value_laplacian(uv, faces, tensors);
  Eigen::Matrix2d tensor;
  tensor << 2.0, 0.6, 0.6, 0.7;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (i == j) continue;
      const int far = 3 - i - j;
      const Eigen::Vector2d near_spoke = uv.row(j) - uv.row(i), far_spoke = uv.row(far) - uv.row(i);
      const double start = std::atan2(far_spoke.y(), far_spoke.x());
      double wedge = std::atan2(near_spoke.y(), near_spoke.x()) - start;  // signed sweep far -> near
      while (wedge > std::numbers::pi) wedge -= 2 * std::numbers::pi;
      while (wedge < -std::numbers::pi) wedge += 2 * std::numbers::pi;
      const int steps = 2000;
      double integral = 0.0;
      for (int s = 0; s <= steps; ++s) {
        const double t = static_cast<double>(s) / steps;
        const double angle = start + t * wedge;
        const Eigen::Vector2d n(std::cos(angle), std::sin(angle));
        const double simpson = (s == 0 || s == steps) ? 1.0 : (s % 2 == 1 ? 4.0 : 2.0);
        integral += simpson * std::sin(t * std::abs(wedge)) * n.dot(tensor * n);
      }
      integral *= std::abs(wedge) / steps / 3.0;
      const double expected = integral / (near_spoke.norm() * std::sin(std::abs(wedge)));
      EXPECT_NEAR(-L.coeff(i, j), expected, 1e-10 * expected) << i << "," << j;
    }
  }
}

TEST(QuasiHarmonicOperators, MismatchedTensorCountIsNamed) {
  const Mesh planar = planar_disk(2);
  try {
    (void)tensor_cotangent_laplacian(planar.vertices.leftCols<2>(), planar.faces, scalar_tensors(Eigen::VectorXd::Ones(3)));
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("3 tensors given for 24 faces"), std::string::npos) << error.what();
  }
}

// The forms and tensors at every scale of the model and of the layout (2^-330, about 1e-100, up to
// 2^500): I goes as (3D length / uv length)^2 and C as its inverse square root, exactly, since each
// face is computed on its edges scaled by powers of two. At 1e100 C used to come out NaN.
TEST(QuasiHarmonicOperator, FormsAndTensorsAtEveryScale) {
  const Mesh mesh = hemisphere(6);
  const Eigen::MatrixX2d uv = mesh.vertices.leftCols(2);
  const TriangleTensors forms = first_fundamental_forms(mesh, uv);
  const TriangleTensors tensors = quasi_harmonic_tensors(mesh, uv);
  ASSERT_TRUE(forms.allFinite() && tensors.allFinite());
  for (const int exponent : {-330, 330, -500, 500}) {
    const double scale = std::ldexp(1.0, exponent);
    Mesh scaled = mesh;
    scaled.vertices *= scale;
    EXPECT_TRUE(first_fundamental_forms(scaled, uv) == TriangleTensors(forms * scale * scale))
        << "model at 2^" << exponent;
    EXPECT_TRUE(quasi_harmonic_tensors(scaled, uv) == TriangleTensors(tensors / scale))
        << "model at 2^" << exponent;
    const Eigen::MatrixX2d scaled_uv = uv * scale;
    EXPECT_TRUE(first_fundamental_forms(mesh, scaled_uv) == TriangleTensors(forms / scale / scale))
        << "layout at 2^" << exponent;
    EXPECT_TRUE(quasi_harmonic_tensors(mesh, scaled_uv) == TriangleTensors(tensors * scale))
        << "layout at 2^" << exponent;
  }
}

TEST(QuasiHarmonicOperators, DeterministicBits) {
  const Mesh planar = planar_disk(10, 1.0);
  const Eigen::MatrixX2d uv = planar.vertices.leftCols<2>();
  const TriangleTensors tensors = varied_tensors(planar.face_count());
  for (int pass = 0; pass < 2; ++pass) {
    const auto build = [&] {
      return pass == 0 ? tensor_cotangent_laplacian(uv, planar.faces, tensors)
                       : tensor_mean_value_laplacian(uv, planar.faces, tensors);
    };
    const Eigen::SparseMatrix<double> first = build(), second = build();
    ASSERT_EQ(first.nonZeros(), second.nonZeros());
    for (Eigen::Index k = 0; k < first.nonZeros(); ++k) ASSERT_EQ(first.valuePtr()[k], second.valuePtr()[k]);
  }
}

}  // namespace
}  // namespace harmonia
