// The pictures of a deformation transfer: every marker has its own colour, and a face whose
// corners lie where one marker's field is 1 shows exactly that colour; the PNGs decode to the
// requested size; a mesh transferred onto itself (identity markers) shows the same picture on
// both sides, also when the target lists its faces in another order (each face takes its
// match's colour) and when it is another size (each view is fitted to its own mesh); the same
// arguments give the same bytes; bad arguments are refused, naming the problem, before anything
// is written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include "harmonia/deformation_transfer.h"
#include "harmonia/procedural.h"
#include "harmonia/transfer_picture.h"
#include "harmonia/types.h"
#include "picture/color_map.h"
#include "support/decoded_png.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;
using detail::Rgb;

// The sphere's first 12 vertices are the icosahedron's corners (harmonia/procedural.h), spread
// evenly over it: markers on them, each paired with the same vertex of the target.
constexpr int kMarkers = 12;

std::vector<MarkerPair> identity_markers() {
  std::vector<MarkerPair> markers;
  for (int v = 0; v < kMarkers; ++v) markers.push_back({v, v});
  return markers;
}

DeformationTransfer sphere_transfer(const Mesh& source, const Mesh& target,
                                    TransferMethod method = TransferMethod::correspondence) {
  DeformationTransferOptions options;
  options.method = method;
  options.solver.backend = BackendChoice::cpu;
  return DeformationTransfer(source, target, identity_markers(), options);
}

// A pose of the sphere: squashed along y and sheared, so that it differs from the rest.
Eigen::MatrixX3d squashed(const Eigen::MatrixX3d& rest) {
  Eigen::MatrixX3d pose = rest;
  pose.col(1) *= 0.6;
  pose.col(0) += 0.3 * rest.col(1);
  return pose;
}

// The error a call throws, ok when it throws none.
Error error_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const Error& error) {
    return error;
  }
  return Error(Status::ok, "");
}

// Pixels of one half (0 left, 1 right) above the captions where something is drawn.
int drawn_pixels(const testing::DecodedImage& image, int half) {
  return testing::count_in_view(image, half, [](const Rgb& color) { return !testing::is_background(color); });
}

class TransferPictureTest : public ::testing::Test {
 protected:
  testing::ScratchFolder scratch_{"transfer-picture"};
  const Mesh sphere_ = unit_sphere(2);
};

TEST(TransferPictureColors, EveryMarkerHasItsOwnColourWhateverTheNumberOfMarkers) {
  std::vector<Eigen::Vector3d> colors;
  for (int marker = 0; marker < 144; ++marker) {
    const Eigen::Vector3d color = marker_color(marker);
    EXPECT_TRUE((color.array() >= 0.0).all() && (color.array() <= 1.0).all()) << marker;
    for (std::size_t other = 0; other < colors.size(); ++other)
      EXPECT_NE(color, colors[other]) << "markers " << other << " and " << marker;
    colors.push_back(color);
  }
  EXPECT_EQ(error_of([] { (void)marker_color(-1); }).status(), Status::invalid_input);
}

