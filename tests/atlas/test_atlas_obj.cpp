// The texture atlas writer (harmonia/atlas_io.h): what it writes reads back as the same mesh, UVs
// and charts; UVs are shared within a chart and only there; it refuses atlases that do not fit
// the mesh; and the evaluator the library is judged by (atlaseval.py, beside the checkout in
// ../shared/tools, run when python3 is there) reads the file and agrees with the library's own
// measure of the atlas (host/atlas/atlas_metrics.h).

#include "harmonia/atlas_io.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "atlas/atlas_metrics.h"
#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;

// Each figure is a handful of roundings per triangle, then a weighted mean: far below this.
constexpr double kTolerance = 64 * std::numeric_limits<double>::epsilon();
// atlaseval.py prints its figures with 6 significant digits: at most half a unit of the sixth.
constexpr double kPrintedRelativePrecision = 5e-6;

struct MeshWithAtlas {
  Mesh mesh;
  TextureAtlas atlas;
};

// The planar unit disk (z = 0) cut at x = 0 into two charts by the faces' centroids; the charts
// alternate along each ring, so the file needs many `g` lines. Each chart is drawn as its own
// piece of the plane scaled by 0.2 (an isometry up to scale, counter-clockwise): chart 0 (x < 0)
// at u = 0.25 + 0.2 x, chart 1 at u = 0.5 + 0.2 x, apart by more than a texel at 64^2.
MeshWithAtlas two_chart_disk() {
  MeshWithAtlas built;
  built.mesh = planar_disk(6, 0.1);
  const Eigen::Index face_count = built.mesh.faces.rows();
  built.atlas.resolution = 64;
  built.atlas.charts.resize(2);
  built.atlas.corner_uv.resize(face_count, 6);
  for (Eigen::Index f = 0; f < face_count; ++f) {
    double centroid_x = 0.0;
    for (int k = 0; k < 3; ++k) centroid_x += built.mesh.vertices(built.mesh.faces(f, k), 0) / 3.0;
    const int chart = centroid_x < 0.0 ? 0 : 1;
    built.atlas.chart_of_face.push_back(chart);
    built.atlas.charts[static_cast<std::size_t>(chart)].faces.push_back(static_cast<int>(f));
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = built.mesh.vertices.row(built.mesh.faces(f, k));
      built.atlas.corner_uv(f, 2 * k) = (chart == 0 ? 0.25 : 0.5) + 0.2 * p.x();
      built.atlas.corner_uv(f, 2 * k + 1) = 0.5 + 0.2 * p.y();
    }
  }
  return built;
}

// What a written atlas reads back as: the textured mesh, and the chart of each face from the
// `g chart_N` lines before it.
struct ReadAtlas {
  TexturedMesh textured;
  std::vector<int> chart_of_face;
  std::string text;
};

ReadAtlas read_back(const fs::path& path) {
  ReadAtlas read;
  read.textured = read_textured_obj(path);
  read.text = testing::file_bytes(path);
  std::istringstream lines(read.text);
  int chart = -2;  // no g line seen yet
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("g chart_", 0) == 0) chart = std::stoi(line.substr(8));
    if (line.rfind("f ", 0) == 0) read.chart_of_face.push_back(chart);
  }
  return read;
}

// ------------------------------------------------------------------------------ the file

TEST(AtlasObj, WhatIsWrittenReadsBackAsTheSameMeshUvsAndCharts) {
  const testing::ScratchFolder folder("atlas-obj");
  const MeshWithAtlas built = two_chart_disk();
  write_atlas_obj(folder.file("atlas.obj"), built.mesh, built.atlas);
  const ReadAtlas read = read_back(folder.file("atlas.obj"));

  // Positions exactly (shortest round-trip printing), faces in input order with their corners.
  EXPECT_EQ(read.textured.mesh.vertices, built.mesh.vertices);
  EXPECT_EQ(read.textured.mesh.faces, built.mesh.faces);
  EXPECT_EQ(read.chart_of_face, built.atlas.chart_of_face);
  ASSERT_EQ(read.textured.uv_faces.rows(), built.mesh.faces.rows());
  for (Eigen::Index f = 0; f < built.mesh.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVector2d uv = read.textured.uv.row(read.textured.uv_faces(f, k));
      EXPECT_EQ(uv.x(), built.atlas.corner_uv(f, 2 * k)) << "face " << f << " corner " << k;
      EXPECT_EQ(uv.y(), built.atlas.corner_uv(f, 2 * k + 1)) << "face " << f << " corner " << k;
    }
  }
  EXPECT_EQ(read.text.rfind("# harmonia texture atlas\n# 2 charts, 64 x 64 texels\n", 0), 0u);
  EXPECT_NE(read.text.find("\n# xatlas_atlas 64 64 1\n"), std::string::npos);
  // A g line only where the chart changes from the previous face.
  int changes = 1;
  for (std::size_t f = 1; f < built.atlas.chart_of_face.size(); ++f) {
    changes += built.atlas.chart_of_face[f] != built.atlas.chart_of_face[f - 1] ? 1 : 0;
  }
  EXPECT_EQ(testing::count_occurrences(read.text, "\ng chart_"), changes);
  EXPECT_GT(changes, 2);
}

