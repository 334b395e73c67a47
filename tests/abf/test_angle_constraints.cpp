// The angle constraints of ABF / linear ABF (abf/angle_constraints.h) and the ABF objective:
// topology, exact values on planar meshes, the Jacobian against finite differences, and the
// shared test meshes' defining properties.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <memory>
#include <random>

#include <Eigen/Dense>

#include "abf/angle_constraints.h"
#include "abf/reduced_angle_system.h"
#include "harmonia/abf.h"
#include "harmonia/lscm.h"
#include "harmonia/topology.h"
#include "solve/backend_selection.h"
#include "support/angle_test_meshes.h"

namespace harmonia {
namespace {

constexpr double kPi = std::numbers::pi;

detail::AngleTopology topology_of(const Mesh& mesh) {
  const auto loops = boundary_loops(mesh);
  return detail::build_angle_topology(mesh, loops.at(0));
}

double angle_sum_at(const detail::AngleTopology& topology, const Eigen::VectorXd& angles, int v) {
  double sum = 0.0;
  for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1]; ++k)
    sum += angles[topology.vertex_corners[k]];
  return sum;
}

TEST(AngleTopology, ObtuseFanHasOneInteriorVertexWithItsThreeCentralCorners) {
  const Mesh mesh = testing::obtuse_fan();
  const detail::AngleTopology topology = topology_of(mesh);
  EXPECT_EQ(topology.face_count, 3);
  EXPECT_EQ(topology.corner_count(), 9);
  ASSERT_EQ(topology.interior_count(), 1);
  EXPECT_EQ(topology.interior_vertices[0], 0);
  EXPECT_EQ(topology.interior_index[0], 0);
  EXPECT_EQ(topology.interior_index[1], -1);
  EXPECT_EQ(topology.boundary_vertices.size(), 3u);
  const std::vector<int> apex_corners(topology.vertex_corners.begin(),
                                      topology.vertex_corners.begin() + 3);
  EXPECT_EQ(apex_corners, (std::vector<int>{0, 3, 6}));
  // Every corner appears once, at its own vertex.
  for (int v = 0; v < topology.vertex_count; ++v)
    for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1]; ++k)
      EXPECT_EQ(mesh.faces(topology.vertex_corners[k] / 3, topology.vertex_corners[k] % 3), v);
}

TEST(AngleTopology, ObtuseFanHasTheThesisAngularDeficit) {
  const Mesh mesh = testing::obtuse_fan();
  const detail::AngleTopology topology = topology_of(mesh);
  const Eigen::VectorXd angles = detail::corner_angles(mesh);
  EXPECT_NEAR(2.0 * kPi - angle_sum_at(topology, angles, 0), 4.56, 0.03);
}

TEST(AngleTopology, LscmFoldsTheObtuseFan) {
  // The thesis' motivating failure of linear conformal maps (figure 3.3).
  const MapResult result = lscm(testing::obtuse_fan());
  EXPECT_GT(result.report.flipped_triangles, 0);
}

TEST(CornerAngles, TriangleAnglesSumToPiAndMatchTheLawOfCosines) {
  const Mesh mesh = testing::test_hemisphere(5);
  const Eigen::VectorXd angles = detail::corner_angles(mesh);
  for (int f = 0; f < mesh.face_count(); ++f) {
    EXPECT_NEAR(angles[3 * f] + angles[3 * f + 1] + angles[3 * f + 2], kPi, 1e-13);
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const double cosine = (b - a).normalized().dot((c - a).normalized());
    EXPECT_NEAR(angles[3 * f], std::acos(cosine), 1e-12);
  }
}

TEST(RescaledAngles, InteriorRingsSumToTwoPiBoundaryAnglesAreKept) {
  const Mesh mesh = testing::spiked_disk();
  const detail::AngleTopology topology = topology_of(mesh);
  const Eigen::VectorXd angles = detail::corner_angles(mesh);
  const Eigen::VectorXd rescaled = detail::rescaled_angles(topology, angles);
  for (const int v : topology.interior_vertices)
    EXPECT_NEAR(angle_sum_at(topology, rescaled, v), 2.0 * kPi, 1e-12);
  for (const int v : topology.boundary_vertices)
    for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1]; ++k)
      EXPECT_EQ(rescaled[topology.vertex_corners[k]], angles[topology.vertex_corners[k]]);
  // The spike's ring really was rescaled (its 3D angle sum is far below 2 pi).
  EXPECT_LT(angle_sum_at(topology, angles, 0), 2.0 * kPi - 1.0);
}

