// The `harmonia` program end to end: it is run as a separate process on files in a temporary
// folder, and its exit codes, one-line failure reasons, JSON fields and output files are checked
// against independent computations (areas, counts, the analytic identity layout).
#include <algorithm>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "harmonia/distortion_plot.h"
#include "harmonia/edit_file.h"
#include "harmonia/gltf.h"
#include "harmonia/io.h"
#include "harmonia/metrics.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "support/test_support.h"
#include "support/view_page_data.h"
#include "support/topology_meshes.h"
#include "support/vulkan_test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
  [[nodiscard]] nlohmann::json json() const { return nlohmann::json::parse(out); }
};

std::string read_text(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

// A failure must be reported as exactly one line "harmonia: <reason>".
void expect_one_line_reason(const Outcome& outcome) {
  const std::vector<std::string> lines = lines_of(outcome.err);
  ASSERT_EQ(lines.size(), 1u) << "stderr: " << outcome.err;
  EXPECT_EQ(lines[0].rfind("harmonia: ", 0), 0u) << lines[0];
}

using testing::octahedron;  // Closed, outward; vertices 4 and 5 are the poles.

double surface_area(const Mesh& mesh) {
  double area = 0.0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  return area;
}

// What a written OBJ contains, parsed here independently of the library's readers.
struct ObjContents {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector2d> uvs;
  std::vector<Eigen::Vector3i> faces;  // 0-based; the faces of the form f a/a b/b c/c only
  int faces_not_in_a_slash_a_form = 0;
  // Every face of the form f a/ta b/tb c/tc (per-corner texture coordinates), 0-based.
  std::vector<Eigen::Vector3i> corner_faces;
  std::vector<Eigen::Vector3i> uv_faces;
  std::vector<int> group_charts;   // N of every `g chart_N` line, in order.
  std::vector<int> chart_of_face;  // Per corner face, N of the last `g chart_N` line above it.
};

ObjContents parse_obj(const fs::path& path) {
  ObjContents obj;
  static const std::regex face_form(R"(f (\d+)/(\d+) (\d+)/(\d+) (\d+)/(\d+)\s*)");
  static const std::regex group_form(R"(g chart_(-?\d+)\s*)");
  for (const std::string& line : lines_of(read_text(path))) {
    std::istringstream fields(line);
    std::string tag;
    fields >> tag;
    std::smatch match;
    if (tag == "v") {
      Eigen::Vector3d p;
      fields >> p.x() >> p.y() >> p.z();
      obj.positions.push_back(p);
    } else if (tag == "vt") {
      Eigen::Vector2d t;
      fields >> t.x() >> t.y();
      obj.uvs.push_back(t);
    } else if (tag == "g" && std::regex_match(line, match, group_form)) {
      obj.group_charts.push_back(std::stoi(match[1]));
    } else if (tag == "f") {
      if (!std::regex_match(line, match, face_form)) {
        ++obj.faces_not_in_a_slash_a_form;
        continue;
      }
      const auto index = [&match](int group) { return std::stoi(match[group]) - 1; };
      obj.corner_faces.emplace_back(index(1), index(3), index(5));
      obj.uv_faces.emplace_back(index(2), index(4), index(6));
      obj.chart_of_face.push_back(obj.group_charts.empty() ? -2 : obj.group_charts.back());
      if (match[1] != match[2] || match[3] != match[4] || match[5] != match[6]) {
        ++obj.faces_not_in_a_slash_a_form;
        continue;
      }
      obj.faces.push_back(obj.corner_faces.back());
    }
  }
  return obj;
}

double signed_uv_area(const ObjContents& obj, const Eigen::Vector3i& face) {
  const Eigen::Vector2d e1 = obj.uvs[face[1]] - obj.uvs[face[0]];
  const Eigen::Vector2d e2 = obj.uvs[face[2]] - obj.uvs[face[0]];
  return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

// The UV angle sum at every boundary vertex of a written layout (one vt per vertex): the boundary
// is where an edge belongs to one face only; each corner angle comes from the UV edge vectors.
std::map<int, double> boundary_angle_sums(const ObjContents& obj) {
  std::map<std::pair<int, int>, int> edge_faces;
  for (const Eigen::Vector3i& face : obj.faces)
    for (int k = 0; k < 3; ++k) {
      const int a = face[k], b = face[(k + 1) % 3];
      ++edge_faces[{std::min(a, b), std::max(a, b)}];
    }
  std::map<int, double> sums;
  for (const auto& [edge, count] : edge_faces)
    if (count == 1) sums[edge.first] = sums[edge.second] = 0.0;
  for (const Eigen::Vector3i& face : obj.faces)
    for (int k = 0; k < 3; ++k) {
      const auto sum = sums.find(face[k]);
      if (sum == sums.end()) continue;
      const Eigen::Vector2d u = obj.uvs[face[(k + 1) % 3]] - obj.uvs[face[k]];
      const Eigen::Vector2d v = obj.uvs[face[(k + 2) % 3]] - obj.uvs[face[k]];
      sum->second += std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
    }
  return sums;
}

// A planar L: the 4 x 4 grid of unit squares without its upper right 2 x 2 block, each square cut
// into two triangles. Its boundary has 16 vertices; the one at grid point (2, 2) is reflex (angle
// 3 pi / 2), so only a boundary control t >= 3/2 keeps the mesh's own (planar, hence optimal)
// angles. Returns the mesh and sets `reflex_vertex`.
Mesh planar_l_shape(int* reflex_vertex) {
  std::map<std::pair<int, int>, int> index;
  Mesh mesh;
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3i> triangles;
  const auto vertex = [&](int i, int j) {
    const auto [entry, added] = index.try_emplace({i, j}, static_cast<int>(points.size()));
    if (added) points.emplace_back(i, j, 0.0);
    return entry->second;
  };
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      if (i >= 2 && j >= 2) continue;
      const int a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1),
                d = vertex(i, j + 1);
      triangles.emplace_back(a, b, c);
      triangles.emplace_back(a, c, d);
    }
  mesh.vertices.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v) mesh.vertices.row(v) = points[v].transpose();
  mesh.faces.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t f = 0; f < triangles.size(); ++f) mesh.faces.row(f) = triangles[f].transpose();
  *reflex_vertex = index.at({2, 2});
  return mesh;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_FALSE(testing::cli_path().empty()) << "the CLI is not built (HARMONIA_BUILD_CLI=OFF)";
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::temp_directory_path() /
              ("harmonia-cli-" + std::to_string(getpid()) + "-" + info->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  [[nodiscard]] fs::path file(const std::string& name) const { return folder_ / name; }

  // Runs `harmonia ARGS` in the temporary folder; ARGS are file names or flags without spaces.
  // `environment` (e.g. "HARMONIA_VULKAN_DEVICE=llvmpipe") is set for that run only.
  Outcome run(const std::string& arguments, const std::string& environment = "") const {
    const fs::path out = folder_ / "stdout.txt", err = folder_ / "stderr.txt";
    const std::string command = "cd '" + folder_.string() + "' && " + environment + " '" +
                                testing::cli_path().string() + "' " + arguments + " >'" +
                                out.string() + "' 2>'" + err.string() + "'";
    const int status = std::system(command.c_str());
    Outcome outcome;
    outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    outcome.out = read_text(out);
    outcome.err = read_text(err);
    return outcome;
  }

  fs::path folder_;
};

// ----------------------------------------------------------------------------------------- info

TEST_F(Cli, InfoJsonReportsTheHemisphereCountsAndTopology) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome outcome = run("info hemisphere.obj --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  // 1 + 6(1+2+3+4) vertices, 6 r^2 faces, Euler: E = V + F - 1 for a disk, 6r boundary edges.
  EXPECT_EQ(report["vertices"], 61);
  EXPECT_EQ(report["faces"], 96);
  EXPECT_EQ(report["edges"], 61 + 96 - 1);
  EXPECT_EQ(report["boundary_edges"], 24);
  EXPECT_EQ(report["boundary_loops"], 1);
  EXPECT_EQ(report["euler_characteristic"], 1);
  EXPECT_EQ(report["genus"], 0);
  EXPECT_EQ(report["components"], 1);
  EXPECT_EQ(report["is_disk"], true);
  EXPECT_EQ(report["is_closed_manifold"], false);
  EXPECT_EQ(report["disk_problem"], "");
  EXPECT_TRUE(report["non_manifold_edges"].empty());
  EXPECT_TRUE(report["unreferenced_vertices"].empty());
}

TEST_F(Cli, InfoTextAlignsValuesAndTruncatesLongListsWithACount) {
  Mesh mesh = hemisphere(4);
  const int original = mesh.vertex_count();
  mesh.vertices.conservativeResize(original + 25, 3);
  for (int i = 0; i < 25; ++i) mesh.vertices.row(original + i) << 3.0 + i, 0.0, 0.0;
  write_mesh(file("loose.obj"), mesh);

  const Outcome outcome = run("info loose.obj");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  std::size_t value_column = std::string::npos;
  bool saw_unreferenced = false;
  for (const std::string& line : lines_of(outcome.out)) {
    // Every row is "name  value" with the values starting in one column.
    const std::size_t gap = line.find("  ");
    ASSERT_NE(gap, std::string::npos) << line;
    const std::size_t column = line.find_first_not_of(' ', gap);
    if (value_column == std::string::npos) value_column = column;
    EXPECT_EQ(column, value_column) << line;
    if (line.rfind("unreferenced vertices", 0) == 0) {
      saw_unreferenced = true;
      EXPECT_EQ(line.substr(column, 7), "25: 61,") << line;
      EXPECT_NE(line.find("80, ... (first 20 shown)"), std::string::npos) << line;
      EXPECT_EQ(line.find(" 81"), std::string::npos) << line;
    }
  }
  EXPECT_TRUE(saw_unreferenced) << outcome.out;

  const nlohmann::json report = run("info loose.obj --json").json();
  EXPECT_EQ(report["unreferenced_vertices"].size(), 25u);
  EXPECT_EQ(report["unreferenced_vertices"][24], original + 24);
}

TEST_F(Cli, MissingFileGivesInputErrorNamingTheFile) {
  const Outcome outcome = run("info no-such-mesh.obj");
  EXPECT_EQ(outcome.exit_code, 2);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("no-such-mesh.obj"), std::string::npos) << outcome.err;

  const Outcome unwrap = run("unwrap no-such-mesh.obj out.obj");
  EXPECT_EQ(unwrap.exit_code, 2);
  expect_one_line_reason(unwrap);
  EXPECT_NE(unwrap.err.find("no-such-mesh.obj"), std::string::npos) << unwrap.err;
  EXPECT_FALSE(fs::exists(file("out.obj")));
}

TEST_F(Cli, MalformedFileGivesInputErrorWithFileAndLine) {
  std::ofstream(file("bad.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
  const Outcome outcome = run("info bad.obj");
  EXPECT_EQ(outcome.exit_code, 2);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("bad.obj:4"), std::string::npos) << outcome.err;
}

// ------------------------------------------------------------------------------------ usage

TEST_F(Cli, UsageErrorsExitWithOneAndOneLine) {
  write_mesh(file("hemisphere.obj"), hemisphere(3));
  for (const std::string arguments :
       {"", "frobnicate", "unwrap hemisphere.obj out.obj --method nonsense",
        "unwrap hemisphere.obj out.obj --weights nonsense", "unwrap hemisphere.obj out.ply",
        "unwrap hemisphere.obj out.obj --picture layout.gif",
        "unwrap hemisphere.obj out.obj --method lscm --boundary square",
        "unwrap hemisphere.obj out.obj --method qhm --weights uniform",
        "unwrap hemisphere.obj out.obj --rounds 3", "cut hemisphere.obj cut.obj --from 1",
        "cut hemisphere.obj cut.stl"}) {
    SCOPED_TRACE(arguments);
    const Outcome outcome = run(arguments);
    EXPECT_EQ(outcome.exit_code, 1);
    expect_one_line_reason(outcome);
  }
  EXPECT_FALSE(fs::exists(file("out.obj")));
  EXPECT_FALSE(fs::exists(file("out.ply")));
}

TEST_F(Cli, HelpExitsWithZeroAndListsEveryCommand) {
  const Outcome outcome = run("--help");
  EXPECT_EQ(outcome.exit_code, 0);
  for (const char* command : {"info", "cut", "unwrap", "eval", "demo", "atlas", "batch", "view"}) {
    EXPECT_NE(outcome.out.find(command), std::string::npos) << command;
  }
}

// ---------------------------------------------------------------------------------------- cut

TEST_F(Cli, CutBetweenTheOctahedronPolesOpensTwoEdgesIntoADisk) {
  write_mesh(file("octahedron.obj"), octahedron());
  const Outcome outcome = run("cut octahedron.obj disk.obj --from 4 --to 5 --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  // The shortest pole-to-pole path has two edges; its one inner vertex is duplicated.
  EXPECT_EQ(report["seam_edges"], 2);
  EXPECT_EQ(report["input_vertices"], 6);
  EXPECT_EQ(report["output_vertices"], 7);
  EXPECT_EQ(report["faces"], 8);

  const nlohmann::json topology = run("info disk.obj --json").json();
  EXPECT_EQ(topology["is_disk"], true);
  EXPECT_EQ(topology["boundary_edges"], 4);  // Both sides of the two seam edges.
  EXPECT_EQ(topology["vertices"], 7);
}

TEST_F(Cli, CutRefusesAVertexOutsideTheMesh) {
  write_mesh(file("octahedron.obj"), octahedron());
  const Outcome outcome = run("cut octahedron.obj disk.obj --from 4 --to 99");
  EXPECT_EQ(outcome.exit_code, 2);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("--to 99"), std::string::npos) << outcome.err;
}

// ------------------------------------------------------------------------------------- unwrap

TEST_F(Cli, UnwrapOfAClosedMeshPointsAtHarmoniaCut) {
  write_mesh(file("octahedron.obj"), octahedron());
  const Outcome outcome = run("unwrap octahedron.obj out.obj");
  EXPECT_EQ(outcome.exit_code, 2);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("harmonia: octahedron.obj is not a disk: "), std::string::npos)
      << outcome.err;
  EXPECT_NE(outcome.err.find("`harmonia cut`"), std::string::npos) << outcome.err;
  EXPECT_FALSE(fs::exists(file("out.obj")));
}

TEST_F(Cli, UnwrapWritesOneVtPerVertexInInputOrderWithSurfaceArea) {
  const Mesh mesh = hemisphere(4);
  write_mesh(file("hemisphere.obj"), mesh);
  const Outcome outcome = run("unwrap hemisphere.obj flat.obj --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;

  const ObjContents obj = parse_obj(file("flat.obj"));
  ASSERT_EQ(obj.positions.size(), 61u);
  ASSERT_EQ(obj.uvs.size(), 61u);
  EXPECT_EQ(obj.faces_not_in_a_slash_a_form, 0);
  ASSERT_EQ(obj.faces.size(), 96u);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_LT((obj.positions[v] - mesh.vertices.row(v).transpose()).norm(), 1e-9) << v;
  }
  double uv_area = 0.0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    EXPECT_EQ(obj.faces[f], mesh.faces.row(f).transpose()) << f;
    const double area = signed_uv_area(obj, obj.faces[f]);
    EXPECT_GT(area, 0.0) << "face " << f << " is flipped or degenerate";
    uv_area += area;
  }
  // Default normalization: the layout's area equals the 3D surface area.
  EXPECT_NEAR(uv_area, surface_area(mesh), 1e-9 * surface_area(mesh));

  const nlohmann::json report = outcome.json();
  EXPECT_EQ(report["status"], "ok");
  EXPECT_EQ(report["method"], "conformal");
  EXPECT_EQ(report["weights"], "cotangent");
  EXPECT_EQ(report["vertices"], 61);
  EXPECT_EQ(report["faces"], 96);
  EXPECT_EQ(report["flipped_triangles"], 0);
  EXPECT_EQ(report["metrics"]["flipped_triangles"], 0);
  EXPECT_EQ(report["metrics"]["faces"], 96);
  EXPECT_FALSE(report["metrics"].contains("face_conformal_distortion"));
  EXPECT_GE(report["metrics"]["conformal_distortion_mean"].get<double>(), 1.0);
  EXPECT_TRUE(report["timings"].is_object());
  EXPECT_TRUE(report["timings"].contains("read"));
  EXPECT_TRUE(report["timings"].contains("write"));
}