TEST(AtlasObj, FacesOfAChartShareTheirVertexUvsAndChartsDoNot) {
  const testing::ScratchFolder folder("atlas-obj");
  const MeshWithAtlas built = two_chart_disk();
  write_atlas_obj(folder.file("atlas.obj"), built.mesh, built.atlas);
  const ReadAtlas read = read_back(folder.file("atlas.obj"));
  // One vt per (chart, vertex): the disk's vertices, plus a second one where both charts meet.
  std::vector<std::vector<int>> vt_of_vertex_in_chart(
      2, std::vector<int>(static_cast<std::size_t>(built.mesh.vertex_count()), -1));
  int seam_vertices = 0;
  std::vector<int> charts_at_vertex(static_cast<std::size_t>(built.mesh.vertex_count()), 0);
  for (Eigen::Index f = 0; f < built.mesh.faces.rows(); ++f) {
    const int chart = built.atlas.chart_of_face[static_cast<std::size_t>(f)];
    for (int k = 0; k < 3; ++k) {
      const auto vertex = static_cast<std::size_t>(built.mesh.faces(f, k));
      int& vt = vt_of_vertex_in_chart[static_cast<std::size_t>(chart)][vertex];
      if (vt < 0) {
        vt = read.textured.uv_faces(f, k);
        if (++charts_at_vertex[vertex] == 2) ++seam_vertices;
      }
      EXPECT_EQ(read.textured.uv_faces(f, k), vt) << "face " << f << " corner " << k;
    }
  }
  EXPECT_GT(seam_vertices, 0);
  EXPECT_EQ(read.textured.uv.rows(), built.mesh.vertex_count() + seam_vertices);
}

TEST(AtlasObj, AnAtlasThatDoesNotFitTheMeshIsRefusedBeforeAnythingIsWritten) {
  const testing::ScratchFolder folder("atlas-obj");
  const MeshWithAtlas good = two_chart_disk();
  auto status_of = [&](auto change) {
    MeshWithAtlas bad = good;
    change(bad);
    try {
      write_atlas_obj(folder.file("bad.obj"), bad.mesh, bad.atlas);
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("bad.obj"), std::string::npos) << error.what();
      return error.status();
    }
    return Status::ok;
  };
  EXPECT_EQ(status_of([](MeshWithAtlas& b) { b.atlas.chart_of_face.pop_back(); }),
            Status::invalid_input);
  EXPECT_EQ(status_of([](MeshWithAtlas& b) { b.atlas.corner_uv.conservativeResize(3, 6); }),
            Status::invalid_input);
  EXPECT_EQ(status_of([](MeshWithAtlas& b) { b.atlas.chart_of_face[0] = 2; }),
            Status::invalid_input);
  EXPECT_EQ(status_of([](MeshWithAtlas& b) { b.atlas.corner_uv(5, 3) = NAN; }),
            Status::invalid_input);
  EXPECT_EQ(status_of([](MeshWithAtlas& b) { b.mesh.vertices(2, 1) = INFINITY; }),
            Status::invalid_input);
  EXPECT_FALSE(fs::exists(folder.file("bad.obj")));
  EXPECT_EQ(status_of([&](MeshWithAtlas&) {}), Status::ok);  // the unchanged atlas is written
  try {
    write_atlas_obj(folder.file("no-such-folder/atlas.obj"), good.mesh, good.atlas);
    ADD_FAILURE() << "an atlas was written into a missing folder";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::io_error);
  }
}

// ------------------------------------------------------------------------------ atlaseval.py