TEST(AngleConstraints, PlanarMeshAnglesSatisfyEveryConstraintExactly) {
  const Mesh mesh = testing::tilted_planar_disk();
  const detail::AngleTopology topology = topology_of(mesh);
  ASSERT_GT(topology.interior_count(), 30);
  const Eigen::VectorXd angles = detail::corner_angles(mesh);
  // Active boundary rows with t chosen so that each holds: the angle sum at the vertex / pi.
  const std::vector<int> active(topology.boundary_vertices.begin(),
                                topology.boundary_vertices.begin() + 5);
  const detail::AngleConstraints constraints =
      detail::evaluate_angle_constraints(topology, angles, active, 1.0);
  const int rows = topology.face_count + 2 * topology.interior_count() + 5;
  ASSERT_EQ(constraints.values.size(), rows);
  const int boundary_start = topology.face_count + 2 * topology.interior_count();
  EXPECT_LT(constraints.values.head(boundary_start).lpNorm<Eigen::Infinity>(), 1e-12);
  for (int b = 0; b < 5; ++b)
    EXPECT_NEAR(constraints.values[boundary_start + b],
                angle_sum_at(topology, angles, active[b]) - kPi, 1e-14);
}

TEST(AngleConstraints, CurvedMeshesViolateVertexRowsAndRescalingBreaksTheWheel) {
  const Mesh mesh = testing::obtuse_fan();
  const detail::AngleTopology topology = topology_of(mesh);
  const Eigen::VectorXd angles = detail::corner_angles(mesh);
  const detail::AngleConstraints spatial = detail::evaluate_angle_constraints(topology, angles);
  ASSERT_EQ(spatial.values.size(), 5);
  EXPECT_LT(spatial.values.head(3).lpNorm<Eigen::Infinity>(), 1e-14);  // Triangles hold.
  EXPECT_NEAR(spatial.values[3], angle_sum_at(topology, angles, 0) - 2.0 * kPi, 1e-14);
  // The sine law holds in every spatial triangle, so the 3D angles satisfy the wheel ...
  EXPECT_LT(std::abs(spatial.values[4]), 1e-14);
  EXPECT_NEAR(detail::constraint_violation(spatial), std::abs(spatial.values[3]), 0.0);
}

TEST(AngleConstraints, RescaledTargetAnglesBreakTheWheel) {
  // Rescaling the rings of neighbouring interior vertices changes the left and right angles of
  // a ring differently, so the ABF targets violate the wheel rows.
  const Mesh mesh = testing::spiked_disk();
  const detail::AngleTopology topology = topology_of(mesh);
  const Eigen::VectorXd angles = detail::corner_angles(mesh);
  const int wheel_start = topology.face_count + topology.interior_count();
  const detail::AngleConstraints spatial = detail::evaluate_angle_constraints(topology, angles);
  EXPECT_LT(spatial.values.tail(topology.interior_count()).lpNorm<Eigen::Infinity>(), 1e-13);
  const Eigen::VectorXd targets = detail::rescaled_angles(topology, angles);
  const detail::AngleConstraints rescaled = detail::evaluate_angle_constraints(topology, targets);
  Eigen::Index worst = 0;
  EXPECT_GT(rescaled.values.tail(topology.interior_count()).cwiseAbs().maxCoeff(&worst), 1e-2);
  const int v = topology.interior_vertices[worst];
  double wheel = 0.0;  // sum log sin(left) - log sin(right), by hand from the faces around v.
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.faces(f, k) == v)
        wheel += std::log(std::sin(targets[3 * f + (k + 1) % 3])) -
                 std::log(std::sin(targets[3 * f + (k + 2) % 3]));
  EXPECT_NEAR(rescaled.values[wheel_start + worst], wheel, 1e-13);
  EXPECT_LT(rescaled.values.segment(topology.face_count, topology.interior_count())
                .lpNorm<Eigen::Infinity>(),
            1e-13);  // Vertex rows hold for the rescaled angles.
}

