// Edit files (harmonia/edit_file.h): the format of ../shared/data/edit/README.md with its defaults,
// ball selections, and a clear error naming the field for every kind of bad file.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "harmonia/edit_file.h"
#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

// The error an edit text raises (status and message).
Error edit_error(const std::string& text, const Mesh& mesh) {
  try {
    (void)parse_edit(text, mesh, "edit.json");
  } catch (const Error& error) {
    return error;
  }
  ADD_FAILURE() << "no error for " << text;
  return Error(Status::ok, "");
}

TEST(EditFile, ParsesSetsTransformationsAndDefaults) {
  const Mesh mesh = unit_sphere(1);  // 42 vertices
  const EditDescription edit = parse_edit(R"json({
      "mesh": "sphere.obj", "description": "a test", "unknown": [1, 2],
      "fixed": {"selection": "below(z, 0)", "vertices": [0, 1, 2]},
      "handles": [
        {"vertices": [3, 4], "translate": [1, 2, 3],
         "rotate": {"axis": [0, 0, 2], "degrees": 90, "center": [1, 0, 0]}, "scale": 2},
        {"vertices": [5, 6]}
      ]})json", mesh);
  EXPECT_EQ(edit.mesh_name, "sphere.obj");
  EXPECT_EQ(edit.description, "a test");
  EXPECT_EQ(edit.regions.fixed, (std::vector<int>{0, 1, 2}));
  ASSERT_EQ(edit.regions.handles.size(), 2u);
  EXPECT_EQ(edit.regions.handles[1], (std::vector<int>{5, 6}));
  ASSERT_EQ(edit.transforms.size(), 2u);
  // (2, 0, 0): scaled about (1, 0, 0) to (3, 0, 0), turned a quarter about z to (1, 2, 0), moved.
  const Eigen::Vector3d moved = edit.transforms[0].apply(Eigen::Vector3d(2.0, 0.0, 0.0));
  EXPECT_LT((moved - Eigen::Vector3d(2.0, 4.0, 3.0)).norm(), 8 * std::numeric_limits<double>::epsilon());
  // Defaults: identity rotation, scale 1, no translation, centre = the handle's centroid.
  const SimilarityTransform& plain = edit.transforms[1];
  EXPECT_EQ(plain.scale, 1.0);
  EXPECT_EQ(plain.translation, Eigen::Vector3d::Zero());
  EXPECT_EQ(plain.rotation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  const Eigen::Vector3d centroid = (mesh.vertices.row(5) + mesh.vertices.row(6)).transpose() / 2.0;
  EXPECT_EQ(plain.center, centroid);
  EXPECT_TRUE(edit.regions.region_of_interest.empty());
}

TEST(EditFile, BallSelectsTheVerticesWithinItsRadius) {
  const Mesh mesh = unit_sphere(2);
  const EditDescription edit = parse_edit(R"json({
      "handles": [{"sphere": {"center": [0, 0, 1], "radius": 0.5}, "translate": [0, 0, 1]}],
      "region_of_interest": {"sphere": {"center": [0, 0, 0], "radius": 10}}})json", mesh);
  int inside = 0;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if ((mesh.vertices.row(v) - Eigen::RowVector3d(0, 0, 1)).norm() <= 0.5) ++inside;
  ASSERT_GT(inside, 0);
  EXPECT_EQ(static_cast<int>(edit.regions.handles[0].size()), inside);
  for (const int v : edit.regions.handles[0])
    EXPECT_LE((mesh.vertices.row(v) - Eigen::RowVector3d(0, 0, 1)).norm(), 0.5);
  EXPECT_EQ(static_cast<int>(edit.regions.region_of_interest.size()), mesh.vertex_count());
}