TEST_F(Cli, EveryMethodAndWeightSchemeUnwrapsTheHemisphereWithoutFlips) {
  write_mesh(file("hemisphere.obj"), hemisphere(5));
  const std::vector<std::string> variants = {"--method lscm",
                                             "--method qhm",
                                             "--method qhm --weights mean-value --rounds 3",
                                             "--method free",
                                             "--method free --polish --weights mean-value",
                                             "--method free --stop-after conformal",
                                             "--method conformal --boundary square",
                                             "--weights uniform",
                                             "--weights chord",
                                             "--weights mean-value",
                                             "--weights linear-precision",
                                             "--weights least-squares",
                                             "--weights least-squares-positive",
                                             "--weights shape-preserving"};
  for (const std::string& variant : variants) {
    SCOPED_TRACE(variant);
    const Outcome outcome = run("unwrap hemisphere.obj flat.obj --json " + variant);
    ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
    const nlohmann::json report = outcome.json();
    EXPECT_EQ(report["status"], "ok");
    EXPECT_EQ(report["metrics"]["flipped_triangles"], 0);
    const ObjContents obj = parse_obj(file("flat.obj"));
    EXPECT_EQ(obj.uvs.size(), obj.positions.size());
    for (const Eigen::Vector3i& face : obj.faces) EXPECT_GT(signed_uv_area(obj, face), 0.0);
  }
}

TEST_F(Cli, UnitSquareNormalizationFitsTheLayoutIntoTheUnitSquare) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome outcome = run("unwrap hemisphere.obj flat.obj --normalize unit-square");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const ObjContents obj = parse_obj(file("flat.obj"));
  Eigen::Vector2d low(1e9, 1e9), high(-1e9, -1e9);
  for (const Eigen::Vector2d& uv : obj.uvs) {
    low = low.cwiseMin(uv);
    high = high.cwiseMax(uv);
  }
  EXPECT_GE(low.minCoeff(), -1e-9);
  EXPECT_LE(high.maxCoeff(), 1.0 + 1e-9);
  EXPECT_NEAR((high - low).maxCoeff(), 1.0, 1e-9);
}

TEST_F(Cli, CutThenUnwrapFlattensAClosedMesh) {
  write_mesh(file("octahedron.off"), octahedron());
  ASSERT_EQ(run("cut octahedron.off disk.ply").exit_code, 0);
  const Outcome outcome = run("unwrap disk.ply flat.obj --method lscm");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const ObjContents obj = parse_obj(file("flat.obj"));
  EXPECT_EQ(obj.uvs.size(), obj.positions.size());
  ASSERT_EQ(obj.faces.size(), 8u);
  for (const Eigen::Vector3i& face : obj.faces) EXPECT_GT(signed_uv_area(obj, face), 0.0);
}

// `--cut` keeps the input's vertices as `v` lines and writes UVs per corner (f a/ta): a seam vertex
// has one vt on each side of the cut.
TEST_F(Cli, UnwrapWithCutWritesInputVerticesAndPerCornerUvs) {
  const Mesh mesh = octahedron();
  write_mesh(file("octahedron.obj"), mesh);
  const Outcome outcome = run("unwrap octahedron.obj flat.obj --cut --weights mean-value --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_GT(report["seam_edges"].get<int>(), 0);

  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector2d> uvs;
  std::vector<Eigen::Vector3i> position_faces, uv_faces;
  static const std::regex face_form(R"(f (\d+)/(\d+) (\d+)/(\d+) (\d+)/(\d+)\s*)");
  for (const std::string& line : lines_of(read_text(file("flat.obj")))) {
    std::istringstream fields(line);
    std::string tag;
    fields >> tag;
    if (tag == "v") {
      Eigen::Vector3d p;
      fields >> p.x() >> p.y() >> p.z();
      positions.push_back(p);
    } else if (tag == "vt") {
      Eigen::Vector2d t;
      fields >> t.x() >> t.y();
      uvs.push_back(t);
    } else if (tag == "f") {
      std::smatch match;
      ASSERT_TRUE(std::regex_match(line, match, face_form)) << line;
      position_faces.emplace_back(std::stoi(match[1]) - 1, std::stoi(match[3]) - 1,
                                  std::stoi(match[5]) - 1);
      uv_faces.emplace_back(std::stoi(match[2]) - 1, std::stoi(match[4]) - 1,
                            std::stoi(match[6]) - 1);
    }
  }
  // The input's vertices in the input's order, its faces in its order.
  ASSERT_EQ(positions.size(), 6u);
  for (int v = 0; v < 6; ++v) EXPECT_EQ(positions[v], Eigen::Vector3d(mesh.vertices.row(v)));
  ASSERT_EQ(position_faces.size(), 8u);
  for (int f = 0; f < 8; ++f) EXPECT_EQ(position_faces[f], Eigen::Vector3i(mesh.faces.row(f)));
  // More UVs than vertices (the seam), every one used, every triangle counter-clockwise.
  EXPECT_EQ(static_cast<int>(uvs.size()), report["uv_vertices"].get<int>());
  EXPECT_GT(uvs.size(), positions.size());
  std::vector<bool> used(uvs.size(), false);
  for (int f = 0; f < 8; ++f) {
    const Eigen::Vector3i t = uv_faces[f];
    for (int k = 0; k < 3; ++k) used[t[k]] = true;
    const Eigen::Vector2d e1 = uvs[t[1]] - uvs[t[0]], e2 = uvs[t[2]] - uvs[t[0]];
    EXPECT_GT(e1.x() * e2.y() - e1.y() * e2.x(), 0.0) << "face " << f;
  }
  EXPECT_TRUE(std::all_of(used.begin(), used.end(), [](bool u) { return u; }));
  // The layout is a valid parameterization of the closed input according to eval.
  const Outcome evaluated = run("eval octahedron.obj flat.obj --json");
  ASSERT_EQ(evaluated.exit_code, 0) << evaluated.err;
  EXPECT_EQ(evaluated.json()["flipped_triangles"], 0);
}

TEST_F(Cli, StrictCleanupRefusesAnUnreferencedVertexAndRepairKeepsInputNumbering) {
  // The clean hemisphere, and the same with an unreferenced vertex in front (all indices + 1).
  const Mesh clean = hemisphere(4);
  Mesh dirty;
  dirty.vertices.resize(clean.vertex_count() + 1, 3);
  dirty.vertices.row(0) << 7.0, 7.0, 7.0;
  dirty.vertices.bottomRows(clean.vertex_count()) = clean.vertices;
  dirty.faces = clean.faces.array() + 1;
  write_mesh(file("clean.obj"), clean);
  write_mesh(file("dirty.obj"), dirty);

  const Outcome strict = run("unwrap dirty.obj flat.obj");
  EXPECT_EQ(strict.exit_code, 2);
  expect_one_line_reason(strict);
  EXPECT_NE(strict.err.find("--cleanup repair"), std::string::npos) << strict.err;
  EXPECT_FALSE(fs::exists(file("flat.obj")));

  ASSERT_EQ(run("unwrap clean.obj clean-flat.obj").exit_code, 0);
  const Outcome repair = run("unwrap dirty.obj flat.obj --cleanup repair --quiet");
  ASSERT_EQ(repair.exit_code, 0) << repair.err;
  EXPECT_EQ(repair.err, "");  // --quiet: no notes about the repair.
  const Outcome noted = run("unwrap dirty.obj flat.obj --cleanup repair");
  ASSERT_EQ(noted.exit_code, 0) << noted.err;
  EXPECT_EQ(noted.err.rfind("harmonia: cleanup: ", 0), 0u) << noted.err;
  const ObjContents reference = parse_obj(file("clean-flat.obj"));
  const ObjContents repaired = parse_obj(file("flat.obj"));
  ASSERT_EQ(repaired.positions.size(), 62u);
  ASSERT_EQ(repaired.uvs.size(), 62u);
  EXPECT_EQ(repaired.uvs[0], Eigen::Vector2d::Zero());  // The removed vertex: vt 0 0.
  EXPECT_EQ(repaired.positions[0], Eigen::Vector3d(7, 7, 7));
  for (int v = 0; v < 61; ++v) {
    EXPECT_LT((repaired.uvs[v + 1] - reference.uvs[v]).norm(), 1e-12) << v;
  }
  ASSERT_EQ(repaired.faces.size(), reference.faces.size());
  for (std::size_t f = 0; f < reference.faces.size(); ++f) {
    EXPECT_EQ(repaired.faces[f], (reference.faces[f].array() + 1).matrix()) << f;
  }
}

TEST_F(Cli, AMapWithFlippedTrianglesIsWrittenButExitsThree) {
  // Least-squares weights (4.56-4.60) can be negative; on this corpus mesh they fold the layout.
  const fs::path camel = testing::shared_data_dir() / "disk" / "camel_b.obj";
  if (!fs::exists(camel)) HARMONIA_SKIP_WITHOUT_CORPUS(camel << " is not available");
  const Outcome outcome =
      run("unwrap '" + camel.string() + "' flat.obj --weights least-squares --json");
  EXPECT_EQ(outcome.exit_code, 3);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("flipped triangles; flat.obj was written anyway"), std::string::npos)
      << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_EQ(report["status"], "flipped_triangles");
  const ObjContents obj = parse_obj(file("flat.obj"));
  ASSERT_EQ(obj.uvs.size(), obj.positions.size());
  int flipped = 0;
  for (const Eigen::Vector3i& face : obj.faces) flipped += signed_uv_area(obj, face) < 0.0;
  EXPECT_GT(flipped, 0);
  EXPECT_EQ(report["metrics"]["flipped_triangles"], flipped);
}

TEST_F(Cli, PicturesAreWrittenAsSvgAndPngUnderATitleWithTheHeadlineNumbers) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome outcome =
      run("unwrap hemisphere.obj flat.obj --method qhm --picture layout.svg --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json metrics = outcome.json()["metrics"];
  char numbers[160];
  std::snprintf(numbers, sizeof numbers, "%d flipped, conformal %.2f, area %.2f",
                metrics["flipped_triangles"].get<int>(),
                metrics["conformal_distortion_mean"].get<double>(),
                metrics["area_distortion_mean"].get<double>());
  const std::string svg = read_text(file("layout.svg"));
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find(">hemisphere.obj - qhm (cotangent) - " + std::string(numbers) + "</text>"),
            std::string::npos)
      << numbers;
  EXPECT_NE(svg.find(">conformal distortion σ1/σ2 (log scale)</text>"), std::string::npos);
  // The PNG: the same bytes from two runs of the program.
  ASSERT_EQ(run("unwrap hemisphere.obj flat.obj --picture layout.png").exit_code, 0);
  const std::string png = read_text(file("layout.png"));
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  ASSERT_EQ(run("unwrap hemisphere.obj again.obj --picture again.png").exit_code, 0);
  EXPECT_EQ(read_text(file("again.png")), png);
}

TEST_F(Cli, AnOutputThatCannotBeWrittenIsAnEnvironmentError) {
  write_mesh(file("hemisphere.obj"), hemisphere(3));
  const Outcome outcome = run("unwrap hemisphere.obj no-such-folder/flat.obj");
  EXPECT_EQ(outcome.exit_code, 5);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("no-such-folder/flat.obj"), std::string::npos) << outcome.err;
}

// The output is checked before the input is read or anything solved: a --verbose run that fails
// on its output prints no solver stage.
TEST_F(Cli, AnUnwritableOutputIsRefusedBeforeAnyWork) {
  write_mesh(file("hemisphere.obj"), hemisphere(3));
  const Outcome outcome = run("unwrap hemisphere.obj no-such-folder/flat.obj --method abf --verbose");
  EXPECT_EQ(outcome.exit_code, 5);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("no-such-folder/flat.obj: cannot write: no folder"),
            std::string::npos)
      << outcome.err;
  EXPECT_EQ(outcome.err.find("newton"), std::string::npos) << outcome.err;
  fs::create_directory(file("folder.obj"));
  const Outcome folder = run("unwrap hemisphere.obj folder.obj");
  EXPECT_EQ(folder.exit_code, 5);
  EXPECT_NE(folder.err.find("folder.obj: cannot write: it is a directory"), std::string::npos)
      << folder.err;
  const Outcome picture = run("unwrap hemisphere.obj flat.obj --picture no-such-folder/p.svg");
  EXPECT_EQ(picture.exit_code, 5);
  EXPECT_FALSE(fs::exists(file("flat.obj")));  // Nothing was written: the picture failed first.
}

// OUT == IN would replace the input with the result: refused (also through a link or a second
// name of the same file) unless --in-place says so.
TEST_F(Cli, AnOutputThatIsTheInputIsRefusedUnlessInPlace) {
  write_mesh(file("disk.obj"), hemisphere(3));
  const std::string before = read_text(file("disk.obj"));
  fs::create_symlink("disk.obj", file("link.obj"));
  fs::create_hard_link(file("disk.obj"), file("second-name.obj"));
  for (const std::string out : {"disk.obj", "link.obj", "second-name.obj", "./disk.obj"}) {
    const Outcome outcome = run("unwrap disk.obj " + out);
    EXPECT_EQ(outcome.exit_code, 1) << out;
    expect_one_line_reason(outcome);
    EXPECT_NE(outcome.err.find("is the input file disk.obj"), std::string::npos) << outcome.err;
    EXPECT_NE(outcome.err.find("--in-place"), std::string::npos) << outcome.err;
    EXPECT_EQ(read_text(file("disk.obj")), before) << out;
  }
  const Outcome cut = run("cut disk.obj disk.obj");
  EXPECT_EQ(cut.exit_code, 1);
  EXPECT_EQ(read_text(file("disk.obj")), before);

  const Outcome in_place = run("unwrap disk.obj disk.obj --in-place");
  ASSERT_EQ(in_place.exit_code, 0) << in_place.err;
  EXPECT_EQ(read_textured_obj(file("disk.obj")).uv.rows(), hemisphere(3).vertex_count());
}

TEST_F(Cli, ProgressLineOnlyWhenAskedAndNeverWithJson) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome shown = run("unwrap hemisphere.obj flat.obj --progress");
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  EXPECT_NE(shown.err.find("\rharmonia: "), std::string::npos) << shown.err;
  // Not a terminal and no --progress: stderr stays empty.
  EXPECT_EQ(run("unwrap hemisphere.obj flat.obj").err, "");
  EXPECT_EQ(run("unwrap hemisphere.obj flat.obj --progress --json").err, "");
  EXPECT_EQ(run("unwrap hemisphere.obj flat.obj --progress --quiet").err, "");
}

TEST_F(Cli, VulkanBackendEitherRunsOrFailsAsAnEnvironmentError) {
  write_mesh(file("hemisphere.obj"), hemisphere(3));
  const Outcome outcome = run("unwrap hemisphere.obj flat.obj --backend vulkan");
  if (outcome.exit_code == 0) {
    EXPECT_EQ(parse_obj(file("flat.obj")).uvs.size(), 37u);
  } else {
    EXPECT_EQ(outcome.exit_code, 5);
    expect_one_line_reason(outcome);
  }
}

// ------------------------------------------------------------------- unwrap: abf and linabf

// Every field the angle-based methods add to the JSON report, and a valid, flip-free layout.
void expect_valid_angle_map(const nlohmann::json& report, const ObjContents& obj) {
  EXPECT_EQ(report["status"], "ok");
  EXPECT_EQ(report["flipped_triangles"], 0);
  EXPECT_EQ(report["metrics"]["flipped_triangles"], 0);
  EXPECT_EQ(report["boundary_self_intersections"], 0);
  EXPECT_TRUE(report["weights"].is_null());
  ASSERT_TRUE(report["abf_energy"].is_number());
  EXPECT_GE(report["abf_energy"].get<double>(), 0.0);
  ASSERT_TRUE(report["constraint_residual"].is_number());
  EXPECT_TRUE(report["rounds"].is_number_integer());
  EXPECT_EQ(obj.uvs.size(), obj.positions.size());
  for (const Eigen::Vector3i& face : obj.faces) EXPECT_GT(signed_uv_area(obj, face), 0.0);
}