// Central differences of h against the Jacobian, column by column, at perturbed angles of a
// curved mesh with active boundary rows.
void expect_jacobian_matches_finite_differences(const Mesh& mesh) {
  const detail::AngleTopology topology = topology_of(mesh);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  Eigen::VectorXd angles = detail::corner_angles(mesh);
  for (Eigen::Index c = 0; c < angles.size(); ++c) angles[c] += noise(random);
  const std::vector<int> active = {topology.boundary_vertices[0], topology.boundary_vertices[2]};
  const detail::AngleConstraints at = detail::evaluate_angle_constraints(topology, angles, active, 1.3);
  const Eigen::MatrixXd jacobian = Eigen::MatrixXd(at.jacobian);
  const double step = 1e-6;
  double worst = 0.0;
  for (Eigen::Index c = 0; c < angles.size(); ++c) {
    Eigen::VectorXd plus = angles, minus = angles;
    plus[c] += step;
    minus[c] -= step;
    const Eigen::VectorXd difference =
        (detail::evaluate_angle_constraints(topology, plus, active, 1.3).values -
         detail::evaluate_angle_constraints(topology, minus, active, 1.3).values) /
        (2.0 * step);
    worst = std::max(worst, (difference - jacobian.col(c)).lpNorm<Eigen::Infinity>());
  }
  EXPECT_LT(worst, 1e-7);
  // The CSR rows are sorted and the pattern has the documented lengths.
  for (Eigen::Index row = 0; row < at.jacobian.rows(); ++row) {
    const int* begin = at.jacobian.innerIndexPtr() + at.jacobian.outerIndexPtr()[row];
    const int* end = at.jacobian.innerIndexPtr() + at.jacobian.outerIndexPtr()[row + 1];
    EXPECT_TRUE(std::is_sorted(begin, end)) << "row " << row;
    EXPECT_EQ(std::adjacent_find(begin, end), end) << "row " << row;
  }
}

TEST(AngleConstraints, JacobianMatchesFiniteDifferencesOnTheHemisphere) {
  expect_jacobian_matches_finite_differences(testing::test_hemisphere(4));
}

TEST(AngleConstraints, JacobianMatchesFiniteDifferencesOnTheSpikedDisk) {
  expect_jacobian_matches_finite_differences(testing::spiked_disk(3));
}

TEST(AbfEnergy, ZeroAtTheTargetsAndTheWeightedSquareOtherwise) {
  const Mesh mesh = testing::spiked_disk();
  const Eigen::MatrixX3d targets = abf_target_angles(mesh);
  EXPECT_EQ(abf_energy(mesh, targets), 0.0);
  // Targets: the 3D angles rescaled around the interior vertices only.
  const detail::AngleTopology topology = topology_of(mesh);
  const Eigen::VectorXd expected =
      detail::rescaled_angles(topology, detail::corner_angles(mesh));
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(targets(f, k), expected[3 * f + k]);
  Eigen::MatrixX3d moved = targets;
  moved(2, 1) *= 1.1;   // relative error 0.1
  moved(7, 0) *= 0.8;   // relative error -0.2
  EXPECT_NEAR(abf_energy(mesh, moved), 0.01 + 0.04, 1e-14);
}

// The target angles are the same bits at every scale of the model (2^-330, about 1e-100, 2^330 and
// 2^-900): at 1e-100 the corner angles' cross products used to underflow (zero angles).
TEST(AbfEnergy, TargetAnglesAreTheSameAtEveryScale) {
  const Mesh mesh = testing::spiked_disk();
  const Eigen::MatrixX3d targets = abf_target_angles(mesh);
  for (const int exponent : {-330, 330, -900}) {
    Mesh scaled = mesh;
    scaled.vertices *= std::ldexp(1.0, exponent);
    EXPECT_TRUE(abf_target_angles(scaled) == targets) << "2^" << exponent;
    EXPECT_EQ(abf_energy(scaled, targets), 0.0) << "2^" << exponent;
  }
}

TEST(AbfEnergy, RejectsAnglesOfTheWrongShape) {
  const Mesh mesh = testing::obtuse_fan();
  try {
    (void)abf_energy(mesh, Eigen::MatrixX3d::Zero(2, 3));
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::invalid_input);
    EXPECT_NE(std::string(error.what()).find("2 rows of angles for 3 faces"), std::string::npos);
  }
  Mesh broken = mesh;
  broken.faces(1, 2) = 9;
  EXPECT_THROW((void)abf_target_angles(broken), Error);
}

