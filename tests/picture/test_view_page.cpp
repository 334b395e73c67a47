// The view page (harmonia/view_page.h): its data read back out of the HTML and decoded here,
// independently of the writer, and checked against hand-made layouts whose charts, turned-over
// triangles and distortions are known: the squares of a unit cube's net laid out without
// distortion, one of them mirrored, and a second layout scaled by 2 along u. Then the page's own
// parts (three.js, the script, no address to fetch) and the refusals. What the page draws in a
// browser is tests/picture/test_view_page_browser.py's.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harmonia/types.h"
#include "harmonia/view_page.h"
#include "support/test_support.h"
#include "support/view_page_data.h"

namespace harmonia {
namespace {

using Json = nlohmann::json;

constexpr double float_eps = std::numeric_limits<float>::epsilon();

using testing::view_page_data;

template <typename T>
std::vector<T> array_of(const Json& text) {
  return testing::view_page_array<T>(text);
}

// Three unit squares of a cube meeting at one corner (two triangles each), in 3D, and their net:
// squares A and B side by side sharing their UV edge (one chart), square C apart and mirrored (a
// second chart, turned over).
Mesh corner_of_a_cube() {
  Mesh mesh;
  mesh.vertices.resize(7, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,  // A: z = 0
      0, 0, 1, 1, 0, 1,                                 // B: y = 0 (with 0 and 1)
      0, 1, 1;                                          // C: x = 0 (with 0, 3, 4)
  mesh.faces.resize(6, 3);
  mesh.faces << 0, 2, 1, 0, 3, 2,  // A, facing -z
      0, 1, 5, 0, 5, 4,            // B, facing -y
      0, 4, 6, 0, 6, 3;            // C, facing -x
  return mesh;
}

ViewLayout corner_layout() {
  ViewLayout layout;
  layout.name = "corner </script> & co";  // the writer must escape this in both places
  layout.method = "by hand";
  layout.mesh3d = corner_of_a_cube();
  // A at [0,1]x[0,1], B beside it at [-1,0]x[0,1] sharing the edge 0-1, C apart at [2,3]x[0,1] and
  // mirrored; every square keeps its lengths.
  layout.uv.resize(10, 2);
  layout.uv << 0, 0, 0, 1, 1, 1, 1, 0,  // A: 0 -> (0,0), 1 -> (0,1), 2 -> (1,1), 3 -> (1,0)
      -1, 0, -1, 1,                     // B: 4 -> (-1,0), 5 -> (-1,1)
      3, 0, 2, 0, 2, 1, 3, 1;           // C mirrored: 0 -> (3,0), 4 -> (2,0), 6 -> (2,1), 3 -> (3,1)
  layout.uv_faces.resize(6, 3);
  layout.uv_faces << 0, 2, 1, 0, 3, 2,  // A
      0, 1, 5, 0, 5, 4,                 // B
      6, 7, 8, 6, 8, 9;                 // C: its corners run clockwise
  return layout;
}

TEST(ViewPage, ItsDataAreTheLayoutsChartsTurnedTrianglesAndDistortions) {
  testing::ScratchFolder scratch("view-page");
  const ViewLayout corner = corner_layout();
  ViewLayout stretched = corner;
  stretched.name = "stretched";
  stretched.uv.col(0) *= 2.0;  // every triangle 2 x 1: conformal distortion and stretch known
  ViewPageOptions options;
  options.title = "a cube's corner";
  options.headline = {{"charts", "2"}};
  write_view_page(scratch.file("page.html"), {corner, stretched}, options);
  const std::string page = testing::file_bytes(scratch.file("page.html"));
  const Json data = view_page_data(page);

  EXPECT_EQ(data["title"], "a cube's corner");
  EXPECT_EQ(data["headline"], Json::parse(R"([["charts", "2"]])"));
  ASSERT_EQ(data["results"].size(), 2u);
  const Json& first = data["results"][0];
  EXPECT_EQ(first["name"], corner.name);
  EXPECT_EQ(first["face_count"], 6);
  // Positions, faces, UVs and UV faces as given (floats of the doubles).
  const std::vector<float> positions = array_of<float>(first["positions"]);
  ASSERT_EQ(positions.size(), 21u);
  for (int v = 0; v < 7; ++v)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(positions[3 * v + k], static_cast<float>(corner.mesh3d.vertices(v, k)));
  const std::vector<std::uint32_t> faces = array_of<std::uint32_t>(first["faces"]);
  const std::vector<std::uint32_t> uv_faces = array_of<std::uint32_t>(first["uv_faces"]);
  const std::vector<float> uvs = array_of<float>(first["uvs"]);
  ASSERT_EQ(faces.size(), 18u);
  ASSERT_EQ(uv_faces.size(), 18u);
  ASSERT_EQ(uvs.size(), 20u);
  for (int f = 0; f < 6; ++f)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(faces[3 * f + k], static_cast<std::uint32_t>(corner.mesh3d.faces(f, k)));
      EXPECT_EQ(uv_faces[3 * f + k], static_cast<std::uint32_t>(corner.uv_faces(f, k)));
    }
  EXPECT_EQ(uvs[2 * 5 + 0], -1.0f);
  // Charts: A and B share UV vertices 0 and 1, C shares none with them.
  EXPECT_EQ(array_of<std::int32_t>(first["chart"]), (std::vector<std::int32_t>{0, 0, 0, 0, 1, 1}));
  ASSERT_EQ(first["charts"].size(), 2u);
  EXPECT_EQ(first["charts"][0]["faces"], 4);
  EXPECT_EQ(first["charts"][1]["faces"], 2);
  // Which triangles are turned over: C's two, laid out mirrored (signed areas by hand).
  const std::vector<std::uint8_t> turned = array_of<std::uint8_t>(first["flipped"]);
  std::vector<std::uint8_t> expected_turned;
  for (int f = 0; f < 6; ++f) {
    const Eigen::Vector2d a = corner.uv.row(corner.uv_faces(f, 0)), b = corner.uv.row(corner.uv_faces(f, 1)),
                          c = corner.uv.row(corner.uv_faces(f, 2));
    const double twice_area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    expected_turned.push_back(twice_area < 0.0 ? 1 : 0);
  }
  EXPECT_EQ(turned, expected_turned);
  EXPECT_EQ(std::count(turned.begin(), turned.end(), 1), 2);

  // The fields: every triangle of the net is an isometry (angle distortion 0, log area ratio 0,
  // stretch 1, up to float rounding of values of order 1); the layout scaled by 2 along u has
  // singular values 2 and 1 everywhere: after scaling to the 3D area, sqrt 2 and 1 / sqrt 2, so
  // its stretch is sqrt((1/2 + 2) / 2) = sqrt(5) / 2 and its log area ratio 0.
  const auto field = [](const Json& result, const std::string& key) {
    for (const Json& entry : result["fields"])
      if (entry["key"] == key) return array_of<float>(entry["values"]);
    ADD_FAILURE() << "no field " << key;
    return std::vector<float>{};
  };
  for (const float value : field(first, "angle")) EXPECT_NEAR(value, 0.0, 8 * float_eps);
  for (const float value : field(first, "area")) EXPECT_NEAR(value, 0.0, 8 * float_eps);
  for (const float value : field(first, "stretch")) EXPECT_NEAR(value, 1.0, 8 * float_eps);
  const Json& second = data["results"][1];
  for (const float value : field(second, "stretch")) EXPECT_NEAR(value, std::sqrt(5.0) / 2, 8 * float_eps);
  for (const float value : field(second, "area")) EXPECT_NEAR(value, 0.0, 8 * float_eps);
  // Each field's colour bar is the same on both layouts, from an isometry's value up.
  for (std::size_t k = 0; k < first["fields"].size(); ++k) {
    EXPECT_EQ(first["fields"][k]["low"], second["fields"][k]["low"]);
    EXPECT_EQ(first["fields"][k]["high"], second["fields"][k]["high"]);
  }
  for (const Json& entry : second["fields"]) {
    if (entry["key"] == "stretch") {
      EXPECT_EQ(entry["low"], 1.0);
      EXPECT_NEAR(entry["high"].get<double>(), std::sqrt(5.0) / 2, 1e-3);  // 4 significant digits
    }
    if (entry["key"] == "area") {
      EXPECT_EQ(entry["low"].get<double>(), -entry["high"].get<double>());
    }
  }
}

TEST(ViewPage, ThePageHoldsItsScriptsAndFetchesNothing) {
  testing::ScratchFolder scratch("view-page");
  write_view_page(scratch.file("page.html"), {corner_layout()}, {.title = "<b>bold</b>"});
  const std::string page = testing::file_bytes(scratch.file("page.html"));
  // three.js (its revision constant), the orbit controls, the page's script, the title escaped.
  EXPECT_NE(page.find("REVISION=\"111\""), std::string::npos);
  EXPECT_NE(page.find("OrbitControls"), std::string::npos);
  EXPECT_NE(page.find("harmoniaView"), std::string::npos);
  const std::size_t title = page.find("<title>");
  EXPECT_NE(title, std::string::npos);
  EXPECT_EQ(page.find("&lt;b&gt;bold&lt;/b&gt;"), page.find_first_not_of(" \n", title + 7));
  EXPECT_EQ(page.find("HARMONIA_"), std::string::npos);  // every placeholder filled
  // The name with "</script>" in it did not end the data element early.
  EXPECT_EQ(view_page_data(page)["results"][0]["name"], "corner </script> & co");
  // Nothing loaded from elsewhere: no script from a file or an address, every link a data URI.
  EXPECT_EQ(page.find("<script src"), std::string::npos);
  for (std::size_t at = page.find("<link"); at != std::string::npos; at = page.find("<link", at + 1)) {
    const std::size_t href = page.find("href=\"", at);
    ASSERT_NE(href, std::string::npos);
    EXPECT_EQ(page.compare(href + 6, 5, "data:"), 0) << page.substr(at, 60);
  }
}

TEST(ViewPage, RefusesWhatItCannotShowAndWritesNothing) {
  testing::ScratchFolder scratch("view-page");
  const auto status_of = [&](const std::filesystem::path& path, const std::vector<ViewLayout>& layouts) {
    try {
      write_view_page(path, layouts);
    } catch (const Error& error) {
      return error.status();
    }
    return Status::ok;
  };
  EXPECT_EQ(status_of(scratch.file("none.html"), {}), Status::invalid_input);
  ViewLayout short_layout = corner_layout();
  short_layout.uv_faces.conservativeResize(5, 3);
  EXPECT_EQ(status_of(scratch.file("short.html"), {short_layout}), Status::invalid_input);
  ViewLayout out_of_range = corner_layout();
  out_of_range.uv_faces(2, 1) = 10;
  EXPECT_EQ(status_of(scratch.file("range.html"), {out_of_range}), Status::invalid_input);
  EXPECT_EQ(status_of(scratch.file("page.png"), {corner_layout()}), Status::io_error);
  EXPECT_EQ(status_of(scratch.file("missing") / "page.html", {corner_layout()}), Status::io_error);
  EXPECT_TRUE(std::filesystem::is_empty(scratch.path()));
}

TEST(ViewPage, AnEmptyLayoutMakesAPageWithNoFaces) {
  testing::ScratchFolder scratch("view-page");
  ViewLayout empty;
  empty.name = "empty";
  empty.mesh3d.vertices.resize(0, 3);
  empty.mesh3d.faces.resize(0, 3);
  empty.uv.resize(0, 2);
  empty.uv_faces.resize(0, 3);
  write_view_page(scratch.file("empty.html"), {empty});
  const Json data = view_page_data(testing::file_bytes(scratch.file("empty.html")));
  EXPECT_EQ(data["results"][0]["face_count"], 0);
  EXPECT_EQ(data["results"][0]["charts"].size(), 0u);
}

}  // namespace
}  // namespace harmonia