TEST_F(Cli, AbfWithEverySolverReachesTheSameOptimumWithoutFlips) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome reference = run("unwrap hemisphere.obj flat.obj --method abf --json");
  ASSERT_EQ(reference.exit_code, 0) << reference.err;
  const nlohmann::json expected = reference.json();
  expect_valid_angle_map(expected, parse_obj(file("flat.obj")));
  EXPECT_EQ(expected["method"], "abf");
  EXPECT_LT(expected["constraint_residual"].get<double>(), 1e-8);
  const double optimum = expected["abf_energy"].get<double>();
  EXPECT_GT(optimum, 0.0);  // A hemisphere is curved: its 3D angles are not a flattening.
  for (const std::string solver :
       {"auto", "schur-minres", "uzawa", "full-minres", "full-cgnr", "schur-direct"}) {
    SCOPED_TRACE(solver);
    const Outcome outcome =
        run("unwrap hemisphere.obj flat.obj --method abf --backend cpu --json --solver " + solver);
    ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
    const nlohmann::json report = outcome.json();
    expect_valid_angle_map(report, parse_obj(file("flat.obj")));
    EXPECT_LT(report["constraint_residual"].get<double>(), 1e-8);
    // One strictly convex problem: every solver must land on the same minimum.
    EXPECT_NEAR(report["abf_energy"].get<double>(), optimum, 1e-6 * optimum);
  }
}

TEST_F(Cli, LinearAbfIsValidAndItsEnergyIsCloseToAbfs) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome abf = run("unwrap hemisphere.obj abf.obj --method abf --json");
  ASSERT_EQ(abf.exit_code, 0) << abf.err;
  for (const std::string variant : {"", " --rounds 2", " --reconstruction greedy"}) {
    SCOPED_TRACE(variant);
    const Outcome outcome = run("unwrap hemisphere.obj flat.obj --method linabf --json" + variant);
    ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
    const nlohmann::json report = outcome.json();
    expect_valid_angle_map(report, parse_obj(file("flat.obj")));
    EXPECT_EQ(report["method"], "linabf");
    if (variant == " --rounds 2") {
      EXPECT_EQ(report["rounds"], 2);
    }
    // The linearized constraints are met exactly, the true ones to second order only.
    EXPECT_LT(report["constraint_residual"].get<double>(), 1e-2);
    const double optimum = abf.json()["abf_energy"].get<double>();
    EXPECT_NEAR(report["abf_energy"].get<double>(), optimum, 0.1 * optimum);
  }
}

TEST_F(Cli, AbfBoundaryControlMakesTheBoundaryConvexOrConcaveAsAsked) {
  int reflex = -1;
  write_mesh(file("l-shape.obj"), planar_l_shape(&reflex));
  // Classic ABF (t = 2) keeps a planar mesh's own angles: the reflex corner stays 3 pi / 2.
  const Outcome classic = run("unwrap l-shape.obj flat.obj --method abf --json");
  ASSERT_EQ(classic.exit_code, 0) << classic.err;
  EXPECT_NEAR(classic.json()["abf_energy"].get<double>(), 0.0, 1e-12);
  const std::map<int, double> own = boundary_angle_sums(parse_obj(file("flat.obj")));
  ASSERT_EQ(own.size(), 16u);
  EXPECT_NEAR(own.at(reflex), 1.5 * std::numbers::pi, 1e-7);

  // t = 1: every boundary angle at most pi (a convex boundary); t = 0.9 (> 1 - 2/16): at most
  // 0.9 pi. Angles sum to (n - 2) pi around the boundary, so the bound is met with some slack.
  for (const double t : {1.0, 0.9}) {
    SCOPED_TRACE(t);
    const Outcome outcome =
        run("unwrap l-shape.obj flat.obj --method abf --json --boundary-t " + std::to_string(t));
    ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
    const nlohmann::json report = outcome.json();
    const ObjContents obj = parse_obj(file("flat.obj"));
    expect_valid_angle_map(report, obj);
    EXPECT_LT(report["constraint_residual"].get<double>(), 1e-8);
    EXPECT_GT(report["abf_energy"].get<double>(), 0.0);  // The L had to change.
    for (const auto& [vertex, sum] : boundary_angle_sums(obj))
      EXPECT_LE(sum, t * std::numbers::pi + 1e-7) << "boundary vertex " << vertex;
  }
}

TEST_F(Cli, AbfRefusesABoundaryControlAtOrBelowItsLowerBound) {
  int reflex = -1;
  write_mesh(file("l-shape.obj"), planar_l_shape(&reflex));
  // n = 16 boundary vertices: t must exceed 1 - 2/16 = 0.875.
  for (const std::string t : {"0.875", "0.5", "-1"}) {
    SCOPED_TRACE(t);
    const Outcome outcome = run("unwrap l-shape.obj flat.obj --method abf --boundary-t " + t);
    EXPECT_EQ(outcome.exit_code, 2);
    expect_one_line_reason(outcome);
    EXPECT_NE(outcome.err.find("l-shape.obj"), std::string::npos) << outcome.err;
    EXPECT_NE(outcome.err.find("lower bound 1 - 2/n = 0.875"), std::string::npos) << outcome.err;
    EXPECT_NE(outcome.err.find("n = 16 boundary vertices"), std::string::npos) << outcome.err;
    EXPECT_FALSE(fs::exists(file("flat.obj")));
  }
}

TEST_F(Cli, FreeBoundaryMapReportsItsStepsAndRefusesOptionsThatMeanNothing) {
  // A nearly closed sphere (0.95 pi from the north pole): the full conformal step folds, so the
  // report lists the shortened step, and each step has its phase.
  Mesh cup = hemisphere(10);
  for (Eigen::Index v = 0; v < cup.vertices.rows(); ++v) {
    const Eigen::Vector3d p = cup.vertices.row(v);
    const double polar = std::acos(std::clamp(p.z(), -1.0, 1.0)) * 0.95 / 0.5;
    const double longitude = std::atan2(p.y(), p.x());
    cup.vertices.row(v) << std::sin(polar) * std::cos(longitude),
        std::sin(polar) * std::sin(longitude), std::cos(polar);
  }
  write_mesh(file("cup.obj"), cup);
  const Outcome outcome = run("unwrap cup.obj flat.obj --json --method free --polish");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_EQ(report["method"], "free");
  EXPECT_EQ(report["weights"], "cotangent");
  EXPECT_TRUE(report["boundary"].is_null());
  EXPECT_EQ(report["metrics"]["flipped_triangles"], 0);
  EXPECT_EQ(report["metrics"]["boundary_self_intersections"], 0);
  for (const char* phase : {"P0 circle", "P1 conformal", "P2 quasi-harmonic", "P3 polish"})
    EXPECT_TRUE(report["timings"].contains(phase)) << phase;
  ASSERT_FALSE(report["fallbacks"].empty());
  EXPECT_NE(report["fallbacks"][0].get<std::string>().find("step shortened"), std::string::npos)
      << report["fallbacks"];

  write_mesh(file("hemisphere.obj"), hemisphere(4));
  for (const std::string bad : {"--method lscm --polish", "--method qhm --stop-after conformal",
                                "--method free --boundary square",
                                "--method free --weights uniform",
                                "--method free --polish --stop-after conformal"}) {
    SCOPED_TRACE(bad);
    const Outcome refused = run("unwrap hemisphere.obj flat.obj " + bad);
    EXPECT_EQ(refused.exit_code, 1);
    expect_one_line_reason(refused);
  }
}

TEST_F(Cli, AngleBasedOptionsOutsideTheirMethodAreUsageErrors) {
  write_mesh(file("hemisphere.obj"), hemisphere(3));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--method abf --solver gauss-seidel", "--solver"},
      {"--method linabf --solver uzawa", "--method abf only"},
      {"--method linabf --boundary-t 1", "--method abf only"},
      {"--method linabf --underdetermined", "--method abf only"},
      {"--method lscm --solver uzawa", "--method abf only"},
      {"--method abf --rounds 2", "--rounds applies"},
      {"--method abf --weights uniform", "do not apply"},
      {"--method linabf --boundary square", "do not apply"},
      {"--method qhm --reconstruction greedy", "--reconstruction applies"},
      {"--method abf --reconstruction sideways", "--reconstruction"},
      {"--method abf --boundary-t two", "--boundary-t"}};
  for (const auto& [arguments, expected] : cases) {
    SCOPED_TRACE(arguments);
    const Outcome outcome = run("unwrap hemisphere.obj flat.obj " + arguments);
    EXPECT_EQ(outcome.exit_code, 1);
    expect_one_line_reason(outcome);
    EXPECT_NE(outcome.err.find(expected), std::string::npos) << outcome.err;
  }
  EXPECT_FALSE(fs::exists(file("flat.obj")));
}

TEST_F(Cli, AngleBasedMethodsOnAClosedMeshPointAtHarmoniaCut) {
  write_mesh(file("octahedron.obj"), octahedron());
  for (const std::string method : {"abf", "linabf"}) {
    SCOPED_TRACE(method);
    const Outcome outcome = run("unwrap octahedron.obj out.obj --method " + method);
    EXPECT_EQ(outcome.exit_code, 2);
    expect_one_line_reason(outcome);
    EXPECT_NE(outcome.err.find("octahedron.obj is not a disk: "), std::string::npos)
        << outcome.err;
    EXPECT_NE(outcome.err.find("`harmonia cut`"), std::string::npos) << outcome.err;
    EXPECT_FALSE(fs::exists(file("out.obj")));
  }
}

TEST_F(Cli, UnderdeterminedAbfIsFeasibleButNoCloserToTheTargetsThanAbf) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome abf = run("unwrap hemisphere.obj flat.obj --method abf --json");
  ASSERT_EQ(abf.exit_code, 0) << abf.err;
  const Outcome outcome =
      run("unwrap hemisphere.obj flat.obj --method abf --underdetermined --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  expect_valid_angle_map(report, parse_obj(file("flat.obj")));
  EXPECT_LT(report["constraint_residual"].get<double>(), 1e-8);
  // ABF minimizes the energy over the same feasible set.
  EXPECT_GE(report["abf_energy"].get<double>(),
            abf.json()["abf_energy"].get<double>() * (1.0 - 1e-9));
}

TEST_F(Cli, VerboseAbfPrintsOneLinePerNewtonStep) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome outcome = run("unwrap hemisphere.obj flat.obj --method abf --verbose --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const int steps = outcome.json()["rounds"].get<int>();  // JSON on stdout stays parseable.
  ASSERT_GE(steps, 2);
  int newton_lines = 0;
  for (const std::string& line : lines_of(outcome.err)) {
    EXPECT_EQ(line.rfind("harmonia: ", 0), 0u) << line;
    EXPECT_EQ(line.find('\r'), std::string::npos) << line;
    if (line.rfind("harmonia: newton " + std::to_string(newton_lines + 1) + " (violation ", 0) ==
        0)
      ++newton_lines;
  }
  EXPECT_EQ(newton_lines, steps) << outcome.err;
  EXPECT_EQ(run("unwrap hemisphere.obj flat.obj --method abf --verbose --quiet").err, "");
}

TEST_F(Cli, AbfAndLinearAbfOnSmallCorpusMeshes) {
  const fs::path folder = testing::shared_data_dir() / "disk";
  std::vector<std::string> meshes;
  for (const char* name : {"woody.obj", "snail.obj"})
    if (fs::exists(folder / name)) meshes.push_back((folder / name).string());
  if (meshes.empty()) HARMONIA_SKIP_WITHOUT_CORPUS("no corpus at " << folder);
  for (const std::string& mesh : meshes) {
    double abf_energy = 0.0;
    for (const std::string method : {"abf", "linabf"}) {
      SCOPED_TRACE(mesh + " " + method);
      const Outcome outcome = run("unwrap '" + mesh + "' flat.obj --json --method " + method);
      ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
      const nlohmann::json report = outcome.json();
      expect_valid_angle_map(report, parse_obj(file("flat.obj")));
      if (method == "abf") {
        EXPECT_LT(report["constraint_residual"].get<double>(), 1e-8);
        abf_energy = report["abf_energy"].get<double>();
      } else {
        // woody is planar: both energies are zero up to rounding.
        EXPECT_NEAR(report["abf_energy"].get<double>(), abf_energy, 0.1 * abf_energy + 1e-12);
      }
    }
  }
}

// Results do not depend on the model's units. Scaled by a power of two the mesh is the same up to
// its exponents, so every method gives the same bits after --normalize unit-square. Scaled by
// 1e-100 or 1e100 each coordinate is rounded once (a relative change of at most eps), which a
// method amplifies by its conditioning: the layouts agree to 1e-9, room for a condition number of
// 4.5e6 (what the reliability issue asks for).
TEST_F(Cli, EveryMethodGivesTheSameLayoutAtEveryScaleOfTheModel) {
  const fs::path snail = testing::shared_data_dir() / "disk" / "snail.obj";
  if (!fs::exists(snail)) HARMONIA_SKIP_WITHOUT_CORPUS("no " << snail);
  const Mesh mesh = read_mesh(snail);
  const auto write_scaled = [&](const std::string& name, double scale) {
    Mesh scaled = mesh;
    scaled.vertices *= scale;
    write_mesh(file(name), scaled);
  };
  write_scaled("unit.obj", 1.0);
  write_scaled("tiny.obj", 1e-100);
  write_scaled("huge.obj", 1e100);
  write_scaled("tiny2.obj", std::ldexp(1.0, -300));
  write_scaled("huge2.obj", std::ldexp(1.0, 300));
  for (const std::string method : {"conformal", "lscm", "qhm", "linabf", "abf", "free"}) {
    SCOPED_TRACE(method);
    const auto layout = [&](const std::string& input) {
      const Outcome outcome = run("unwrap " + input + " flat.obj --quiet --normalize unit-square "
                                  "--method " + method);
      EXPECT_EQ(outcome.exit_code, 0) << input << ": " << outcome.err;
      return read_textured_obj(file("flat.obj")).uv;
    };
    const Eigen::MatrixX2d unit = layout("unit.obj");
    ASSERT_EQ(unit.rows(), mesh.vertex_count());
    for (const std::string exact : {"tiny2.obj", "huge2.obj"})
      EXPECT_TRUE(layout(exact) == unit) << exact << " is not bit for bit the unit layout";
    for (const std::string rounded : {"tiny.obj", "huge.obj"}) {
      const Eigen::MatrixX2d scaled = layout(rounded);
      ASSERT_EQ(scaled.rows(), unit.rows()) << rounded;
      EXPECT_LE((scaled - unit).cwiseAbs().maxCoeff(), 1e-9) << rounded;
    }
  }
}

// A valid quad at coordinates around 1e200 (its area, 1e400, does not fit in a double) is repaired
// unchanged and unwrapped by every method, with finite UVs in the model's units and exact metrics.
TEST_F(Cli, AQuadAtHugeCoordinatesIsRepairedAndUnwrapped) {
  Mesh quad;
  quad.vertices.resize(4, 3);
  quad.vertices << 1e200, 1e200, 0.0, 3e200, 1e200, 0.0, 3e200, 2e200, 0.0, 1e200, 2e200, 1e199;
  quad.faces.resize(2, 3);
  quad.faces << 0, 1, 2, 0, 2, 3;
  write_mesh(file("quad.obj"), quad);
  for (const std::string method : {"conformal", "lscm", "qhm", "linabf", "abf", "free"}) {
    SCOPED_TRACE(method);
    const Outcome outcome =
        run("unwrap quad.obj flat.obj --cleanup repair --json --method " + method);
    ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
    const nlohmann::json report = outcome.json();
    EXPECT_EQ(report["vertices"].get<int>(), 4);
    EXPECT_EQ(report["faces"].get<int>(), 2);
    EXPECT_EQ(report["metrics"]["zero_area_triangles"].get<int>(), 0);
    EXPECT_EQ(report["metrics"]["flipped_triangles"].get<int>(), 0);
    const Eigen::MatrixX2d uv = read_textured_obj(file("flat.obj")).uv;
    ASSERT_EQ(uv.rows(), 4);
    EXPECT_TRUE(uv.allFinite());
    // UV area equal to the surface's (about 2.01e400), so the layout spans about 1e200.
    const double extent = (uv.colwise().maxCoeff() - uv.colwise().minCoeff()).maxCoeff();
    EXPECT_GT(extent, 1e199);
    EXPECT_LT(extent, 1e201);
  }
}