// The CPU backend seen as a device: no direct factorization, so the reduced system takes the
// device path (B' uploaded, normal product, PCG) on the CPU's primitives.
class IterativeOnlyBackend final : public detail::Backend {
 public:
  IterativeOnlyBackend() : inner_(detail::make_backend(BackendChoice::cpu, nullptr)) {}
  BackendKind kind() const override { return inner_->kind(); }
  std::string description() const override { return "cpu without factorization"; }
  bool supports(detail::Feature feature) const override {
    return feature != detail::Feature::direct_factorization && inner_->supports(feature);
  }
  std::unique_ptr<detail::DeviceMatrix> upload(const detail::RowMajorSparse& matrix) override {
    return inner_->upload(matrix);
  }
  std::unique_ptr<detail::DeviceVectors> upload(
      const Eigen::Ref<const Eigen::MatrixXd>& values) override {
    return inner_->upload(values);
  }
  std::unique_ptr<detail::DeviceVectors> allocate(int rows, int cols) override {
    return inner_->allocate(rows, cols);
  }
  void spmv(const detail::DeviceMatrix& a, const detail::DeviceVectors& x,
            detail::DeviceVectors& y) override {
    inner_->spmv(a, x, y);
  }
  Eigen::VectorXd dot(const detail::DeviceVectors& x, const detail::DeviceVectors& y) override {
    return inner_->dot(x, y);
  }
  void axpy(const Eigen::VectorXd& alpha, const detail::DeviceVectors& x,
            detail::DeviceVectors& y) override {
    inner_->axpy(alpha, x, y);
  }
  void xpay(const detail::DeviceVectors& x, const Eigen::VectorXd& beta,
            detail::DeviceVectors& y) override {
    inner_->xpay(x, beta, y);
  }
  void copy(const detail::DeviceVectors& x, detail::DeviceVectors& y) override {
    inner_->copy(x, y);
  }
  void jacobi(const detail::DeviceMatrix& a, const detail::DeviceVectors& r,
              detail::DeviceVectors& z) override {
    inner_->jacobi(a, r, z);
  }
  std::unique_ptr<detail::TriangleOperators> triangle_operators(const Eigen::MatrixX3i& faces,
                                                                int vertex_count) override {
    return inner_->triangle_operators(faces, vertex_count);
  }

 private:
  std::unique_ptr<detail::Backend> inner_;
};

struct SaddlePointCase {
  detail::AngleConstraints constraints;
  Eigen::VectorXd weights, r, s;
};

SaddlePointCase random_case(const Mesh& mesh, const detail::AngleTopology& topology,
                            const std::vector<int>& active, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd angles = detail::corner_angles(mesh);
  for (Eigen::Index c = 0; c < angles.size(); ++c) angles[c] += 0.05 * unit(random);
  SaddlePointCase problem;
  problem.constraints = detail::evaluate_angle_constraints(topology, angles, active, 1.5);
  const Eigen::Index rows = problem.constraints.jacobian.rows(), corners = angles.size();
  problem.weights.resize(corners);
  for (Eigen::Index c = 0; c < corners; ++c) problem.weights[c] = std::exp(1.5 * unit(random));
  problem.r = Eigen::VectorXd::NullaryExpr(corners, [&] { return unit(random); });
  problem.s = Eigen::VectorXd::NullaryExpr(rows, [&] { return unit(random); });
  return problem;
}

// The full saddle-point system [W^-1 J^T; J 0] solved densely.
void dense_solution(const SaddlePointCase& problem, Eigen::VectorXd& dx, Eigen::VectorXd& lambda) {
  const Eigen::MatrixXd j = Eigen::MatrixXd(problem.constraints.jacobian);
  const Eigen::Index n = j.cols(), m = j.rows();
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(n + m, n + m);
  system.topLeftCorner(n, n) = problem.weights.cwiseInverse().asDiagonal();
  system.topRightCorner(n, m) = j.transpose();
  system.bottomLeftCorner(m, n) = j;
  Eigen::VectorXd rhs(n + m);
  rhs << problem.r, problem.s;
  const Eigen::VectorXd solution = system.fullPivLu().solve(rhs);
  dx = solution.head(n);
  lambda = solution.tail(m);
}

