// The angle constraints of ABF / linear ABF (detail/angle_constraints.h) and the ABF objective:
// topology, exact values on planar meshes, the Jacobian against finite differences, and the
// shared test meshes' defining properties.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "detail/angle_constraints.h"
#include "harmonia/abf.h"
#include "harmonia/lscm.h"
#include "harmonia/topology.h"
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

}  // namespace
}  // namespace harmonia