TEST_F(Cli, AngleBasedMethodsOnTheVulkanBackend) {
#ifdef HARMONIA_HAVE_VULKAN
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const std::string lavapipe = "HARMONIA_VULKAN_DEVICE=llvmpipe";
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome cpu = run("unwrap hemisphere.obj flat.obj --method abf --backend cpu --json");
  ASSERT_EQ(cpu.exit_code, 0) << cpu.err;
  const double cpu_energy = cpu.json()["abf_energy"].get<double>();
  for (const std::string method : {"abf", "linabf"}) {
    SCOPED_TRACE(method);
    const Outcome outcome = run(
        "unwrap hemisphere.obj flat.obj --backend vulkan --json --method " + method, lavapipe);
    ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
    const nlohmann::json report = outcome.json();
    EXPECT_EQ(report["backend"], "vulkan");
    expect_valid_angle_map(report, parse_obj(file("flat.obj")));
    if (method == "abf") {
      EXPECT_LT(report["constraint_residual"].get<double>(), 1e-8);
      EXPECT_NEAR(report["abf_energy"].get<double>(), cpu_energy, 0.01 * cpu_energy);
    }
  }
  // The direct factorization exists on the CPU only.
  const Outcome direct = run(
      "unwrap hemisphere.obj flat.obj --method abf --backend vulkan --solver schur-direct",
      lavapipe);
  EXPECT_NE(direct.exit_code, 0);
  expect_one_line_reason(direct);
#else
  write_mesh(file("hemisphere.obj"), hemisphere(3));
  const Outcome outcome = run("unwrap hemisphere.obj flat.obj --method abf --backend vulkan");
  EXPECT_EQ(outcome.exit_code, 5);
  expect_one_line_reason(outcome);
#endif
}

// --------------------------------------------------------------------------------------- eval