TEST(EditFile, BadFilesNameTheField) {
  const Mesh mesh = unit_sphere(1);  // 42 vertices
  struct Bad {
    const char* text;
    Status status;
    const char* expected;
  };
  const Bad cases[] = {
      {"{\"handles\": [\n  {\"vertices\": [1,}]}", Status::parse_error, "edit.json:2:"},
      {"[1, 2]", Status::invalid_input, "expected a JSON object"},
      {"{\"fixed\": {\"vertices\": [0]}}", Status::invalid_input, "handles: missing"},
      {"{\"handles\": []}", Status::invalid_input, "handles: expected a non-empty array"},
      {"{\"handles\": [{\"vertices\": [1, 2, 42]}]}", Status::invalid_input,
       "handles[0].vertices[2]: vertex index 42 is outside the mesh's 42 vertices"},
      {"{\"fixed\": {\"vertices\": [-1]}, \"handles\": [{\"vertices\": [1]}]}", Status::invalid_input,
       "fixed.vertices[0]: vertex index -1"},
      {"{\"handles\": [{\"vertices\": [1.5]}]}", Status::invalid_input,
       "handles[0].vertices[0]: expected an integer"},
      {"{\"handles\": [{\"vertices\": []}]}", Status::invalid_input, "handles[0].vertices: empty"},
      {"{\"handles\": [{\"vertices\": [1], \"rotate\": {\"axis\": [0, 0], \"degrees\": 5}}]}",
       Status::invalid_input, "handles[0].rotate.axis: expected an array of 3 numbers"},
      {"{\"handles\": [{\"vertices\": [1], \"rotate\": {\"axis\": [0, 0, 0], \"degrees\": 5}}]}",
       Status::invalid_input, "handles[0].rotate.axis: must not be zero"},
      {"{\"handles\": [{\"vertices\": [1], \"rotate\": {\"axis\": [0, 0, 1]}}]}",
       Status::invalid_input, "handles[0].rotate.degrees: missing"},
      {"{\"handles\": [{\"vertices\": [1], \"rotate\": {\"axis\": [0, 0, 1], \"degrees\": \"x\"}}]}",
       Status::invalid_input, "handles[0].rotate.degrees: expected a number"},
      {"{\"handles\": [{\"vertices\": [1], \"scale\": 0}]}", Status::invalid_input,
       "handles[0].scale: must be positive"},
      {"{\"handles\": [{\"vertices\": [1], \"translate\": [1, 2, \"3\"]}]}", Status::invalid_input,
       "handles[0].translate[2]: expected a number"},
      {"{\"handles\": [{\"vertices\": [1], \"sphere\": {\"center\": [0, 0, 0], \"radius\": 1}}]}",
       Status::invalid_input, "handles[0]: give either \"vertices\" or \"sphere\", not both"},
      {"{\"handles\": [{\"sphere\": {\"center\": [9, 9, 9], \"radius\": 0.1}}]}",
       Status::invalid_input, "handles[0].sphere: selects no vertex"},
      {"{\"handles\": [{\"sphere\": {\"center\": [0, 0, 1], \"radius\": -1}}]}",
       Status::invalid_input, "handles[0].sphere.radius: must be positive"},
      {"{\"handles\": [{\"translate\": [0, 0, 1]}]}", Status::invalid_input,
       "handles[0]: expected \"vertices\" or \"sphere\""},
  };
  for (const Bad& bad : cases) {
    const Error error = edit_error(bad.text, mesh);
    EXPECT_EQ(error.status(), bad.status) << bad.text;
    EXPECT_NE(std::string(error.what()).find(bad.expected), std::string::npos)
        << bad.text << "\n  gave: " << error.what();
    EXPECT_NE(std::string(error.what()).find("edit.json"), std::string::npos) << error.what();
  }
}

TEST(EditFile, MissingFileIsAnIoError) {
  const Mesh mesh = unit_sphere(1);
  try {
    (void)read_edit_file("/nonexistent/edit.json", mesh);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::io_error);
    EXPECT_NE(std::string(error.what()).find("/nonexistent/edit.json"), std::string::npos);
  }
}

// Every public edit file reads against its mesh, with the sets the README's table gives.
TEST(EditFile, CorpusEditFilesRead) {
  const std::filesystem::path folder = testing::shared_data_dir() / "edit";
  if (!std::filesystem::exists(folder)) HARMONIA_SKIP_WITHOUT_CORPUS("no " << folder);
  const Mesh homer = read_mesh(testing::shared_data_dir() / "closed" / "homer.obj");
  const EditDescription homer_c = read_edit_file(folder / "homer-c.json", homer);
  EXPECT_EQ(homer_c.regions.fixed.size(), 825u);
  ASSERT_EQ(homer_c.regions.handles.size(), 2u);
  EXPECT_EQ(homer_c.regions.handles[0].size(), 324u);
  EXPECT_EQ(homer_c.regions.handles[1].size(), 334u);
  // Handle 0 turns 75 degrees about z; handle 1 only translates.
  EXPECT_NEAR(Eigen::AngleAxisd(homer_c.transforms[0].rotation).angle(), 75.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_EQ(homer_c.transforms[1].rotation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
}

}  // namespace
}  // namespace harmonia