// atlaseval.py's report on `mesh` and its written `atlas`, or nothing (the test is then skipped)
// when python3 or the script is not there.
std::optional<nlohmann::json> atlaseval(const testing::ScratchFolder& folder,
                                        const MeshWithAtlas& built) {
  const fs::path script = testing::shared_data_dir() / ".." / "tools" / "atlaseval.py";
  if (!fs::exists(script) || std::system("python3 -c '' >/dev/null 2>&1") != 0) return {};
  write_mesh(folder.file("mesh.obj"), built.mesh);
  write_atlas_obj(folder.file("atlas.obj"), built.mesh, built.atlas);
  const std::string command = "python3 '" + script.string() + "' '" +
                              folder.file("mesh.obj").string() + "' '" +
                              folder.file("atlas.obj").string() + "' > '" +
                              folder.file("report.json").string() + "'";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return nlohmann::json::parse(testing::file_bytes(folder.file("report.json")));
}

TEST(AtlasObj, AtlasevalFindsAValidAtlasInTheWrittenFile) {
  const testing::ScratchFolder folder("atlas-obj");
  const MeshWithAtlas built = two_chart_disk();
  const std::optional<nlohmann::json> report = atlaseval(folder, built);
  if (!report) HARMONIA_SKIP_WITHOUT_CORPUS("python3 or ../shared/tools/atlaseval.py is not available");
  EXPECT_EQ((*report)["F"], built.mesh.face_count());
  EXPECT_EQ((*report)["face_index_mismatch"], 0);
  EXPECT_EQ((*report)["atlas_size"], nlohmann::json::array({64, 64}));
  EXPECT_EQ((*report)["charts"], 2);
  EXPECT_EQ((*report)["flipped"], 0);
  EXPECT_EQ((*report)["overlap_texels"], 0);
  EXPECT_EQ((*report)["boundary_crossings"]["between_charts"], 0);
  EXPECT_EQ((*report)["boundary_crossings"]["within_chart"], 0);
  EXPECT_EQ((*report)["valid"], true);
}

// The disk's two charts drawn over each other, each on a page of its own: the file names each
// chart's page (g chart_N_aP) and the page count, and atlaseval.py finds two atlases, no overlap
// and the coverage over both pages that the library measures.
TEST(AtlasObj, AtlasevalReadsThePagesOfTheWrittenFile) {
  MeshWithAtlas built = two_chart_disk();
  for (Eigen::Index f = 0; f < built.mesh.faces.rows(); ++f)
    if (built.atlas.chart_of_face[static_cast<std::size_t>(f)] == 1)
      for (int k = 0; k < 3; ++k) built.atlas.corner_uv(f, 2 * k) -= 0.35;  // over chart 0
  EXPECT_GT(detail::measure_atlas(built.mesh, built.atlas).overlapping_texels, 0);  // on one page
  built.atlas.pages = 2;
  built.atlas.charts[1].page = 1;
  const testing::ScratchFolder folder("atlas-obj");
  const std::optional<nlohmann::json> report = atlaseval(folder, built);
  if (!report) HARMONIA_SKIP_WITHOUT_CORPUS("python3 or ../shared/tools/atlaseval.py is not available");
  const std::string text = testing::file_bytes(folder.file("atlas.obj"));
  EXPECT_NE(text.find("# xatlas_atlas 64 64 2\n"), std::string::npos);
  EXPECT_NE(text.find("g chart_1_a1\n"), std::string::npos);
  EXPECT_NE(text.find("g chart_0_a0\n"), std::string::npos);
  const AtlasMetrics metrics = detail::measure_atlas(built.mesh, built.atlas);
  EXPECT_EQ((*report)["atlases"], 2);
  EXPECT_EQ((*report)["overlap_texels"], 0);
  EXPECT_EQ(metrics.overlapping_texels, 0);
  EXPECT_EQ((*report)["boundary_crossings"]["between_charts"], 0);
  EXPECT_EQ(metrics.boundary_crossings, 0);
  EXPECT_EQ((*report)["valid"], true);
  EXPECT_NEAR((*report)["coverage"].get<double>(), metrics.coverage,
              kPrintedRelativePrecision * metrics.coverage + kTolerance);
}