TEST_F(Cli, EvalOfAPlanarMeshAgainstItselfIsDistortionFree) {
  write_mesh(file("disk.obj"), planar_disk(5, 0.2));
  const Outcome outcome = run("eval disk.obj disk.obj --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json metrics = outcome.json();
  EXPECT_EQ(metrics["flipped_triangles"], 0);
  EXPECT_NEAR(metrics["conformal_distortion_mean"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(metrics["conformal_distortion_max"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(metrics["area_distortion_mean"].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(metrics["angle_error_mean_squared"].get<double>(), 0.0, 1e-18);
}

TEST_F(Cli, EvalOfAMirroredLayoutCountsEveryTriangleAsFlippedAndExitsThree) {
  const Mesh disk = planar_disk(4, 0.1);
  Mesh mirrored = disk;
  mirrored.vertices.col(0) *= -1.0;
  write_mesh(file("disk.obj"), disk);
  write_mesh(file("mirrored.off"), mirrored);
  const Outcome outcome = run("eval disk.obj mirrored.off --json");
  EXPECT_EQ(outcome.exit_code, 3);
  expect_one_line_reason(outcome);
  EXPECT_EQ(outcome.json()["flipped_triangles"], disk.face_count());
}

TEST_F(Cli, EvalOfAnUnwrapResultMatchesTheUnwrapReport) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome unwrap = run("unwrap hemisphere.obj flat.obj --method qhm --json");
  ASSERT_EQ(unwrap.exit_code, 0) << unwrap.err;
  const Outcome eval = run("eval hemisphere.obj flat.obj --json");
  ASSERT_EQ(eval.exit_code, 0) << eval.err;
  const nlohmann::json expected = unwrap.json()["metrics"], measured = eval.json();
  for (const char* field : {"conformal_distortion_mean", "area_distortion_mean", "l2_stretch",
                            "abf_energy", "angle_error_mean_squared"}) {
    // The OBJ stores decimal UVs, so the two agree to the printed precision.
    EXPECT_NEAR(measured[field].get<double>(), expected[field].get<double>(),
                1e-6 * (1.0 + std::abs(expected[field].get<double>())))
        << field;
  }
  EXPECT_EQ(measured["flipped_triangles"], 0);
  EXPECT_EQ(measured["uv_vertices"], 61);
}

TEST_F(Cli, EvalRefusesALayoutOfAnotherMesh) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  write_mesh(file("small.obj"), planar_disk(3));
  const Outcome count = run("eval hemisphere.obj small.obj");
  EXPECT_EQ(count.exit_code, 2);
  expect_one_line_reason(count);
  EXPECT_NE(count.err.find("faces"), std::string::npos) << count.err;

  // Same face count, different faces: the disk with its face corners rotated to other vertices.
  Mesh shuffled = hemisphere(4);
  for (int f = 0; f < shuffled.face_count(); ++f) {
    shuffled.faces(f, 0) = (shuffled.faces(f, 0) + 1) % shuffled.vertex_count();
  }
  write_mesh(file("shuffled.obj"), shuffled);
  const Outcome mismatch = run("eval hemisphere.obj shuffled.obj");
  EXPECT_EQ(mismatch.exit_code, 2);
  expect_one_line_reason(mismatch);
  EXPECT_NE(mismatch.err.find("do not match"), std::string::npos) << mismatch.err;
}

// ------------------------------------------------------------------------------------ compare

// The value at fraction p of the sorted values lies between the two order statistics around
// position p (n - 1).
void expect_between_order_statistics(double value, const std::vector<double>& sorted, double p) {
  const double position = p * static_cast<double>(sorted.size() - 1);
  EXPECT_GE(value, sorted[static_cast<std::size_t>(std::floor(position))]) << p;
  EXPECT_LE(value, sorted[static_cast<std::size_t>(std::ceil(position))]) << p;
}

TEST_F(Cli, CompareReportsForEachLayoutWhatTheLibraryMeasuresOnIt) {
  write_mesh(file("hemisphere.obj"), hemisphere(5));
  ASSERT_EQ(run("unwrap hemisphere.obj conformal.obj").exit_code, 0);
  ASSERT_EQ(run("unwrap hemisphere.obj lscm.obj --method lscm").exit_code, 0);
  const Outcome outcome =
      run("compare hemisphere.obj conformal.obj lscm.obj --labels cotangent,LSCM --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  const Mesh mesh = read_mesh(file("hemisphere.obj"));
  EXPECT_EQ(report["mesh"], "hemisphere.obj");
  EXPECT_EQ(report["faces"], mesh.face_count());
  EXPECT_TRUE(report["picture"].is_null());
  ASSERT_EQ(report["layouts"].size(), 2u);
  const std::vector<std::string> files = {"conformal.obj", "lscm.obj"};
  const std::vector<std::string> labels = {"cotangent", "LSCM"};
  for (std::size_t i = 0; i < files.size(); ++i) {
    SCOPED_TRACE(files[i]);
    const nlohmann::json& entry = report["layouts"][i];
    EXPECT_EQ(entry["label"], labels[i]);
    EXPECT_EQ(entry["parameterization"], files[i]);
    // The same computation on the same numbers (JSON keeps every bit of a double): equal.
    const TexturedMesh layout = read_textured_obj(file(files[i]));
    const DistortionMetrics expected = evaluate_map(mesh, layout.uv, layout.uv_faces);
    EXPECT_EQ(entry["flipped_triangles"], expected.flipped_triangles);
    EXPECT_EQ(entry["zero_area_triangles"], expected.zero_area_triangles);
    EXPECT_EQ(entry["boundary_self_intersections"], expected.boundary_self_intersections);
    EXPECT_EQ(entry["abf_energy"].get<double>(), expected.abf_energy);
    EXPECT_EQ(entry["conformal_distortion_mean"].get<double>(), expected.conformal_distortion_mean);
    EXPECT_EQ(entry["conformal_distortion_max"].get<double>(), expected.conformal_distortion_max);
    EXPECT_EQ(entry["area_distortion_mean"].get<double>(), expected.area_distortion_mean);
    EXPECT_EQ(entry["area_distortion_max"].get<double>(), expected.area_distortion_max);
    EXPECT_EQ(entry["l2_stretch"].get<double>(), expected.l2_stretch);
    const Eigen::VectorXd angle = face_angle_distortion(mesh, layout.uv, layout.uv_faces);
    std::vector<double> sorted(angle.begin(), angle.end());
    std::sort(sorted.begin(), sorted.end());
    ASSERT_GT(sorted.back(), 0.0);  // A hemisphere cannot be flattened without angle distortion.
    EXPECT_EQ(entry["angle_distortion_max"].get<double>(), sorted.back());
    expect_between_order_statistics(entry["angle_distortion_median"].get<double>(), sorted, 0.5);
    expect_between_order_statistics(entry["angle_distortion_p90"].get<double>(), sorted, 0.9);
  }
}

TEST_F(Cli, CompareFindsNoAngleDistortionInAPlanarMeshsOwnCoordinates) {
  const Mesh disk = planar_disk(5, 0.2);
  write_mesh(file("disk.obj"), disk);
  write_obj(file("own-uv.obj"), disk, disk.vertices.leftCols<2>());  // As `unwrap` writes layouts.
  const Outcome outcome = run("compare disk.obj own-uv.obj --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json layout = outcome.json()["layouts"][0];
  EXPECT_EQ(layout["angle_distortion_max"].get<double>(), 0.0);
  EXPECT_EQ(layout["angle_distortion_median"].get<double>(), 0.0);
  EXPECT_EQ(layout["flipped_triangles"], 0);

  // A planar corpus mesh (z = 0 everywhere) as its own layout: the x, y of the same file.
  const fs::path woody = testing::shared_data_dir() / "disk" / "woody.obj";
  if (!fs::exists(woody)) HARMONIA_SKIP_WITHOUT_CORPUS(woody << " is not available");
  const Outcome corpus = run("compare '" + woody.string() + "' '" + woody.string() + "' --json");
  ASSERT_EQ(corpus.exit_code, 0) << corpus.err;
  EXPECT_EQ(corpus.json()["layouts"][0]["angle_distortion_max"].get<double>(), 0.0);
}

TEST_F(Cli, ComparePrintsATableAndDrawsTheSortedCurves) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  ASSERT_EQ(run("unwrap hemisphere.obj conformal.obj").exit_code, 0);
  ASSERT_EQ(run("unwrap hemisphere.obj lscm.obj --method lscm").exit_code, 0);
  const Outcome outcome = run("compare hemisphere.obj conformal.obj lscm.obj --picture cmp.svg");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const std::vector<std::string> lines = lines_of(outcome.out);
  ASSERT_EQ(lines.size(), 3u) << outcome.out;
  EXPECT_EQ(lines[0].rfind("layout", 0), 0u);
  EXPECT_NE(lines[0].find("angle p90"), std::string::npos);
  for (std::size_t row = 1; row < 3; ++row) {
    std::istringstream cells(lines[row]);
    std::string label;
    int flips = -1, zero_area = -1, crossings = -1;
    cells >> label >> flips >> zero_area >> crossings;
    EXPECT_EQ(label, row == 1 ? "conformal.obj" : "lscm.obj");  // Default labels: file names.
    EXPECT_EQ(flips, 0);
    EXPECT_EQ(zero_area, 0);
    EXPECT_EQ(crossings, 0);
  }
  const std::string svg = read_text(file("cmp.svg"));
  EXPECT_NE(svg.find(">hemisphere.obj - sorted per-triangle distortion of 2 layouts</text>"),
            std::string::npos);
  EXPECT_NE(svg.find(">conformal.obj</text>"), std::string::npos);
  EXPECT_NE(svg.find(">lscm.obj</text>"), std::string::npos);
  int curves = 0;
  for (std::size_t at = svg.find("<polyline"); at != std::string::npos;
       at = svg.find("<polyline", at + 1)) {
    ++curves;
  }
  EXPECT_EQ(curves, 4);  // Two layouts in two panels.
  ASSERT_EQ(run("compare hemisphere.obj conformal.obj lscm.obj --picture cmp.png").exit_code, 0);
  EXPECT_EQ(read_text(file("cmp.png")).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

TEST_F(Cli, CompareRefusesALayoutWithAnotherFaceCountNamingIt) {
  const Mesh surface = hemisphere(4), small = planar_disk(3);
  write_mesh(file("hemisphere.obj"), surface);
  write_mesh(file("small.obj"), small);
  const Outcome outcome = run("compare hemisphere.obj hemisphere.obj small.obj --json");
  EXPECT_EQ(outcome.exit_code, 2);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("small.obj has " + std::to_string(small.face_count()) +
                             " faces but hemisphere.obj has " +
                             std::to_string(surface.face_count())),
            std::string::npos)
      << outcome.err;
  EXPECT_TRUE(outcome.out.empty()) << outcome.out;  // Nothing is reported for half the layouts.
}

TEST_F(Cli, CompareRefusesLabelsThatDoNotMatchTheLayoutsAndPicturesOfOtherFormats) {
  write_mesh(file("disk.obj"), planar_disk(3));
  const Outcome labels = run("compare disk.obj disk.obj disk.obj --labels one");
  EXPECT_EQ(labels.exit_code, 1);
  expect_one_line_reason(labels);
  EXPECT_NE(labels.err.find("--labels names 1 layouts but 2 PARAM files are given"),
            std::string::npos)
      << labels.err;
  const Outcome picture = run("compare disk.obj disk.obj --picture plot.jpg");
  EXPECT_EQ(picture.exit_code, 1);
  expect_one_line_reason(picture);
  EXPECT_FALSE(fs::exists(file("plot.jpg")));
}

TEST_F(Cli, CompareExitsThreeWhenALayoutHasFlippedTrianglesAfterReportingEverything) {
  const Mesh disk = planar_disk(4, 0.1);
  Mesh mirrored = disk;
  mirrored.vertices.col(0) *= -1.0;
  write_mesh(file("disk.obj"), disk);
  write_mesh(file("mirrored.off"), mirrored);
  const Outcome outcome = run("compare disk.obj disk.obj mirrored.off --json --picture cmp.png");
  EXPECT_EQ(outcome.exit_code, 3);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("mirrored.off has " + std::to_string(disk.face_count()) +
                             " flipped triangles"),
            std::string::npos)
      << outcome.err;
  const nlohmann::json mirror = outcome.json()["layouts"][1];
  EXPECT_EQ(mirror["flipped_triangles"], disk.face_count());
  // Every angle is kept by a mirror (angles are unsigned): the flips are the only sign of it.
  EXPECT_EQ(mirror["angle_distortion_max"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(file("cmp.png")));
}

// --------------------------------------------------------------------------------------- demo

TEST_F(Cli, DemoWritesEveryMethodsFilesAndASummaryTable) {
  const Outcome outcome = run("demo results");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_TRUE(fs::exists(file("results/demo-surface.obj")));
  const Mesh surface = demo_surface();
  const std::vector<std::string> lines = lines_of(outcome.out);
  ASSERT_EQ(lines.size(), 6u) << outcome.out;
  EXPECT_EQ(lines[0].rfind("method", 0), 0u);
  const std::vector<std::string> methods = {"conformal", "mean-value", "lscm", "qhm", "free"};
  for (std::size_t i = 0; i < methods.size(); ++i) {
    SCOPED_TRACE(methods[i]);
    const std::string stem = "results/demo-" + methods[i];
    const ObjContents obj = parse_obj(file(stem + ".obj"));
    EXPECT_EQ(obj.positions.size(), static_cast<std::size_t>(surface.vertex_count()));
    EXPECT_EQ(obj.uvs.size(), obj.positions.size());
    int flips = 0;
    for (const Eigen::Vector3i& face : obj.faces) flips += signed_uv_area(obj, face) <= 0.0;
    EXPECT_EQ(flips, 0);
    EXPECT_TRUE(fs::exists(file(stem + ".svg")));
    EXPECT_TRUE(fs::exists(file(stem + ".png")));
    // Row: method, status, flips, ... as printed.
    std::istringstream row(lines[i + 1]);
    std::string name, status;
    int table_flips = -1;
    row >> name >> status >> table_flips;
    EXPECT_EQ(name, methods[i]);
    EXPECT_EQ(status, "ok");
    EXPECT_EQ(table_flips, 0);
  }
  // Each picture's title names the surface, the method and its headline numbers.
  EXPECT_NE(read_text(file("results/demo-mean-value.svg"))
                .find(">demo-surface.obj - conformal (mean-value) - 0 flipped, conformal "),
            std::string::npos);
}

// ------------------------------------------------------------------------------------- sphere

TEST_F(Cli, SphereWritesUnitPointsInInputOrderThatEvalAndTheReportAgreeOn) {
  write_mesh(file("sphere.obj"), unit_sphere(3));
  const Outcome outcome = run("sphere sphere.obj out.obj --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_EQ(report["status"], "ok");
  EXPECT_EQ(report["metrics"]["flipped_triangles"], 0);
  EXPECT_NEAR(report["metrics"]["degree"].get<double>(), 1.0, 1e-9);
  EXPECT_EQ(report["vertices"], unit_sphere(3).vertex_count());
  const Mesh written = read_mesh(file("out.obj"));
  ASSERT_EQ(written.vertex_count(), unit_sphere(3).vertex_count());
  EXPECT_EQ(written.faces, unit_sphere(3).faces);
  for (Eigen::Index v = 0; v < written.vertices.rows(); ++v)
    EXPECT_NEAR(written.vertices.row(v).norm(), 1.0, 4.0 * std::numeric_limits<double>::epsilon());
  // eval --sphere measures the written file as the report did (the OBJ keeps every digit).
  const Outcome evaluated = run("eval sphere.obj out.obj --sphere --json");
  ASSERT_EQ(evaluated.exit_code, 0) << evaluated.err;
  EXPECT_EQ(evaluated.json()["area_distortion_mean"], report["metrics"]["area_distortion_mean"]);
  EXPECT_EQ(evaluated.json()["flipped_triangles"], 0);
}

// eval --sphere measures a spherical map as ../shared/tools/sphereval.py (an independent
// evaluator) does, docs/cli.md ("eval") says: the same counts, degree and distortion figures, on an
// ellipsoid whose map has distortion to measure.
TEST_F(Cli, EvalSphereAgreesWithTheIndependentEvaluator) {
  const fs::path script = testing::shared_data_dir() / ".." / "tools" / "sphereval.py";
  if (!fs::exists(script) || std::system("python3 -c '' >/dev/null 2>&1") != 0)
    HARMONIA_SKIP_WITHOUT_CORPUS("python3 or " << script << " is not available");
  Mesh ellipsoid = unit_sphere(4);
  ellipsoid.vertices.col(0) *= 1.7;
  ellipsoid.vertices.col(2) *= 0.6;
  write_mesh(file("ellipsoid.obj"), ellipsoid);
  ASSERT_EQ(run("sphere ellipsoid.obj sphere.obj").exit_code, 0);
  const Outcome ours = run("eval ellipsoid.obj sphere.obj --sphere --json");
  ASSERT_EQ(ours.exit_code, 0) << ours.err;
  const std::string command = "cd '" + folder_.string() + "' && python3 '" + script.string() +
                              "' ellipsoid.obj sphere.obj --orient ccw > sphereval.json";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const nlohmann::json independent = nlohmann::json::parse(read_text(file("sphereval.json")));
  const nlohmann::json measured = ours.json();
  EXPECT_EQ(measured["flipped_triangles"].get<int>() + measured["degenerate_triangles"].get<int>(),
            independent["flipped"].get<int>());
  EXPECT_EQ(independent["valid"], true);
  // sphereval prints 6 significant digits.
  const auto agree = [](double a, double b) { return std::abs(a - b) <= 1e-5 * std::max(std::abs(b), 1e-3); };
  EXPECT_TRUE(agree(measured["degree"].get<double>(), independent["degree"].get<double>()))
      << measured["degree"] << " against " << independent["degree"];
  EXPECT_TRUE(agree(measured["angle_error_mean_squared"].get<double>(), independent["angle_mse"].get<double>()))
      << measured["angle_error_mean_squared"] << " against " << independent["angle_mse"];
  EXPECT_TRUE(agree(measured["conformal_distortion_mean"].get<double>(),
                    independent["conformal"]["mean"].get<double>()))
      << measured["conformal_distortion_mean"] << " against " << independent["conformal"]["mean"];
  EXPECT_TRUE(agree(measured["area_distortion_mean"].get<double>(), independent["area"]["mean"].get<double>()))
      << measured["area_distortion_mean"] << " against " << independent["area"]["mean"];
}

// Every closed genus-0 file of the wild corpus, the coarsest (cubes of 12 faces, a tetrahedron)
// among them, gets a bijective map by the independent evaluator; those too coarse for
// curvilinear coordinates say they were projected.
TEST_F(Cli, SphereMapsEveryClosedGenusZeroFileOfTheWildCorpus) {
  const fs::path script = testing::shared_data_dir() / ".." / "tools" / "sphereval.py";
  const fs::path wild = testing::shared_data_dir() / "wild";
  if (!fs::exists(script) || !fs::exists(wild) || std::system("python3 -c '' >/dev/null 2>&1") != 0)
    HARMONIA_SKIP_WITHOUT_CORPUS("python3, " << script << " or " << wild << " is not available");
  int spheres = 0, projected = 0;
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(wild)) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& path : files) {
    Mesh mesh;
    try {
      mesh = read_mesh(path);
    } catch (const Error&) {
      continue;  // no surface in it (the wild set holds such files on purpose)
    }
    std::string why;
    if (check_sphere(mesh, &why) != Status::ok) continue;
    ++spheres;
    write_mesh(file("in.obj"), mesh);
    const Outcome mapped = run("sphere '" + path.string() + "' sphere.obj --json");
    ASSERT_EQ(mapped.exit_code, 0) << path << ": " << mapped.err;
    projected += mapped.out.find("central projection") != std::string::npos;
    const std::string command = "cd '" + folder_.string() + "' && python3 '" + script.string() +
                                "' in.obj sphere.obj > sphereval.json";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const nlohmann::json independent = nlohmann::json::parse(read_text(file("sphereval.json")));
    EXPECT_EQ(independent["valid"], true) << path << ": " << independent.dump();
    EXPECT_EQ(independent["flipped"], 0) << path;
  }
  EXPECT_GE(spheres, 15);
  EXPECT_GE(projected, 7);  // the cubes, boxes and the tetrahedron
}

TEST_F(Cli, SphereRefusesADiskSayingWhatItIsAndWritesNothing) {
  write_mesh(file("hemisphere.obj"), hemisphere(4));
  const Outcome outcome = run("sphere hemisphere.obj out.obj");
  EXPECT_EQ(outcome.exit_code, 2);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("1 boundary loop"), std::string::npos) << outcome.err;
  EXPECT_NE(outcome.err.find("harmonia unwrap"), std::string::npos) << outcome.err;
  EXPECT_FALSE(fs::exists(file("out.obj")));
}

TEST_F(Cli, SpherePolesAreUsedAndCheckedAgainstTheMesh) {
  write_mesh(file("sphere.obj"), unit_sphere(2));
  const Outcome outcome = run("sphere sphere.obj out.obj --poles 3 100 --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_EQ(outcome.json()["north_pole"], 3);
  EXPECT_EQ(outcome.json()["south_pole"], 100);
  const Outcome outside = run("sphere sphere.obj out.obj --poles 3 4000");
  EXPECT_EQ(outside.exit_code, 2);
  expect_one_line_reason(outside);
  EXPECT_NE(outside.err.find("--poles: 4000"), std::string::npos) << outside.err;
}

TEST_F(Cli, SphereUvSplitsTheDateLineSoThatNoTextureTriangleWrapsAround) {
  write_mesh(file("sphere.obj"), unit_sphere(3));
  const Outcome outcome = run("sphere sphere.obj out.obj --uv --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const TexturedMesh textured = read_textured_obj(file("out.obj"));
  ASSERT_EQ(textured.uv_faces.rows(), unit_sphere(3).face_count());
  EXPECT_GT(textured.uv.rows(), unit_sphere(3).vertex_count());  // the seam and poles split
  for (Eigen::Index f = 0; f < textured.uv_faces.rows(); ++f) {
    double low = 2.0, high = -1.0;
    for (int k = 0; k < 3; ++k) {
      const double u = textured.uv(textured.uv_faces(f, k), 0);
      low = std::min(low, u);
      high = std::max(high, u);
    }
    EXPECT_LE(high - low, 0.5) << "face " << f << " wraps around the date line";
  }
}

TEST_F(Cli, SpherePictureIsAPngAndOtherFormatsAreRefusedBeforeAnyWork) {
  write_mesh(file("sphere.obj"), unit_sphere(3));
  const Outcome outcome = run("sphere sphere.obj out.obj --picture out.png --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_EQ(report["picture"], "out.png");
  EXPECT_TRUE(report["timings"].contains("picture"));
  // A PNG of the default size: the signature, then IHDR's big-endian width and height.
  const std::string png = read_text(file("out.png"));
  ASSERT_GE(png.size(), 24u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const auto big_endian = [&](std::size_t at) {
    unsigned value = 0;
    for (std::size_t k = 0; k < 4; ++k)
      value = value << 8 | static_cast<unsigned char>(png[at + k]);
    return value;
  };
  EXPECT_EQ(big_endian(16), 1600u);
  EXPECT_EQ(big_endian(20), 900u);

  const Outcome jpg = run("sphere sphere.obj other.obj --picture out.jpg");
  EXPECT_EQ(jpg.exit_code, 1);
  expect_one_line_reason(jpg);
  EXPECT_FALSE(fs::exists(file("other.obj")));
  EXPECT_FALSE(fs::exists(file("out.jpg")));
}

TEST_F(Cli, EvalSphereRefusesAFileOfAnotherMesh) {
  write_mesh(file("small.obj"), unit_sphere(1));
  write_mesh(file("large.obj"), unit_sphere(2));
  const Outcome outcome = run("eval small.obj large.obj --sphere");
  EXPECT_EQ(outcome.exit_code, 2);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("does not belong to small.obj"), std::string::npos) << outcome.err;
}

// ----------------------------------------------------------------------------------------- deform

// An edit of the unit sphere: the bottom fixed, the top cap turned 60 degrees about x and lifted.
constexpr const char* kSphereEdit = R"({"description": "bend the top",
  "fixed": {"sphere": {"center": [0, 0, -1], "radius": 0.5}},
  "handles": [{"sphere": {"center": [0, 0, 1], "radius": 0.5}, "translate": [0, 0.2, 0.3],
               "rotate": {"axis": [1, 0, 0], "degrees": 60}}]})";

TEST_F(Cli, DeformPlaysFramesOnOneEditorAndPlacesTheHandles) {
  const Mesh mesh = unit_sphere(3);
  write_mesh(file("sphere.obj"), mesh);
  std::ofstream(file("edit.json")) << kSphereEdit;
  const Outcome outcome = run("deform sphere.obj edit.json out.obj --frames 4 --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_EQ(report["status"], "ok");
  EXPECT_EQ(report["frame_seconds"].size(), 4u);
  EXPECT_GT(report["setup_seconds"].get<double>(), 0.0);
  EXPECT_EQ(report["factorizations"], 1);
  EXPECT_EQ(report["turned_over_triangles"], 0);
  EXPECT_EQ(report["folded_triangles"], 0);
  EXPECT_EQ(report["handles"], 1);
  for (const char* stage : {"blending", "assembly", "solve"})
    EXPECT_GE(report["frame_split"][stage].get<double>(), 0.0) << stage;
  // OUT is the last frame: the full edit, handle vertices at their targets.
  const Mesh written = read_mesh(file("out.obj"));
  EXPECT_EQ(written.faces, mesh.faces);
  const EditDescription edit = parse_edit(kSphereEdit, mesh);
  for (const int v : edit.regions.handles[0])
    EXPECT_LT((written.vertices.row(v).transpose() - edit.transforms[0].apply(mesh.vertices.row(v).transpose())).norm(),
              1e-12);
  for (const int v : edit.regions.fixed) EXPECT_EQ(written.vertices.row(v), mesh.vertices.row(v));
}

// glTF in and out: the deformed positions go into the document (as floats, in each primitive's
// own coordinates), the same shape as the OBJ output; a map goes in as a texture-coordinate set.
TEST_F(Cli, DeformAndUnwrapWriteIntoGltfDocuments) {
  const Mesh mesh = unit_sphere(3);
  write_mesh(file("sphere.glb"), mesh);
  std::ofstream(file("edit.json")) << kSphereEdit;
  ASSERT_EQ(run("deform sphere.glb edit.json out.obj").exit_code, 0);
  const Outcome outcome = run("deform sphere.glb edit.json out.glb");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const Mesh as_obj = read_mesh(file("out.obj"));
  const Mesh as_gltf = read_mesh(file("out.glb"));
  EXPECT_EQ(as_gltf.faces, as_obj.faces);
  // Positions of about unit size, stored as floats: within float32's rounding.
  EXPECT_LT((as_gltf.vertices - as_obj.vertices).cwiseAbs().maxCoeff(), 4 * 0x1p-24);

  write_mesh(file("disk.obj"), hemisphere(4));
  ASSERT_EQ(run("unwrap disk.obj disk-uv.obj").exit_code, 0);
  const Outcome unwrapped = run("unwrap disk.obj disk-uv.glb");
  ASSERT_EQ(unwrapped.exit_code, 0) << unwrapped.err;
  const std::string glb = testing::file_bytes(file("disk-uv.glb"));
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  const nlohmann::json document = nlohmann::json::parse(glb.substr(20, json_length));
  EXPECT_TRUE(document["meshes"][0]["primitives"][0]["attributes"].contains("TEXCOORD_0"));
  EXPECT_EQ(document["accessors"][document["meshes"][0]["primitives"][0]["indices"].get<int>()]["count"],
            3 * hemisphere(4).face_count());
  // A repair that drops a face (here a repeated one) would change the file's faces: refused.
  Mesh doubled = hemisphere(4);
  doubled.faces.conservativeResize(doubled.faces.rows() + 1, 3);
  doubled.faces.row(doubled.faces.rows() - 1) = doubled.faces.row(0);
  write_mesh(file("doubled.obj"), doubled);
  const Outcome repaired = run("unwrap doubled.obj doubled-uv.gltf --cleanup repair");
  EXPECT_EQ(repaired.exit_code, 1) << repaired.err;
  EXPECT_NE(repaired.err.find("keeps the file's own faces"), std::string::npos) << repaired.err;
  EXPECT_FALSE(std::filesystem::exists(file("doubled-uv.gltf")));
}

// --frame-budget: each frame's refinement steps in the report, capped by --refine, none when the
// budget is shorter than the frame itself.
TEST_F(Cli, DeformFrameBudgetReportsEachFramesRefinementSteps) {
  write_mesh(file("sphere.obj"), unit_sphere(3));
  std::ofstream(file("edit.json")) << kSphereEdit;
  const Outcome capped = run("deform sphere.obj edit.json out.obj --frames 2 --refine 3 --frame-budget 3600000 --json");
  ASSERT_EQ(capped.exit_code, 0) << capped.err;
  EXPECT_EQ(capped.json()["frame_refinement_steps"], nlohmann::json::array({3, 3}));
  EXPECT_EQ(capped.json()["frame_budget_ms"], 3600000.0);
  const Outcome too_short = run("deform sphere.obj edit.json out.obj --frame-budget 0.000001 --json");
  ASSERT_EQ(too_short.exit_code, 0) << too_short.err;
  EXPECT_EQ(too_short.json()["frame_refinement_steps"], nlohmann::json::array({0}));
  const Outcome without = run("deform sphere.obj edit.json out.obj --refine 2 --json");
  ASSERT_EQ(without.exit_code, 0) << without.err;
  EXPECT_EQ(without.json()["frame_refinement_steps"], nlohmann::json::array({2}));
  EXPECT_TRUE(without.json()["frame_budget_ms"].is_null());
  const Outcome negative = run("deform sphere.obj edit.json out.obj --frame-budget -5");
  EXPECT_EQ(negative.exit_code, 1);  // a bad value: usage
  expect_one_line_reason(negative);
}

// The top cap pushed down through the fixed bottom cap: the band between them turns inside out.
// The deformed file is written, and the run exits 3 as every result with turned-over triangles.
TEST_F(Cli, DeformThatTurnsTrianglesOverIsWrittenButExitsThree) {
  const Mesh mesh = unit_sphere(3);
  write_mesh(file("sphere.obj"), mesh);
  std::ofstream(file("edit.json")) << R"({"fixed": {"sphere": {"center": [0, 0, -1], "radius": 0.5}},
    "handles": [{"sphere": {"center": [0, 0, 1], "radius": 0.5}, "translate": [0, 0, -3]}]})";
  const Outcome outcome = run("deform sphere.obj edit.json out.obj --json");
  EXPECT_EQ(outcome.exit_code, 3) << outcome.err;
  EXPECT_NE(outcome.err.find("turned over"), std::string::npos) << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_GT(report["turned_over_triangles"].get<int>(), 0);
  // Counted here from the written file: triangles whose normal left the rest normal's half-space
  // (a translation-only edit turns no triangle's target orientation).
  const Mesh written = read_mesh(file("out.obj"));
  int turned = 0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const auto normal = [&](const Mesh& m) {
      const Eigen::Vector3d a = m.vertices.row(m.faces(f, 0)), b = m.vertices.row(m.faces(f, 1)),
                            c = m.vertices.row(m.faces(f, 2));
      return Eigen::Vector3d((b - a).cross(c - a));
    };
    turned += normal(written).dot(normal(mesh)) <= 0.0;
  }
  EXPECT_EQ(report["turned_over_triangles"].get<int>(), turned);
}

TEST_F(Cli, DeformRefusesABadEditNamingTheFieldAndWritesNothing) {
  write_mesh(file("sphere.obj"), unit_sphere(2));
  std::ofstream(file("edit.json")) << R"({"handles": [{"vertices": [0, 5000]}]})";
  const Outcome outcome = run("deform sphere.obj edit.json out.obj");
  EXPECT_EQ(outcome.exit_code, 2);
  expect_one_line_reason(outcome);
  EXPECT_NE(outcome.err.find("handles[0].vertices[1]: vertex index 5000"), std::string::npos)
      << outcome.err;
  EXPECT_FALSE(fs::exists(file("out.obj")));
  std::ofstream(file("broken.json")) << "{\"handles\": [\n";
  const Outcome broken = run("deform sphere.obj broken.json out.obj");
  EXPECT_EQ(broken.exit_code, 2);
  EXPECT_NE(broken.err.find("broken.json:2:"), std::string::npos) << broken.err;
  EXPECT_FALSE(fs::exists(file("out.obj")));
}

TEST_F(Cli, DeformPictureIsAPngAndOtherFormatsAreRefusedBeforeAnyWork) {
  write_mesh(file("sphere.obj"), unit_sphere(3));
  std::ofstream(file("edit.json")) << kSphereEdit;
  const Outcome outcome = run("deform sphere.obj edit.json out.obj --picture edit.png");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const std::string png = testing::file_bytes(file("edit.png"));
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const Outcome refused = run("deform sphere.obj edit.json other.obj --picture edit.gif");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_FALSE(fs::exists(file("other.obj")));
}

// --------------------------------------------------------------------------------------- transfer

TEST_F(Cli, TransferWritesOnePoseFilePerSourcePoseInTheTargetsOrder) {
  // The source onto itself (identity markers): every triangle matches itself, so the pose comes
  // back exactly (the library tests transfer between different meshes).
  const Mesh source = unit_sphere(2);
  const Mesh target = source;
  write_mesh(file("source.obj"), source);
  write_mesh(file("target.obj"), target);
  Mesh pose = source;
  pose.vertices.col(1) *= 0.8;
  write_mesh(file("squashed.obj"), pose);
  std::ofstream(file("markers.txt")) << "# pairs\n0 0\n5 5\n9 9\n20 20\n33 33\n";
  const Outcome outcome = run(
      "transfer --source-rest source.obj --source-poses squashed.obj --target target.obj "
      "--markers markers.txt --out poses --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_EQ(report["markers"], 5);
  EXPECT_EQ(report["pose_seconds"].size(), 1u);
  EXPECT_GT(report["setup_seconds"].get<double>(), 0.0);
  // Every triangle matches itself.
  EXPECT_EQ(report["matched_triangles"], target.face_count());
  EXPECT_EQ(report["unmatched_triangles"], 0);
  EXPECT_EQ(report["poses"][0]["turned_over_triangles"], 0);
  EXPECT_EQ(report["poses"][0]["folded_triangles"], 0);
  const Mesh written = read_mesh(file("poses/squashed.obj"));
  EXPECT_EQ(written.faces, target.faces);
  // The squash along y comes back: the height shrinks to 0.8, up to the solve's rounding.
  const auto height = [](const Mesh& mesh) {
    return mesh.vertices.col(1).maxCoeff() - mesh.vertices.col(1).minCoeff();
  };
  EXPECT_NEAR(height(written) / height(target), 0.8, 1e-6);
  EXPECT_FALSE(report.contains("pictures"));  // Only with --picture.
}

TEST_F(Cli, TransferPictureDrawsTheCorrespondenceAndEveryPoseBesideItsSource) {
  const Mesh sphere = unit_sphere(2);
  write_mesh(file("source.obj"), sphere);
  Mesh pose = sphere;
  pose.vertices.col(1) *= 0.8;
  write_mesh(file("squashed.obj"), pose);
  std::ofstream(file("markers.txt")) << "0 0\n5 5\n9 9\n20 20\n33 33\n";
  const Outcome outcome = run(
      "transfer --source-rest source.obj --source-poses squashed.obj --target source.obj "
      "--markers markers.txt --out poses --picture --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_EQ(report["pictures"],
            nlohmann::json::array({"poses/correspondence.png", "poses/squashed.png"}));
  for (const std::string picture : {"poses/correspondence.png", "poses/squashed.png"}) {
    const std::string png = testing::file_bytes(file(picture));
    ASSERT_GT(png.size(), 8u) << picture;
    EXPECT_EQ(png.substr(1, 3), "PNG") << picture;
  }
  EXPECT_TRUE(fs::exists(file("poses/squashed.obj")));

  // A pose whose picture would replace the correspondence picture is refused before any work.
  write_mesh(file("correspondence.obj"), pose);
  const Outcome clash = run(
      "transfer --source-rest source.obj --source-poses correspondence.obj --target source.obj "
      "--markers markers.txt --out clash --picture");
  EXPECT_EQ(clash.exit_code, 2);
  expect_one_line_reason(clash);
  EXPECT_NE(clash.err.find("would replace correspondence.png"), std::string::npos) << clash.err;
  EXPECT_FALSE(fs::exists(file("clash")));
}

TEST_F(Cli, TransferRefusesBadMarkersAndPosesNamingFileAndLine) {
  write_mesh(file("source.obj"), unit_sphere(2));
  write_mesh(file("other.obj"), unit_sphere(1));
  std::ofstream(file("markers.txt")) << "0 0\n5 five\n";
  const Outcome malformed = run(
      "transfer --source-rest source.obj --source-poses source.obj --target source.obj "
      "--markers markers.txt --out poses");
  EXPECT_EQ(malformed.exit_code, 2);
  expect_one_line_reason(malformed);
  EXPECT_NE(malformed.err.find("markers.txt:2:"), std::string::npos) << malformed.err;
  std::ofstream(file("good.txt")) << "0 0\n5 5\n9 9\n";
  const Outcome wrong_pose = run(
      "transfer --source-rest source.obj --source-poses other.obj --target source.obj "
      "--markers good.txt --out poses");
  EXPECT_EQ(wrong_pose.exit_code, 2);
  EXPECT_NE(wrong_pose.err.find("not the connectivity of source.obj"), std::string::npos)
      << wrong_pose.err;
  EXPECT_FALSE(fs::exists(file("poses")));
}

// ------------------------------------------------------------------------------------------ atlas

// Two components with holes and genus: a sphere, and beside it a torus with two faces removed.
Mesh sphere_and_holed_torus() {
  const Mesh sphere = unit_sphere(2);
  Mesh torus = testing::without_faces(testing::torus(24, 12), {0, 100});
  torus.vertices.col(0).array() += 4.0;
  Mesh both;
  both.vertices.resize(sphere.vertex_count() + torus.vertex_count(), 3);
  both.vertices << sphere.vertices, torus.vertices;
  both.faces.resize(sphere.face_count() + torus.face_count(), 3);
  both.faces << sphere.faces, (torus.faces.array() + sphere.vertex_count()).matrix();
  return both;
}

TEST_F(Cli, AtlasWritesPerCornerUvsInTheUnitSquareWithOneGroupLinePerChartChange) {
  const Mesh mesh = sphere_and_holed_torus();
  write_mesh(file("two.obj"), mesh);
  const Outcome outcome = run("atlas two.obj atlas.obj --resolution 256 --backend cpu --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json report = outcome.json();
  EXPECT_EQ(report["status"], "ok");
  EXPECT_EQ(report["backend"], "cpu");
  EXPECT_EQ(report["faces"], mesh.face_count());
  EXPECT_EQ(report["resolution"], 256);
  for (const char* defect : {"flipped_triangles", "mirrored_charts", "overlapping_texels",
                             "boundary_crossings", "dropped_faces"})
    EXPECT_EQ(report[defect], 0) << defect;
  EXPECT_GT(report["coverage"].get<double>(), 0.0);
  EXPECT_LE(report["coverage"].get<double>(), 1.0);
  EXPECT_GT(report["texels_per_unit"].get<double>(), 0.0);
  EXPECT_GE(report["l2_stretch"].get<double>(), 1.0);
  EXPECT_GE(report["angle_distortion"].get<double>(), 1.0);
  EXPECT_GE(report["area_distortion"].get<double>(), 0.0);
  for (const char* phase : {"read", "segmentation", "flattening", "packing", "metrics", "write"})
    EXPECT_TRUE(report["timings"].contains(phase)) << phase;
  EXPECT_GT(report["seconds"].get<double>(), 0.0);
  const int charts = report["charts"];
  ASSERT_EQ(report["per_chart"].size(), static_cast<std::size_t>(charts));
  int chart_faces = 0;
  for (const nlohmann::json& chart : report["per_chart"]) {
    chart_faces += chart["faces"].get<int>();
    for (const char* field : {"method", "l2_stretch", "angle_distortion", "area_distortion",
                              "surface_area", "texel_box"})
      EXPECT_TRUE(chart.contains(field)) << field;
    EXPECT_LE(chart["texel_box"]["max"][0].get<double>(), 256.0);
  }
  EXPECT_EQ(chart_faces, mesh.face_count());

  const ObjContents obj = parse_obj(file("atlas.obj"));
  // The input's vertices and faces, in input order.
  ASSERT_EQ(obj.positions.size(), static_cast<std::size_t>(mesh.vertex_count()));
  ASSERT_EQ(obj.corner_faces.size(), static_cast<std::size_t>(mesh.face_count()));
  for (int f = 0; f < mesh.face_count(); ++f)
    EXPECT_EQ(obj.corner_faces[f], mesh.faces.row(f).transpose()) << "face " << f;
  for (const Eigen::Vector2d& uv : obj.uvs) {
    EXPECT_GE(uv.minCoeff(), 0.0);
    EXPECT_LE(uv.maxCoeff(), 1.0);
  }
  // A group line before the first face and wherever the chart changes, and nowhere else.
  int changes = 0;
  for (std::size_t f = 0; f < obj.chart_of_face.size(); ++f)
    if (f == 0 || obj.chart_of_face[f] != obj.chart_of_face[f - 1]) ++changes;
  EXPECT_EQ(static_cast<int>(obj.group_charts.size()), changes);
  EXPECT_EQ(static_cast<int>(std::set<int>(obj.group_charts.begin(), obj.group_charts.end()).size()),
            charts);
  // Every UV triangle counter-clockwise: no flip, no mirrored chart.
  for (std::size_t f = 0; f < obj.uv_faces.size(); ++f) {
    const Eigen::Vector2d a = obj.uvs[obj.uv_faces[f][0]], b = obj.uvs[obj.uv_faces[f][1]],
                          c = obj.uvs[obj.uv_faces[f][2]];
    const Eigen::Vector2d e1 = b - a, e2 = c - a;
    EXPECT_GT(e1.x() * e2.y() - e1.y() * e2.x(), 0.0) << "face " << f;
  }
}

// `view` of an atlas: a page whose charts are the atlas' own (the report's count, found again by
// the page's writer as the faces connected through shared UVs), with the atlas' faces; given the
// 3D mesh apart, the same; a file that is missing or no HTML page is refused in one line.
TEST_F(Cli, ViewWritesAPageOfTheAtlasWithItsChartsAndRefusesBadFiles) {
  const Mesh mesh = sphere_and_holed_torus();
  write_mesh(file("two.obj"), mesh);
  const Outcome atlas = run("atlas two.obj atlas.obj --resolution 256 --backend cpu --json");
  ASSERT_EQ(atlas.exit_code, 0) << atlas.err;
  const int charts = atlas.json()["charts"];
  for (const std::string arguments : {"view atlas.obj --out page.html", "view atlas.obj --mesh two.obj -o page.html"}) {
    SCOPED_TRACE(arguments);
    fs::remove(file("page.html"));
    const Outcome outcome = run(arguments);
    ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
    const nlohmann::json data = testing::view_page_data(testing::file_bytes(file("page.html")));
    ASSERT_EQ(data["results"].size(), 1u);
    const nlohmann::json& result = data["results"][0];
    EXPECT_EQ(result["face_count"], mesh.face_count());
    EXPECT_EQ(result["charts"].size(), static_cast<std::size_t>(charts));
    const std::vector<std::int32_t> chart = testing::view_page_array<std::int32_t>(result["chart"]);
    EXPECT_EQ(*std::max_element(chart.begin(), chart.end()), charts - 1);
    const std::vector<std::uint8_t> turned = testing::view_page_array<std::uint8_t>(result["flipped"]);
    EXPECT_EQ(std::count(turned.begin(), turned.end(), 1), 0);
  }
  for (const std::string arguments : {"view missing.obj --out bad.html", "view atlas.obj --out bad.png"}) {
    SCOPED_TRACE(arguments);
    const Outcome outcome = run(arguments);
    EXPECT_NE(outcome.exit_code, 0);
    expect_one_line_reason(outcome);
  }
  EXPECT_FALSE(fs::exists(file("bad.html")));
  EXPECT_FALSE(fs::exists(file("bad.png")));
}

TEST_F(Cli, AtlasPictureIsAPngAndBadInputOrOptionsAreRefusedBeforeAnyWork) {
  write_mesh(file("sphere.obj"), unit_sphere(2));
  const Outcome outcome = run("atlas sphere.obj atlas.obj --picture atlas.png --threads 1");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("charts"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("coverage"), std::string::npos) << outcome.out;
  const std::string png = testing::file_bytes(file("atlas.png"));
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");

  std::ofstream(file("bad.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
  const Outcome bad = run("atlas bad.obj bad-atlas.obj");
  EXPECT_EQ(bad.exit_code, 2);
  expect_one_line_reason(bad);
  EXPECT_NE(bad.err.find("bad.obj:4"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(file("bad-atlas.obj")));

  for (const std::string arguments :
       {"atlas sphere.obj other.obj --picture atlas.svg", "atlas sphere.obj other.obj --max-distortion 1",
        "atlas sphere.obj other.obj --resolution 8", "atlas sphere.obj other.ply",
        "atlas sphere.obj other.obj --backend gpu"}) {
    SCOPED_TRACE(arguments);
    const Outcome refused = run(arguments);
    EXPECT_EQ(refused.exit_code, 1);
    expect_one_line_reason(refused);
  }
  EXPECT_FALSE(fs::exists(file("other.obj")));
}

// ------------------------------------------------------------------------------------------ batch

// The lines of a batch log, by input file name (the last line of each name wins), and their count.
struct BatchLogContents {
  std::map<std::string, nlohmann::json> by_name;
  std::vector<nlohmann::json> lines;
};

BatchLogContents read_batch_log(const fs::path& path) {
  BatchLogContents log;
  for (const std::string& line : lines_of(read_text(path))) {
    log.lines.push_back(nlohmann::json::parse(line));
    log.by_name[fs::path(log.lines.back()["input"].get<std::string>()).filename().string()] =
        log.lines.back();
  }
  return log;
}

TEST_F(Cli, BatchRunsEachInputInItsOwnProcessLogsTheBadOneAndResumes) {
  // Three small meshes and, in the middle of the sorted order, a file that is not a mesh.
  fs::create_directories(file("meshes/sub"));
  write_mesh(file("meshes/a.obj"), unit_sphere(1));
  std::ofstream(file("meshes/bad.obj")) << "this is not a mesh\n";
  write_mesh(file("meshes/c.obj"), testing::torus(12, 6));
  write_mesh(file("meshes/sub/d.off"), hemisphere(3));
  std::ofstream(file("meshes/notes.txt")) << "not a mesh file: not an input\n";

  const Outcome outcome = run("batch meshes --out out -j 2 --json");
  EXPECT_EQ(outcome.exit_code, 2) << outcome.err;
  const nlohmann::json summary = outcome.json();
  EXPECT_EQ(summary["inputs"], 4);
  EXPECT_EQ(summary["ok"], 3);
  EXPECT_EQ(summary["failed"], 1);
  EXPECT_EQ(summary["skipped"], 0);
  for (const char* output : {"out/a.obj", "out/c.obj", "out/sub/d.obj"})
    EXPECT_TRUE(fs::exists(file(output))) << output;
  EXPECT_FALSE(fs::exists(file("out/bad.obj")));
  EXPECT_FALSE(fs::exists(file("out/notes.obj")));

  const BatchLogContents log = read_batch_log(file("out/batch-log.jsonl"));
  ASSERT_EQ(log.lines.size(), 4u);
  const nlohmann::json& bad = log.by_name.at("bad.obj");
  EXPECT_EQ(bad["status"], "failed");
  EXPECT_EQ(bad["exit_code"], 2);
  EXPECT_NE(bad["error"].get<std::string>().find("bad.obj:1"), std::string::npos) << bad;
  for (const char* name : {"a.obj", "c.obj", "d.off"}) {
    const nlohmann::json& line = log.by_name.at(name);
    EXPECT_EQ(line["status"], "ok") << line;
    EXPECT_TRUE(line["error"].is_null());
    EXPECT_GT(line["seconds"].get<double>(), 0.0);
    EXPECT_GE(line["quality"]["charts"].get<int>(), 1);
    EXPECT_GT(line["quality"]["coverage"].get<double>(), 0.0);
    EXPECT_EQ(line["quality"]["flips"], 0);
    EXPECT_EQ(line["quality"]["overlaps"], 0);
  }

  // The batch's children each flatten on one thread; `harmonia atlas` on 1, 2 or 3 threads
  // writes the same bytes as they did.
  for (const char* threads : {"1", "2", "3"}) {
    SCOPED_TRACE(threads);
    const Outcome single = run(std::string("atlas meshes/c.obj c-") + threads + ".obj --threads " + threads);
    EXPECT_EQ(single.exit_code, 0) << single.err;
    EXPECT_EQ(read_text(file("out/c.obj")), read_text(file(std::string("c-") + threads + ".obj")));
  }

  // Resumed: the three outputs are there and skipped; the bad file is tried again.
  const Outcome resumed = run("batch meshes --out out -j 2 --resume --json");
  EXPECT_EQ(resumed.exit_code, 2) << resumed.err;
  EXPECT_EQ(resumed.json()["skipped"], 3);
  EXPECT_EQ(resumed.json()["failed"], 1);
  const BatchLogContents appended = read_batch_log(file("out/batch-log.jsonl"));
  ASSERT_EQ(appended.lines.size(), 8u);
  for (const char* name : {"a.obj", "c.obj", "d.off"})
    EXPECT_EQ(appended.by_name.at(name)["status"], "skipped") << name;
  EXPECT_EQ(appended.by_name.at("bad.obj")["status"], "failed");
}

// The pieces another scheduler runs the batch with (python -m harmonia.distributed): the plan
// names what the batch would run and skip, a task makes the batch's output and log line, and the
// summary of a run's lines is the batch's, with its exit code.
TEST_F(Cli, BatchPlanTaskAndSummaryAreTheBatchsOwn) {
  fs::create_directories(file("meshes"));
  write_mesh(file("meshes/a.obj"), unit_sphere(1));
  std::ofstream(file("meshes/bad.obj")) << "this is not a mesh\n";
  ASSERT_EQ(run("batch meshes --out batch -j 1").exit_code, 2);

  // A plan writes and runs nothing; with --resume it carries the skipped input's log line.
  const Outcome plan = run("batch meshes --out planned --plan");
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  std::map<std::string, nlohmann::json> steps;
  for (const std::string& line : lines_of(plan.out)) {
    const nlohmann::json step = nlohmann::json::parse(line);
    steps[fs::path(step["input"].get<std::string>()).filename().string()] = step;
  }
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps.at("a.obj")["run"], true);
  EXPECT_EQ(steps.at("a.obj")["output"], "planned/a.obj");
  EXPECT_FALSE(fs::exists(file("planned/batch-log.jsonl")));
  EXPECT_FALSE(fs::exists(file("planned/a.obj")));

  // Each task: the batch's output, byte for byte, and its log line but for the folder and time.
  for (const auto& [name, step] : steps) {
    const Outcome task = run("batch --out planned --task " + step["input"].get<std::string>() + " " +
                             step["output"].get<std::string>());
    ASSERT_EQ(task.exit_code, 0) << task.err;
    std::ofstream(file("planned/run.jsonl"), std::ios::app) << task.out;
    nlohmann::json line = nlohmann::json::parse(task.out);
    nlohmann::json expected = read_batch_log(file("batch/batch-log.jsonl")).by_name.at(name);
    for (nlohmann::json* entry : {&line, &expected}) entry->erase("seconds"), entry->erase("output");
    EXPECT_EQ(line, expected) << name;
  }
  EXPECT_EQ(read_text(file("planned/a.obj")), read_text(file("batch/a.obj")));
  const Outcome summary = run("batch --out planned --summary-of " + file("planned/run.jsonl").string() +
                              " --elapsed 2.5 -j 3 --json");
  EXPECT_EQ(summary.exit_code, 2);
  EXPECT_EQ(summary.json()["inputs"], 2);
  EXPECT_EQ(summary.json()["failed"], 1);
  EXPECT_EQ(summary.json()["jobs"], 3);
  EXPECT_DOUBLE_EQ(summary.json()["seconds"].get<double>(), 2.5);

  const Outcome resumed_plan = run("batch meshes --out batch --plan --resume");
  ASSERT_EQ(resumed_plan.exit_code, 0) << resumed_plan.err;
  for (const std::string& line : lines_of(resumed_plan.out)) {
    const nlohmann::json step = nlohmann::json::parse(line);
    const bool is_a = fs::path(step["input"].get<std::string>()).filename() == "a.obj";
    EXPECT_EQ(step["run"], !is_a) << step;  // the bad file runs again, a.obj is skipped
    if (is_a) EXPECT_EQ(step["record"]["status"], "skipped");
  }
  EXPECT_EQ(read_batch_log(file("batch/batch-log.jsonl")).lines.size(), 2u);  // the plan wrote none
}

TEST_F(Cli, BatchWithAMethodWritesUvObjsAndRefusesOptionsThatMeanNothing) {
  fs::create_directories(file("disks"));
  fs::create_directories(file("more"));
  write_mesh(file("disks/cap.obj"), hemisphere(3));
  write_mesh(file("disks/flat.ply"), planar_disk(3));
  write_mesh(file("more/cap.obj"), hemisphere(2));
  // A given file goes to OUT/<its name>: more/cap.obj and disks/cap.obj share their name, so the
  // later one is numbered.
  const Outcome outcome = run("batch disks more/cap.obj --out uv --method conformal -j 2");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.err;
  const std::map<std::string, std::pair<std::string, int>> expected = {
      {"disks/cap.obj", {"uv/cap.obj", hemisphere(3).vertex_count()}},
      {"disks/flat.ply", {"uv/flat.obj", planar_disk(3).vertex_count()}},
      {"more/cap.obj", {"uv/cap-2.obj", hemisphere(2).vertex_count()}}};
  const BatchLogContents log = read_batch_log(file("uv/batch-log.jsonl"));
  ASSERT_EQ(log.lines.size(), 3u);
  for (const nlohmann::json& line : log.lines) {
    SCOPED_TRACE(line.dump());
    const auto& [output, vertices] = expected.at(line["input"].get<std::string>());
    EXPECT_EQ(line["output"], output);
    EXPECT_EQ(line["status"], "ok");
    EXPECT_EQ(line["quality"]["flipped_triangles"], 0);
    const ObjContents obj = parse_obj(file(output));
    EXPECT_EQ(obj.faces_not_in_a_slash_a_form, 0);
    EXPECT_EQ(obj.uvs.size(), obj.positions.size());
    EXPECT_EQ(static_cast<int>(obj.positions.size()), vertices);
  }

  for (const std::string arguments :
       {"batch disks --out x --method lscm --resolution 64", "batch disks --out x --cut",
        "batch disks --out x --method nonsense", "batch disks --out x --atlas --method lscm",
        "batch disks --out x -j 0", "batch disks --out disks"}) {
    SCOPED_TRACE(arguments);
    const Outcome refused = run(arguments);
    EXPECT_EQ(refused.exit_code, 1);
    expect_one_line_reason(refused);
  }
  EXPECT_FALSE(fs::exists(file("x")));
}

// Inputs whose outputs would share a name each get their own: side by side in one folder, the
// extension is kept in front of the .obj (fuze.obj and fuze.ply, box.obj and box.STL); the same
// relative path below two given folders is numbered. --resume finds the same names again.
TEST_F(Cli, BatchGivesEveryInputAnOutputOfItsOwn) {
  fs::create_directories(file("models"));
  fs::create_directories(file("more"));
  write_mesh(file("models/fuze.obj"), unit_sphere(1));
  write_mesh(file("models/fuze.ply"), testing::torus(10, 5));
  write_mesh(file("models/box.obj"), octahedron());
  {  // No STL writer in the library: an ASCII STL by hand, one facet per face.
    const Mesh sphere = unit_sphere(0);
    std::ofstream stl(file("models/box.STL"));
    stl.precision(17);
    stl << "solid box\n";
    for (int f = 0; f < sphere.face_count(); ++f) {
      stl << "facet normal 0 0 0\nouter loop\n";
      for (int k = 0; k < 3; ++k) stl << "vertex " << sphere.vertices.row(sphere.faces(f, k)) << "\n";
      stl << "endloop\nendfacet\n";
    }
    stl << "endsolid box\n";
  }
  write_mesh(file("models/part.off"), hemisphere(3));
  write_mesh(file("more/part.off"), hemisphere(2));
  const std::map<std::string, std::pair<std::string, int>> expected = {
      {"models/fuze.obj", {"out/fuze.obj.obj", unit_sphere(1).face_count()}},
      {"models/fuze.ply", {"out/fuze.ply.obj", testing::torus(10, 5).face_count()}},
      {"models/box.obj", {"out/box.obj.obj", octahedron().face_count()}},
      {"models/box.STL", {"out/box.STL.obj", unit_sphere(0).face_count()}},
      {"models/part.off", {"out/part.obj", hemisphere(3).face_count()}},
      {"more/part.off", {"out/part-2.obj", hemisphere(2).face_count()}}};

  const Outcome outcome = run("batch models more --out out -j 2 --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_EQ(outcome.json()["ok"], 6);
  const BatchLogContents log = read_batch_log(file("out/batch-log.jsonl"));
  ASSERT_EQ(log.lines.size(), 6u);
  double seconds = 0.0;
  for (const nlohmann::json& line : log.lines) {
    SCOPED_TRACE(line.dump());
    const auto& [output, faces] = expected.at(line["input"].get<std::string>());
    EXPECT_EQ(line["output"], output);
    EXPECT_EQ(line["status"], "ok");
    EXPECT_EQ(static_cast<int>(parse_obj(file(output)).corner_faces.size()), faces);
    seconds += line["seconds"].get<double>();
  }
  // The mean over the inputs that ran, from the log's own figures.
  EXPECT_NEAR(outcome.json()["seconds_per_file"].get<double>(), seconds / 6.0, 1e-9 * seconds);

  // Resumed with an output the log says was written with defects (exit code 3): that input runs
  // again, the others are skipped; the mean seconds count the one that ran, not the skipped.
  std::ofstream(file("out/batch-log.jsonl"), std::ios::app)
      << R"({"input":"models/box.STL","output":"out/box.STL.obj","status":"failed","error":"the )"
         R"(atlas has 1 crossing chart boundaries","exit_code":3,"signal":null,"seconds":0.5,)"
         R"("quality":null})" << '\n';
  const Outcome resumed = run("batch models more --out out -j 2 --resume --json");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(resumed.json()["skipped"], 5);
  EXPECT_EQ(resumed.json()["ok"], 1);
  const BatchLogContents appended = read_batch_log(file("out/batch-log.jsonl"));
  ASSERT_EQ(appended.lines.size(), 13u);
  const nlohmann::json& rerun = appended.by_name.at("box.STL");
  EXPECT_EQ(rerun["status"], "ok") << rerun;
  EXPECT_NEAR(resumed.json()["seconds_per_file"].get<double>(), rerun["seconds"].get<double>(),
              1e-9 * rerun["seconds"].get<double>());

  // --resume-keep-defective keeps such an output as it is.
  std::ofstream(file("out/batch-log.jsonl"), std::ios::app)
      << R"({"input":"models/box.STL","output":"out/box.STL.obj","status":"failed","error":"x",)"
         R"("exit_code":3,"signal":null,"seconds":0.5,"quality":null})" << '\n';
  const Outcome kept = run("batch models more --out out --resume --resume-keep-defective --json");
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_EQ(kept.json()["skipped"], 6);
  EXPECT_EQ(kept.json()["seconds_per_file"], 0.0);
  EXPECT_EQ(run("batch models --out out --resume-keep-defective").exit_code, 1);
}

// A fin on a plate as an exporter writes it, each square with vertices of its own: --cleanup
// repair welds the split vertices, which makes the shared edge non-manifold; the atlas keeps it as
// a chart boundary and says so, instead of refusing the asset. --keep-splits keeps the file's
// splits as chart boundaries; by default the charts span them.
TEST_F(Cli, AtlasRepairKeepsWhatWeldingMakesNonManifoldAndChartsSpanSplits) {
  std::ofstream(file("fin.obj")) << "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\n"
                                    "v 0 0 0\nv 0 1 0\nv -1 0 0\nv -1 1 0\n"
                                    "v 0 0 0\nv 0 1 0\nv 0 0 1\nv 0 1 1\n"
                                    "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 9 11 12\nf 9 12 10\n";
  const Outcome repaired = run("atlas fin.obj fin-atlas.obj --cleanup repair --json");
  ASSERT_EQ(repaired.exit_code, 0) << repaired.err;
  const nlohmann::json report = repaired.json();
  bool said = false;
  for (const auto& change : report["cleanup_changes"])
    said = said || change.get<std::string>().find("1 non-manifold edge") != std::string::npos;
  EXPECT_TRUE(said) << report["cleanup_changes"];
  EXPECT_EQ(parse_obj(file("fin-atlas.obj")).corner_faces.size(), 6u);

  // A flat square of two triangles written with its diagonal split: one chart by default, two
  // with --keep-splits.
  std::ofstream(file("square.obj")) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 0\nv 1 1 0\nv 0 1 0\n"
                                       "f 1 2 3\nf 4 5 6\n";
  const Outcome spanned = run("atlas square.obj spanned.obj --json");
  ASSERT_EQ(spanned.exit_code, 0) << spanned.err;
  EXPECT_EQ(spanned.json()["charts"], 1);
  EXPECT_EQ(spanned.json()["welded_vertices"], 2);
  const ObjContents spanned_obj = parse_obj(file("spanned.obj"));
  ASSERT_EQ(spanned_obj.uv_faces.size(), 2u);
  // The corners at (0,0,0) and (1,1,0) of both triangles share their UV.
  EXPECT_EQ(spanned_obj.uvs[spanned_obj.uv_faces[0][0]], spanned_obj.uvs[spanned_obj.uv_faces[1][0]]);
  EXPECT_EQ(spanned_obj.uvs[spanned_obj.uv_faces[0][2]], spanned_obj.uvs[spanned_obj.uv_faces[1][1]]);
  const Outcome kept = run("atlas square.obj kept.obj --keep-splits --json");
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_EQ(kept.json()["charts"], 2);
}

// --join-charts joins the charts of a sphere whose unions flatten within the limit (segmented in
// a 30-degree cone: at the default 60 the segmentation already leaves about the charts a sphere
// needs): fewer charts than without it, each within --max-distortion, and the report says it was
// asked. batch passes it on to each atlas and refuses it for unwrap.
TEST_F(Cli, AtlasJoinChartsMakesFewerChartsWithinTheLimit) {
  write_mesh(file("sphere.obj"), unit_sphere(4));
  const Outcome separate = run("atlas sphere.obj separate.obj --max-normal-deviation 30 --json");
  ASSERT_EQ(separate.exit_code, 0) << separate.err;
  EXPECT_EQ(separate.json()["join_charts"], false);
  const Outcome joined = run("atlas sphere.obj joined.obj --max-normal-deviation 30 --join-charts --json");
  ASSERT_EQ(joined.exit_code, 0) << joined.err;
  const nlohmann::json report = joined.json();
  EXPECT_EQ(report["join_charts"], true);
  EXPECT_LT(report["charts"].get<int>(), separate.json()["charts"].get<int>());
  EXPECT_EQ(report["flipped_triangles"], 0);
  EXPECT_EQ(report["overlapping_texels"], 0);
  for (const auto& chart : report["per_chart"]) EXPECT_LE(chart["l2_stretch"].get<double>(), 1.006);

  // batch has no cone option: an ellipsoid three times longer than wide, whose charts at the
  // default cone still join, shows that it passes --join-charts on.
  Mesh ellipsoid = unit_sphere(4);
  ellipsoid.vertices.col(2) *= 3.0;
  write_mesh(file("ellipsoid.obj"), ellipsoid);
  fs::create_directories(file("models"));
  write_mesh(file("models/ellipsoid.obj"), ellipsoid);
  const Outcome ellipsoid_separate = run("atlas ellipsoid.obj ellipsoid-separate.obj --json");
  const Outcome ellipsoid_joined = run("atlas ellipsoid.obj ellipsoid-joined.obj --join-charts --json");
  ASSERT_EQ(ellipsoid_separate.exit_code, 0) << ellipsoid_separate.err;
  ASSERT_EQ(ellipsoid_joined.exit_code, 0) << ellipsoid_joined.err;
  ASSERT_LT(ellipsoid_joined.json()["charts"].get<int>(), ellipsoid_separate.json()["charts"].get<int>());
  const Outcome batch = run("batch models --out out --join-charts --json");
  ASSERT_EQ(batch.exit_code, 0) << batch.err;
  EXPECT_EQ(read_batch_log(file("out/batch-log.jsonl")).by_name.at("ellipsoid.obj")["quality"]["charts"],
            ellipsoid_joined.json()["charts"]);
  EXPECT_EQ(run("batch models --out out2 --method lscm --join-charts").exit_code, 1);
}

// At --texels-per-unit the charts that do not fit one square go on further pages: a cube of side
// 2 at 400 texels per unit has sides of 800 texels, one per 1024^2 page. The OBJ names each
// chart's page (g chart_N_aP) and the page count; the glTF gives each vertex its page (_PAGE);
// --max-pages below what is needed, and --picture of several pages, are refused with nothing
// written; batch passes both options on.
TEST_F(Cli, AtlasAtATexelDensityTakesAsManyPagesAsItNeeds) {
  write_mesh(file("cube.obj"), testing::grid_cube(4));
  const Outcome paged = run("atlas cube.obj paged.obj --texels-per-unit 400 --json");
  ASSERT_EQ(paged.exit_code, 0) << paged.err;
  const nlohmann::json report = paged.json();
  EXPECT_EQ(report["pages"], 6);
  EXPECT_EQ(report["page_coverage"].size(), 6u);
  for (const char* defect : {"flipped_triangles", "mirrored_charts", "overlapping_texels", "boundary_crossings", "dropped_faces"})
    EXPECT_EQ(report[defect], 0) << defect;
  std::set<int> pages_of_charts;
  for (const nlohmann::json& chart : report["per_chart"]) pages_of_charts.insert(chart["page"].get<int>());
  EXPECT_EQ(pages_of_charts, (std::set<int>{0, 1, 2, 3, 4, 5}));
  const std::string text = read_text(file("paged.obj"));
  EXPECT_NE(text.find("# xatlas_atlas 1024 1024 6\n"), std::string::npos);
  static const std::regex paged_group(R"(g chart_(\d+)_a(\d+))");
  std::set<int> pages_in_file;
  for (std::sregex_iterator it(text.begin(), text.end(), paged_group), end; it != end; ++it)
    pages_in_file.insert(std::stoi((*it)[2]));
  EXPECT_EQ(pages_in_file, pages_of_charts);

  const Outcome gltf = run("atlas cube.obj paged.glb --texels-per-unit 400");
  ASSERT_EQ(gltf.exit_code, 0) << gltf.err;
  const std::string glb = read_text(file("paged.glb"));
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  EXPECT_TRUE(nlohmann::json::parse(glb.substr(20, json_length))["meshes"][0]["primitives"][0]["attributes"].contains("_PAGE"));

  const Outcome limited = run("atlas cube.obj limited.obj --texels-per-unit 400 --max-pages 3");
  EXPECT_EQ(limited.exit_code, 2) << limited.err;
  EXPECT_NE(limited.err.find("3 pages"), std::string::npos) << limited.err;
  EXPECT_FALSE(fs::exists(file("limited.obj")));
  const Outcome drawn = run("atlas cube.obj drawn.obj --texels-per-unit 400 --picture drawn.png");
  EXPECT_EQ(drawn.exit_code, 1) << drawn.err;
  EXPECT_NE(drawn.err.find("6 pages"), std::string::npos) << drawn.err;
  EXPECT_FALSE(fs::exists(file("drawn.obj")));
  EXPECT_FALSE(fs::exists(file("drawn.png")));

  fs::create_directories(file("models"));
  write_mesh(file("models/cube.obj"), testing::grid_cube(4));
  const Outcome batch = run("batch models --out out --texels-per-unit 400 --json");
  ASSERT_EQ(batch.exit_code, 0) << batch.err;
  EXPECT_NE(read_text(file("out/cube.obj")).find("# xatlas_atlas 1024 1024 6\n"), std::string::npos);
  const Outcome limited_batch = run("batch models --out out2 --texels-per-unit 400 --max-pages 3");
  EXPECT_EQ(limited_batch.exit_code, 2) << limited_batch.err;  // some inputs failed: the log says why
  EXPECT_NE(read_text(file("out2/batch-log.jsonl")).find("3 pages"), std::string::npos);
  EXPECT_FALSE(fs::exists(file("out2/cube.obj")));
  EXPECT_EQ(run("batch models --out out3 --method lscm --texels-per-unit 400").exit_code, 1);
}

// --resolution WxH makes a non-square atlas: the report and the OBJ's size line say 512 x 128, the
// charts stay inside it and isometric in texels; batch passes it on; malformed sizes are refused.
TEST_F(Cli, AtlasResolutionWxHMakesANonSquareAtlas) {
  write_mesh(file("cube.obj"), testing::grid_cube(4));
  const Outcome wide = run("atlas cube.obj wide.obj --resolution 512x128 --json");
  ASSERT_EQ(wide.exit_code, 0) << wide.err;
  const nlohmann::json report = wide.json();
  EXPECT_EQ(report["resolution"], 512);
  EXPECT_EQ(report["height"], 128);
  EXPECT_NEAR(report["l2_stretch"].get<double>(), 1.0, 1e-9);
  for (const nlohmann::json& chart : report["per_chart"]) {
    EXPECT_LE(chart["texel_box"]["max"][0].get<double>(), 512.0);
    EXPECT_LE(chart["texel_box"]["max"][1].get<double>(), 128.0);
  }
  EXPECT_NE(read_text(file("wide.obj")).find("# xatlas_atlas 512 128 1\n"), std::string::npos);
  EXPECT_EQ(run("atlas cube.obj square.obj --json").json()["height"], 1024);
  for (const char* bad : {"512x", "x128", "512x8", "512y128", "0"}) {
    const Outcome refused = run(std::string("atlas cube.obj bad.obj --resolution ") + bad);
    EXPECT_EQ(refused.exit_code, 1) << bad << ": " << refused.err;
    EXPECT_NE(refused.err.find("WxH"), std::string::npos) << refused.err;
  }
  EXPECT_FALSE(fs::exists(file("bad.obj")));
  fs::create_directories(file("models"));
  write_mesh(file("models/cube.obj"), testing::grid_cube(4));
  ASSERT_EQ(run("batch models --out out --resolution 512x128").exit_code, 0);
  EXPECT_NE(read_text(file("out/cube.obj")).find("# xatlas_atlas 512 128 1\n"), std::string::npos);
}

// --repack keeps an OBJ's own UV charts and packs them: a unit square textured in a corner of UV
// space and a 1 x 2 rectangle textured in a far tile come out as two charts at one density (the
// rectangle twice as many texels high as the square), the corners that shared a `vt` share one.
// An OBJ without texture coordinates, or one face without, is refused (exit 2, one line), and so
// are the options that would change the charts (exit 1); nothing is written.
TEST_F(Cli, AtlasRepackKeepsTheFilesChartsAtOneDensity) {
  std::ofstream(file("textured.obj")) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                         "v 2 0 0\nv 3 0 0\nv 3 2 0\nv 2 2 0\n"
                                         "vt 0 0\nvt 0.5 0\nvt 0.5 0.5\nvt 0 0.5\n"
                                         "vt 3 3\nvt 3.25 3\nvt 3.25 3.5\nvt 3 3.5\n"
                                         "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 5/5 6/6 7/7\nf 5/5 7/7 8/8\n";
  const Outcome repacked = run("atlas textured.obj repacked.obj --repack --json");
  ASSERT_EQ(repacked.exit_code, 0) << repacked.err;
  const nlohmann::json report = repacked.json();
  EXPECT_EQ(report["repack"], true);
  EXPECT_EQ(report["charts"], 2);
  const auto& charts = report["per_chart"];
  ASSERT_EQ(charts.size(), 2u);
  // Each chart's longer side in texels: the square's 1 unit and the rectangle's 2 at one density.
  const auto longer_side = [](const nlohmann::json& chart) {
    const auto& box = chart["texel_box"];
    return std::max(box["max"][0].get<double>() - box["min"][0].get<double>(),
                    box["max"][1].get<double>() - box["min"][1].get<double>());
  };
  const double first = longer_side(charts[0]), second = longer_side(charts[1]);
  EXPECT_NEAR(std::max(first, second) / std::min(first, second), 2.0, 1e-9);
  const ObjContents obj = parse_obj(file("repacked.obj"));
  ASSERT_EQ(obj.uv_faces.size(), 4u);
  EXPECT_EQ(obj.uvs[obj.uv_faces[0][0]], obj.uvs[obj.uv_faces[1][0]]);
  EXPECT_EQ(obj.uvs[obj.uv_faces[0][2]], obj.uvs[obj.uv_faces[1][1]]);

  std::ofstream(file("bare.obj")) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n";
  const Outcome bare = run("atlas bare.obj bare-out.obj --repack");
  EXPECT_EQ(bare.exit_code, 2) << bare.err;
  expect_one_line_reason(bare);
  EXPECT_FALSE(fs::exists(file("bare-out.obj")));
  std::ofstream(file("partly.obj")) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                       "f 1/1 2/2 3/3\nf 1 3 4\n";
  const Outcome partly = run("atlas partly.obj partly-out.obj --repack");
  EXPECT_EQ(partly.exit_code, 2) << partly.err;
  EXPECT_NE(partly.err.find("triangle 1"), std::string::npos) << partly.err;
  EXPECT_FALSE(fs::exists(file("partly-out.obj")));
  // batch passes it on.
  fs::create_directories(file("assets"));
  fs::copy_file(file("textured.obj"), file("assets/textured.obj"));
  const Outcome batch = run("batch assets --out batch-out --repack --json");
  ASSERT_EQ(batch.exit_code, 0) << batch.err;
  EXPECT_EQ(read_batch_log(file("batch-out/batch-log.jsonl")).by_name.at("textured.obj")["quality"]["charts"], 2);
  EXPECT_EQ(run("batch assets --out batch-out2 --method lscm --repack").exit_code, 1);
  EXPECT_EQ(run("atlas textured.obj x.obj --repack --cleanup repair").exit_code, 1);
  EXPECT_EQ(run("atlas textured.obj x.glb --repack").exit_code, 1);
  EXPECT_FALSE(fs::exists(file("x.obj")));
}

// --repack of a glTF document keeps each primitive's TEXCOORD_0 charts and writes the repacked
// layout beside them (TEXCOORD_1 by default): TEXCOORD_0 comes back unchanged, and as the source
// layout was an atlas at one density already, every edge of the new set is the same multiple of
// its length in the source set. A document without TEXCOORD_0 is refused naming the primitive.
TEST_F(Cli, AtlasRepackOfAGltfDocumentAddsASetBesideTheTextureSet) {
  write_mesh(file("sphere.obj"), unit_sphere(2));
  ASSERT_EQ(run("atlas sphere.obj textured.glb").exit_code, 0);
  const Outcome repacked = run("atlas textured.glb repacked.glb --repack --json");
  ASSERT_EQ(repacked.exit_code, 0) << repacked.err;
  const GltfDocument source = GltfDocument::read(file("textured.glb"));
  const GltfDocument result = GltfDocument::read(file("repacked.glb"));
  ASSERT_EQ(result.texcoord_sets(0, 0), 2);
  const GltfTriangles source_triangles = source.mesh_triangles(0), result_triangles = result.mesh_triangles(0);
  const Eigen::Matrix<double, Eigen::Dynamic, 6> before = corner_texcoords(source, source_triangles, 0);
  EXPECT_EQ(corner_texcoords(result, result_triangles, 0), before);
  const Eigen::Matrix<double, Eigen::Dynamic, 6> after = corner_texcoords(result, result_triangles, 1);
  ASSERT_EQ(after.rows(), before.rows());
  // Coordinates in [0, 1] stored as float32 (relative rounding 2^-24 at each of an edge's two
  // ends, in both sets): on edges at least 1/100 long, a ratio within 4 * 2^-24 * 100 of another.
  double first_ratio = 0.0;
  for (Eigen::Index f = 0; f < before.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int next = (k + 1) % 3;
      const double old_length = std::hypot(before(f, 2 * next) - before(f, 2 * k), before(f, 2 * next + 1) - before(f, 2 * k + 1));
      const double new_length = std::hypot(after(f, 2 * next) - after(f, 2 * k), after(f, 2 * next + 1) - after(f, 2 * k + 1));
      if (old_length < 0.01) continue;
      if (first_ratio == 0.0) first_ratio = new_length / old_length;
      EXPECT_NEAR(new_length / old_length / first_ratio, 1.0, 4 * 0x1p-24 * 100) << "face " << f << " edge " << k;
    }
  }
  EXPECT_GT(first_ratio, 0.0);
  write_mesh(file("bare.glb"), unit_sphere(1));
  const Outcome bare = run("atlas bare.glb bare-out.glb --repack");
  EXPECT_EQ(bare.exit_code, 2) << bare.err;
  EXPECT_NE(bare.err.find("meshes[0].primitives[0]"), std::string::npos) << bare.err;
  EXPECT_FALSE(fs::exists(file("bare-out.glb")));
}

// Asked for the device where there is none (the Vulkan loader pointed at a driver that does not
// exist), the atlas is refused as every other command refuses: exit 5, one line, nothing written.
TEST_F(Cli, AtlasOnAVulkanBackendWithoutADeviceIsRefused) {
  write_mesh(file("sphere.obj"), unit_sphere(1));
  const std::string no_driver =
      "VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json";
  const Outcome refused = run("atlas sphere.obj atlas.obj --backend vulkan", no_driver);
  EXPECT_EQ(refused.exit_code, 5) << refused.err;
  expect_one_line_reason(refused);
  EXPECT_NE(refused.err.find("Vulkan"), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(file("atlas.obj")));
  // Left to choose, it runs on the CPU and says why.
  const Outcome automatic = run("atlas sphere.obj atlas.obj --json", no_driver);
  ASSERT_EQ(automatic.exit_code, 0) << automatic.err;
  EXPECT_EQ(automatic.json()["backend"], "cpu");
  EXPECT_NE(automatic.json()["backend_notice"].get<std::string>(), "");
}

}  // namespace
}  // namespace harmonia
