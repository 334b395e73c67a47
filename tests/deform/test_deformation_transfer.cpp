// Deformation transfer from marker pairs (thesis 8.4, 8.5): the marker fields are a partition of
// unity, a mesh transferred onto itself with identity markers reproduces every pose, a rigid motion
// of the source transfers as the same rigid motion of the target's shape, the lion's pose 01 comes
// out as the cat's true pose 01 within 2 % of the diagonal, no lion pose folds more of the cat's
// triangles than it folds of the lion's, and bad markers or poses are refused.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "harmonia/deformation_transfer.h"
#include "harmonia/io.h"
#include "harmonia/marker_file.h"
#include "harmonia/procedural.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

DeformationTransferOptions cpu_options(TransferMethod method = TransferMethod::correspondence) {
  DeformationTransferOptions options;
  options.method = method;
  options.solver.backend = BackendChoice::cpu;
  return options;
}

double diagonal(const Eigen::MatrixX3d& points) {
  return (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
}

// RMS distance between `points` moved by the best rigid motion onto `reference` and `reference`
// (Kabsch), over the reference's diagonal.
double aligned_rms_relative(const Eigen::MatrixX3d& points, const Eigen::MatrixX3d& reference) {
  const Eigen::RowVector3d centre = points.colwise().mean(), reference_centre = reference.colwise().mean();
  const Eigen::MatrixX3d a = points.rowwise() - centre, b = reference.rowwise() - reference_centre;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(a.transpose() * b, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d sign = Eigen::Matrix3d::Identity();
  sign(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  const Eigen::Matrix3d rotation = svd.matrixV() * sign * svd.matrixU().transpose();
  const Eigen::MatrixX3d moved = a * rotation.transpose();
  return std::sqrt((moved - b).rowwise().squaredNorm().mean()) / diagonal(reference);
}

// A smooth non-rigid pose of a mesh: a bend about z growing with height plus a swelling.
Eigen::MatrixX3d bent(const Eigen::MatrixX3d& rest) {
  Eigen::MatrixX3d pose(rest.rows(), 3);
  for (Eigen::Index v = 0; v < rest.rows(); ++v) {
    const Eigen::Vector3d p = rest.row(v);
    const double angle = 0.6 * p.y();
    pose.row(v) = (Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()) * p *
                   (1.0 + 0.1 * p.x() * p.x()))
                      .transpose();
  }
  return pose;
}

// Vertices spread over the unit sphere (the one nearest to each of these directions).
std::vector<int> spread_vertices(const Mesh& mesh) {
  const std::vector<Eigen::Vector3d> directions = {
      {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1},
      {1, 1, 1}, {-1, 1, -1}, {1, -1, -1}, {-1, -1, 1}, {1, 1, -1}, {-1, -1, -1}};
  std::vector<int> vertices;
  for (const Eigen::Vector3d& direction : directions) {
    Eigen::Index nearest = 0;
    (mesh.vertices.rowwise() - direction.normalized().transpose()).rowwise().squaredNorm().minCoeff(&nearest);
    vertices.push_back(static_cast<int>(nearest));
  }
  return vertices;
}

TEST(DeformationTransfer, MarkerFieldsAreAPartitionOfUnity) {
  const Mesh sphere = unit_sphere(3);
  Mesh ellipsoid = sphere;
  ellipsoid.vertices.col(0) *= 2.0;
  std::vector<MarkerPair> markers;
  for (const int v : spread_vertices(sphere)) markers.push_back({v, v});
  DeformationTransfer transfer(sphere, ellipsoid, markers, cpu_options());
  ASSERT_TRUE(transfer.setup_report().ok()) << transfer.setup_report().message;
  for (const Eigen::MatrixXd* fields : {&transfer.source_fields(), &transfer.target_fields()}) {
    ASSERT_EQ(fields->cols(), static_cast<Eigen::Index>(markers.size()));
    // The sum of the fields is harmonic with value 1 on every marker: 1 up to the solve's rounding.
    EXPECT_LT((fields->rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-10);
  }
  EXPECT_EQ(transfer.source_fields()(markers[3].source, 3), 1.0);
  EXPECT_EQ(transfer.source_fields()(markers[3].source, 4), 0.0);
}

TEST(DeformationTransfer, SelfTransferWithIdentityMarkersReproducesThePose) {
  const Mesh mesh = unit_sphere(3);
  std::vector<MarkerPair> markers;
  for (const int v : spread_vertices(mesh)) markers.push_back({v, v});
  const Eigen::MatrixX3d pose = bent(mesh.vertices);
  for (const TransferMethod method : {TransferMethod::correspondence}) {
    DeformationTransfer transfer(mesh, mesh, markers, cpu_options(method));
    ASSERT_TRUE(transfer.setup_report().ok()) << transfer.setup_report().message;
    EXPECT_EQ(transfer.unmatched_triangles(), 0);
    for (int f = 0; f < mesh.face_count(); ++f) EXPECT_EQ(transfer.matches()[static_cast<std::size_t>(f)], f);
    const TransferResult result = transfer.transfer(pose);
    ASSERT_TRUE(result.report.ok()) << result.report.message;
    EXPECT_LT(aligned_rms_relative(result.positions, pose), 1e-6);
    EXPECT_EQ(result.report.flipped_triangles, 0);
  }
}

TEST(DeformationTransfer, RigidMotionTransfersAsTheSameRigidMotion) {
  const Mesh sphere = unit_sphere(3);
  Mesh target = sphere;
  for (Eigen::Index v = 0; v < target.vertices.rows(); ++v)
    target.vertices.row(v) *= 1.0 + 0.15 * std::sin(3.0 * target.vertices(v, 0) + 2.0 * target.vertices(v, 1));
  std::vector<MarkerPair> markers;
  for (const int v : spread_vertices(sphere)) markers.push_back({v, v});
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -1.0, 0.5).normalized()).toRotationMatrix();
  const Eigen::MatrixX3d moved =
      (sphere.vertices * rotation.transpose()).rowwise() + Eigen::RowVector3d(2.0, -1.0, 0.5);
  for (const TransferMethod method : {TransferMethod::correspondence, TransferMethod::quaternion}) {
    DeformationTransfer transfer(sphere, target, markers, cpu_options(method));
    ASSERT_TRUE(transfer.setup_report().ok()) << transfer.setup_report().message;
    const TransferResult result = transfer.transfer(moved);
    ASSERT_TRUE(result.report.ok()) << result.report.message;
    // Every triangle's gradient is the rotation: the target's shape turned by it (the placement
    // moves its centroid as the source's moved), to the solve's rounding.
    const Eigen::MatrixX3d expected = target.vertices * rotation.transpose();
    const Eigen::MatrixX3d centred = result.positions.rowwise() - result.positions.colwise().mean();
    const Eigen::MatrixX3d expected_centred = expected.rowwise() - expected.colwise().mean();
    EXPECT_LT((centred - expected_centred).rowwise().norm().maxCoeff(), 1e-9 * diagonal(expected));
    EXPECT_EQ(result.report.flipped_triangles, 0);
  }
}

// The yardstick: the lion's pose 01 transferred onto the cat comes out as the cat's true
// pose 01 within 2 % of the diagonal after the best rigid alignment.
TEST(DeformationTransfer, LionPoseBecomesTheTrueCatPose) {
  const std::filesystem::path folder = testing::shared_data_dir() / "deform";
  if (!std::filesystem::exists(folder)) HARMONIA_SKIP_WITHOUT_CORPUS("no " << folder);
  const Mesh lion = read_mesh(folder / "lion-reference.obj");
  const Mesh cat = read_mesh(folder / "cat-reference.obj");
  const std::vector<MarkerPair> markers =
      read_marker_file(folder / "markers-lion-cat.txt", lion.vertex_count(), cat.vertex_count());
  DeformationTransfer transfer(lion, cat, markers, cpu_options());
  ASSERT_TRUE(transfer.setup_report().ok()) << transfer.setup_report().message;
  const TransferResult result = transfer.transfer(read_mesh(folder / "lion-01.obj").vertices);
  ASSERT_TRUE(result.report.ok()) << result.report.message;
  EXPECT_EQ(result.report.degenerate_triangles, 0);
  const double error = aligned_rms_relative(result.positions, read_mesh(folder / "cat-01.obj").vertices);
  EXPECT_LE(error, 0.02) << "rms after alignment / diagonal: " << error;
}

// The lion's nine poses onto the cat: no transfer folds more triangles onto their neighbours than
// the source pose itself folds (the count each pose adds to its rest pose), by either method.
TEST(DeformationTransfer, NoPoseFoldsMoreTrianglesThanTheSourcePose) {
  const std::filesystem::path folder = testing::shared_data_dir() / "deform";
  if (!std::filesystem::exists(folder)) HARMONIA_SKIP_WITHOUT_CORPUS("no " << folder);
  const Mesh lion = read_mesh(folder / "lion-reference.obj");
  const Mesh cat = read_mesh(folder / "cat-reference.obj");
  const std::vector<MarkerPair> markers =
      read_marker_file(folder / "markers-lion-cat.txt", lion.vertex_count(), cat.vertex_count());
  for (const TransferMethod method : {TransferMethod::correspondence, TransferMethod::quaternion}) {
    DeformationTransfer transfer(lion, cat, markers, cpu_options(method));
    ASSERT_TRUE(transfer.setup_report().ok()) << transfer.setup_report().message;
    for (int pose = 1; pose <= 9; ++pose) {
      const std::string name = "lion-0" + std::to_string(pose) + ".obj";
      const TransferResult result = transfer.transfer(read_mesh(folder / name).vertices);
      ASSERT_TRUE(result.report.ok()) << name << ": " << result.report.message;
      EXPECT_EQ(result.report.degenerate_triangles, 0) << name;
      EXPECT_LE(result.report.flipped_triangles, result.source_folded_triangles) << name;
    }
  }
}

// A fold counts against the rest pose: the rest pose folds nothing, and dragging one vertex along
// the surface well past a neighbour turns some of its fan over (their normals point into the
// sphere while their neighbours' point out), while only its fan and their neighbours can turn.
TEST(DeformationTransfer, FoldsAreCountedAgainstTheRestPose) {
  const Mesh sphere = unit_sphere(2);
  std::vector<MarkerPair> markers;
  for (const int v : spread_vertices(sphere)) markers.push_back({v, v});
  DeformationTransfer transfer(sphere, sphere, markers, cpu_options());
  ASSERT_TRUE(transfer.setup_report().ok()) << transfer.setup_report().message;
  EXPECT_EQ(transfer.transfer(sphere.vertices).source_folded_triangles, 0);
  int fan = 0, neighbour = -1;
  for (Eigen::Index f = 0; f < sphere.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (sphere.faces(f, k) == 0) {
        ++fan;
        neighbour = sphere.faces(f, (k + 1) % 3);
      }
  Eigen::MatrixX3d dragged = sphere.vertices;
  const Eigen::RowVector3d past = sphere.vertices.row(neighbour) +
                                  2.0 * (sphere.vertices.row(neighbour) - sphere.vertices.row(0));
  dragged.row(0) = past.normalized();
  const int folded = transfer.transfer(dragged).source_folded_triangles;
  EXPECT_GT(folded, 0);
  EXPECT_LE(folded, 4 * fan);  // the fan and the triangles across its outer edges
}

TEST(DeformationTransfer, BadMarkersAndPosesAreRefused) {
  const Mesh mesh = unit_sphere(2);
  const auto setup_message = [&mesh](const std::vector<MarkerPair>& markers) {
    DeformationTransfer transfer(mesh, mesh, markers, cpu_options());
    EXPECT_EQ(transfer.setup_report().status, Status::invalid_input);
    EXPECT_EQ(transfer.transfer(mesh.vertices).report.status, Status::invalid_input);
    return transfer.setup_report().message;
  };
  EXPECT_NE(setup_message({{0, 0}, {1, 1}}).find("at least 3"), std::string::npos);
  EXPECT_NE(setup_message({{0, 0}, {1, 1}, {2, 9999}}).find("marker pair 2: target vertex 9999"),
            std::string::npos);
  EXPECT_NE(setup_message({{0, 0}, {1, 1}, {0, 2}}).find("marker pair 2: source vertex 0 is in an earlier pair"),
            std::string::npos);
  DeformationTransfer transfer(mesh, mesh, {{0, 0}, {5, 5}, {9, 9}}, cpu_options());
  ASSERT_TRUE(transfer.setup_report().ok());
  const TransferResult short_pose = transfer.transfer(mesh.vertices.topRows(5));
  EXPECT_EQ(short_pose.report.status, Status::invalid_input);
  EXPECT_EQ(short_pose.positions.rows(), 0);
}

TEST(MarkerFile, ParsesPairsAndNamesTheLineOfAnError) {
  const std::vector<MarkerPair> pairs =
      parse_markers("# comment\n 1 2   # paw\n\n3 4\n5 6\n", 10, 10, "m.txt");
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[1].source, 3);
  EXPECT_EQ(pairs[1].target, 4);
  const auto error_of = [](const std::string& text) -> Error {
    try {
      (void)parse_markers(text, 10, 10, "m.txt");
    } catch (const Error& error) {
      return error;
    }
    ADD_FAILURE() << "no error for " << text;
    return Error(Status::ok, "");
  };
  const Error malformed = error_of("1 2\n3\n5 6\n7 8\n");
  EXPECT_EQ(malformed.status(), Status::parse_error);
  EXPECT_NE(std::string(malformed.what()).find("m.txt:2:"), std::string::npos) << malformed.what();
  const Error extra = error_of("1 2\n3 4 5\n");
  EXPECT_NE(std::string(extra.what()).find("m.txt:2:"), std::string::npos);
  const Error range = error_of("1 2\n3 4\n5 10\n");
  EXPECT_EQ(range.status(), Status::invalid_input);
  EXPECT_NE(std::string(range.what()).find("m.txt:3: target vertex 10 is outside"), std::string::npos);
  const Error duplicate = error_of("1 2\n1 4\n5 6\n");
  EXPECT_NE(std::string(duplicate.what()).find("m.txt:2: source vertex 1 is already a marker"),
            std::string::npos);
  EXPECT_NE(std::string(error_of("1 2\n3 4\n").what()).find("at least 3"), std::string::npos);
}

}  // namespace
}  // namespace harmonia