TEST(AtlasObj, AtlasevalAndTheLibraryMeasureTheSameFigures) {
  // The disk's atlas spoiled on purpose: chart 0 mirrored (u reversed), chart 1 squeezed in v
  // (0.15 instead of 0.2) and moved over chart 0, one of its faces turned clockwise.
  MeshWithAtlas built = two_chart_disk();
  for (Eigen::Index f = 0; f < built.mesh.faces.rows(); ++f) {
    const int chart = built.atlas.chart_of_face[static_cast<std::size_t>(f)];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = built.mesh.vertices.row(built.mesh.faces(f, k));
      built.atlas.corner_uv(f, 2 * k) = chart == 0 ? 0.05 - 0.2 * p.x() : 0.15 + 0.2 * p.x();
      built.atlas.corner_uv(f, 2 * k + 1) = 0.5 + (chart == 0 ? 0.2 : 0.15) * p.y();
    }
  }
  const int turned = built.atlas.charts[1].faces[3];
  for (int axis = 0; axis < 2; ++axis) {
    std::swap(built.atlas.corner_uv(turned, 2 + axis), built.atlas.corner_uv(turned, 4 + axis));
  }

  const testing::ScratchFolder folder("atlas-obj");
  const std::optional<nlohmann::json> report = atlaseval(folder, built);
  if (!report) HARMONIA_SKIP_WITHOUT_CORPUS("python3 or ../shared/tools/atlaseval.py is not available");
  const AtlasMetrics metrics = detail::measure_atlas(built.mesh, built.atlas);
  EXPECT_EQ((*report)["flipped"], metrics.flipped_triangles);
  EXPECT_EQ(metrics.flipped_triangles, 1);
  EXPECT_EQ((*report)["mirrored_charts"], metrics.mirrored_charts);
  EXPECT_EQ(metrics.mirrored_charts, 1);
  EXPECT_EQ((*report)["overlap_texels"], metrics.overlapping_texels);
  EXPECT_GT(metrics.overlapping_texels, 0);
  const nlohmann::json& crossings = (*report)["boundary_crossings"];
  EXPECT_EQ(crossings["between_charts"].get<int>() + crossings["within_chart"].get<int>(),
            metrics.boundary_crossings);
  EXPECT_GT(metrics.boundary_crossings, 0);

  auto expect_printed = [](const nlohmann::json& printed, double measured, const char* what) {
    EXPECT_NEAR(printed.get<double>(), measured,
                kPrintedRelativePrecision * std::abs(measured) + kTolerance)
        << what;
  };
  expect_printed((*report)["coverage"], metrics.coverage, "coverage");
  expect_printed((*report)["stretch"]["L2"], metrics.l2_stretch, "stretch");
  expect_printed((*report)["conformal"]["mean"], metrics.angle_distortion, "conformal");
  expect_printed((*report)["area_global"]["mean_abs_log"], metrics.area_distortion,
                 "area_global");
  // atlaseval's per-chart area figure over the whole atlas: the charts' means weighted by their
  // 3D areas (every triangle of this atlas is measured).
  double weighted_area = 0.0, total_area = 0.0;
  for (const AtlasChart& chart : built.atlas.charts) {
    weighted_area += chart.surface_area * chart.area_distortion;
    total_area += chart.surface_area;
  }
  expect_printed((*report)["area"]["mean_abs_log"], weighted_area / total_area, "area");
  EXPECT_GT(metrics.l2_stretch, 1.0);
}

// A non-square atlas (64 x 32 texels): the disk's charts drawn isometric in texels (spread twice
// as far in v as in u, the atlas being half as high), which the file's size line tells atlaseval.py. Both
// measure the same figures, and an isometry's: no stretch, no angle distortion.
TEST(AtlasObj, AtlasevalMeasuresANonSquareAtlasAsTheLibraryDoes) {
  MeshWithAtlas built = two_chart_disk();
  built.atlas.height = 32;
  for (Eigen::Index f = 0; f < built.mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) built.atlas.corner_uv(f, 2 * k + 1) = 0.5 + 2.0 * (built.atlas.corner_uv(f, 2 * k + 1) - 0.5);
  const testing::ScratchFolder folder("atlas-obj");
  const std::optional<nlohmann::json> report = atlaseval(folder, built);
  if (!report) HARMONIA_SKIP_WITHOUT_CORPUS("python3 or ../shared/tools/atlaseval.py is not available");
  EXPECT_EQ((*report)["atlas_size"], nlohmann::json::array({64, 32}));
  const AtlasMetrics metrics = detail::measure_atlas(built.mesh, built.atlas);
  EXPECT_NEAR(metrics.l2_stretch, 1.0, kTolerance);
  EXPECT_NEAR(metrics.angle_distortion, 1.0, kTolerance);
  EXPECT_EQ((*report)["overlap_texels"], metrics.overlapping_texels);
  EXPECT_EQ((*report)["valid"], true);
  for (const auto& [printed, measured] : {std::pair{(*report)["coverage"], metrics.coverage},
                                          std::pair{(*report)["stretch"]["L2"], metrics.l2_stretch},
                                          std::pair{(*report)["conformal"]["mean"], metrics.angle_distortion}})
    EXPECT_NEAR(printed.get<double>(), measured, kPrintedRelativePrecision * std::abs(measured) + kTolerance);
}

}  // namespace
}  // namespace harmonia