void expect_reduced_matches_dense(const Mesh& mesh, bool with_boundary_rows,
                                  detail::Backend& backend, double tolerance) {
  const detail::AngleTopology topology = topology_of(mesh);
  std::vector<int> active;
  // Distinct vertices, and never all of the boundary (with the vertex rows the boundary rows of a
  // whole fan would add up to the triangle rows: a dependent set).
  const auto& loop = topology.boundary_vertices;
  if (with_boundary_rows) active = {loop[0], loop[1]};
  if (with_boundary_rows && loop.size() > 4) active.push_back(loop[loop.size() / 2]);
  detail::IterativeSettings settings;
  settings.relative_tolerance = 1e-14;
  detail::ReducedAngleSystem system(backend, topology, settings, {});
  // Two different problems through the same object: values change, the pattern stays.
  for (const unsigned seed : {1u, 2u}) {
    const SaddlePointCase problem = random_case(mesh, topology, active, seed);
    Eigen::VectorXd expected_dx, expected_lambda, dx, lambda;
    dense_solution(problem, expected_dx, expected_lambda);
    const detail::SolveStats stats =
        system.solve(problem.constraints.jacobian, problem.weights, problem.r, problem.s, dx, lambda);
    ASSERT_EQ(stats.status, Status::ok) << stats.message;
    ASSERT_EQ(dx.size(), expected_dx.size());
    ASSERT_EQ(lambda.size(), expected_lambda.size());
    const double scale = std::max(1.0, expected_lambda.lpNorm<Eigen::Infinity>());
    EXPECT_LT((dx - expected_dx).lpNorm<Eigen::Infinity>(), tolerance * scale) << "seed " << seed;
    EXPECT_LT((lambda - expected_lambda).lpNorm<Eigen::Infinity>(), tolerance * scale)
        << "seed " << seed;
  }
}

TEST(ReducedAngleSystem, DirectSolveMatchesTheDenseSaddlePointSolution) {
  auto backend = detail::make_backend(BackendChoice::cpu, nullptr);
  for (const bool boundary_rows : {false, true}) {
    SCOPED_TRACE(boundary_rows ? "with active boundary rows" : "without boundary rows");
    expect_reduced_matches_dense(testing::obtuse_fan(), boundary_rows, *backend, 1e-10);
    expect_reduced_matches_dense(testing::spiked_disk(2), boundary_rows, *backend, 1e-10);
    expect_reduced_matches_dense(testing::test_hemisphere(3), boundary_rows, *backend, 1e-10);
  }
}

TEST(ReducedAngleSystem, DevicePathMatchesTheDenseSaddlePointSolution) {
  IterativeOnlyBackend backend;
  for (const bool boundary_rows : {false, true}) {
    SCOPED_TRACE(boundary_rows ? "with active boundary rows" : "without boundary rows");
    expect_reduced_matches_dense(testing::spiked_disk(2), boundary_rows, backend, 1e-9);
    expect_reduced_matches_dense(testing::test_hemisphere(3), boundary_rows, backend, 1e-9);
  }
}

TEST(ReducedAngleSystem, NamesItsSolver) {
  auto cpu = detail::make_backend(BackendChoice::cpu, nullptr);
  const Mesh mesh = testing::spiked_disk(2);
  const detail::AngleTopology topology = topology_of(mesh);
  detail::ReducedAngleSystem direct(*cpu, topology, {}, {});
  const SaddlePointCase problem = random_case(mesh, topology, {}, 3);
  Eigen::VectorXd dx, lambda;
  ASSERT_EQ(direct.solve(problem.constraints.jacobian, problem.weights, problem.r, problem.s, dx,
                         lambda).status,
            Status::ok);
  EXPECT_NE(direct.solver_name().find("(reduced, 2 per interior vertex)"), std::string::npos);
  IterativeOnlyBackend device;
  detail::ReducedAngleSystem iterative(device, topology, {}, {});
  EXPECT_EQ(iterative.solver_name(), "pcg-jacobi (reduced, 2 per interior vertex)");
}

}  // namespace
}  // namespace harmonia