TEST(TransferPictureColors, AFaceWhereOneFieldIsOneTakesThatMarkersColour) {
  // Two faces: the first has field 2 at 1 in all its corners, the second shares two of them and
  // has field 0 at 1 in its third.
  Mesh mesh;
  mesh.vertices = Eigen::MatrixX3d{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  mesh.faces = Eigen::MatrixX3i{{0, 1, 2}, {1, 3, 2}};
  Eigen::MatrixXd fields = Eigen::MatrixXd::Zero(4, 3);
  fields(0, 2) = fields(1, 2) = fields(2, 2) = 1.0;
  fields(3, 0) = 1.0;
  const Eigen::MatrixX3d colors = marker_face_colors(mesh, fields);
  ASSERT_EQ(colors.rows(), 2);
  EXPECT_EQ(Eigen::Vector3d(colors.row(0).transpose()), marker_color(2));
  // At the second face's barycentre the fields are 2/3 of marker 2 and 1/3 of marker 0.
  const Eigen::Vector3d blend = (2.0 * marker_color(2) + marker_color(0)) / 3.0;
  EXPECT_TRUE(Eigen::Vector3d(colors.row(1).transpose()).isApprox(blend))
      << colors.row(1) << " against " << blend.transpose();

  const auto problem = [&](const Eigen::MatrixXd& bad) {
    return std::string(error_of([&] { (void)marker_face_colors(mesh, bad); }).what());
  };
  EXPECT_NE(problem(fields.topRows(3)).find("3 rows for 4 vertices"), std::string::npos);
  EXPECT_NE(problem(Eigen::MatrixXd(4, 0)).find("no column"), std::string::npos);
  Eigen::MatrixXd not_finite = fields;
  not_finite(1, 1) = std::nan("");
  EXPECT_NE(problem(not_finite).find("not finite"), std::string::npos);
}

TEST_F(TransferPictureTest, ArePngsOfTheRequestedSizeWithAShapeInEachHalf) {
  const DeformationTransfer transfer = sphere_transfer(sphere_, sphere_);
  const fs::path correspondence = scratch_.file("correspondence.png");
  write_transfer_correspondence_picture(correspondence, sphere_, sphere_, transfer);
  const fs::path pose = scratch_.file("pose.png");
  TransferPictureOptions options;
  options.width = 901;
  options.height = 500;
  options.title = "sphere.obj → sphere.obj - 12 markers";
  const Eigen::MatrixX3d source_pose = squashed(sphere_.vertices);
  write_transfer_pose_picture(pose, sphere_, source_pose, sphere_, source_pose, transfer, options);
  for (const auto& [path, width, height] : {std::tuple{correspondence, 1600, 800},
                                            std::tuple{pose, 901, 500}}) {
    const testing::DecodedImage image = testing::decode_png(path);
    ASSERT_EQ(image.width, width) << path;
    ASSERT_EQ(image.height, height) << path;
    for (const auto& [x, y] : testing::corner_pixels(image))
      EXPECT_TRUE(testing::is_background(image.at(x, y))) << path << " corner " << x << ", " << y;
    for (int half = 0; half < 2; ++half)
      EXPECT_GT(drawn_pixels(image, half), width * height / 20) << path << " half " << half;
  }
}

TEST_F(TransferPictureTest, ASelfTransferShowsTheSamePictureOnBothSides) {
  for (const TransferMethod method : {TransferMethod::correspondence, TransferMethod::quaternion}) {
    const DeformationTransfer transfer = sphere_transfer(sphere_, sphere_, method);
    const fs::path correspondence = scratch_.file("correspondence.png");
    write_transfer_correspondence_picture(correspondence, sphere_, sphere_, transfer);
    EXPECT_EQ(testing::differences_between_halves(testing::decode_png(correspondence)), 0);

    // The same positions on both sides, and then a target that did not follow the pose.
    const Eigen::MatrixX3d source_pose = squashed(sphere_.vertices);
    const fs::path pose = scratch_.file("pose.png");
    write_transfer_pose_picture(pose, sphere_, source_pose, sphere_, source_pose, transfer);
    EXPECT_EQ(testing::differences_between_halves(testing::decode_png(pose)), 0);
    write_transfer_pose_picture(pose, sphere_, source_pose, sphere_, sphere_.vertices, transfer);
    EXPECT_GT(testing::differences_between_halves(testing::decode_png(pose)), 10000);
  }
}

TEST_F(TransferPictureTest, EachTargetFaceTakesTheColourOfItsMatch) {
  // The target lists the faces backwards: target face f is source face #F - 1 - f, which its
  // match must find, so that it shows that face's colour where that face lies.
  Mesh reversed = sphere_;
  reversed.faces = sphere_.faces.colwise().reverse();
  const DeformationTransfer transfer = sphere_transfer(sphere_, reversed);
  for (std::size_t f = 0; f < transfer.matches().size(); ++f)
    ASSERT_EQ(transfer.matches()[f], sphere_.face_count() - 1 - static_cast<int>(f)) << f;
  const fs::path png = scratch_.file("reversed.png");
  write_transfer_correspondence_picture(png, sphere_, reversed, transfer);
  EXPECT_EQ(testing::differences_between_halves(testing::decode_png(png)), 0);
}

TEST_F(TransferPictureTest, EachViewIsFittedToItsOwnMesh) {
  // Twice the size (a power of 2: the same pixels after fitting) and the same fields.
  Mesh larger = sphere_;
  larger.vertices *= 2.0;
  const DeformationTransfer transfer = sphere_transfer(sphere_, larger);
  const fs::path png = scratch_.file("larger.png");
  write_transfer_correspondence_picture(png, sphere_, larger, transfer);
  EXPECT_EQ(testing::differences_between_halves(testing::decode_png(png)), 0);
}

TEST_F(TransferPictureTest, TheSameArgumentsGiveTheSameBytes) {
  DeformationTransfer transfer = sphere_transfer(sphere_, sphere_);
  TransferPictureOptions options;
  options.width = 800;
  options.height = 400;
  options.title = "sphere - squashed";
  const Eigen::MatrixX3d source_pose = squashed(sphere_.vertices);
  const TransferResult result = transfer.transfer(source_pose);
  for (const std::string name : {"first.png", "second.png"})
    write_transfer_pose_picture(scratch_.file(name), sphere_, source_pose, sphere_,
                                result.positions, transfer, options);
  const std::string first = testing::file_bytes(scratch_.file("first.png"));
  EXPECT_FALSE(first.empty());
  EXPECT_EQ(first, testing::file_bytes(scratch_.file("second.png")));
}

TEST_F(TransferPictureTest, RefusesBadArgumentsNamingTheProblemAndWritesNothing) {
  const DeformationTransfer transfer = sphere_transfer(sphere_, sphere_);
  const Eigen::MatrixX3d pose = squashed(sphere_.vertices);
  const auto pose_error = [&](const std::string& name, const Eigen::MatrixX3d& source_pose,
                              const Eigen::MatrixX3d& transferred,
                              const TransferPictureOptions& options = {}) {
    return error_of([&] {
      write_transfer_pose_picture(scratch_.file(name), sphere_, source_pose, sphere_, transferred,
                                  transfer, options);
    });
  };
  const auto expect_refused = [](const Error& error, Status status, const std::string& problem) {
    EXPECT_EQ(error.status(), status) << error.what();
    EXPECT_NE(std::string(error.what()).find(problem), std::string::npos) << error.what();
  };
  expect_refused(pose_error("pose.svg", pose, pose), Status::io_error, "PNG only");
  expect_refused(pose_error("pose.jpg", pose, pose), Status::io_error, "pose.jpg");
  TransferPictureOptions narrow;
  narrow.width = 100;
  expect_refused(pose_error("narrow.png", pose, pose, narrow), Status::invalid_input,
                 "width 100 is outside [320, 16384]");
  expect_refused(pose_error("rows.png", pose.topRows(3), pose), Status::invalid_input,
                 "3 source pose positions for 162 source vertices");
  expect_refused(pose_error("rows.png", pose, pose.topRows(5)), Status::invalid_input,
                 "5 transferred positions for 162 target vertices");
  Eigen::MatrixX3d not_finite = pose;
  not_finite(7, 2) = std::nan("");
  expect_refused(pose_error("nan.png", pose, not_finite), Status::invalid_input,
                 "transferred position of vertex 7 is not finite");

  // The meshes must be the transfer's, and its set-up must have succeeded.
  const Mesh other = unit_sphere(1);
  expect_refused(error_of([&] {
                   write_transfer_correspondence_picture(scratch_.file("other.png"), sphere_,
                                                         other, transfer);
                 }),
                 Status::invalid_input, "target marker fields have 162 rows for 42 vertices");
  DeformationTransferOptions cpu;
  cpu.solver.backend = BackendChoice::cpu;
  const DeformationTransfer failed(sphere_, sphere_, {{0, 0}, {1, 1}}, cpu);
  ASSERT_FALSE(failed.setup_report().ok());
  expect_refused(error_of([&] {
                   write_transfer_correspondence_picture(scratch_.file("failed.png"), sphere_,
                                                         sphere_, failed);
                 }),
                 Status::invalid_input, "set-up failed");
  EXPECT_TRUE(fs::is_empty(scratch_.path()));

  // Unwritable: a folder that does not exist.
  expect_refused(error_of([&] {
                   write_transfer_correspondence_picture(scratch_.path() / "missing" / "c.png",
                                                         sphere_, sphere_, transfer);
                 }),
                 Status::io_error, "missing");
  EXPECT_TRUE(fs::is_empty(scratch_.path()));
}

}  // namespace
}  // namespace harmonia
