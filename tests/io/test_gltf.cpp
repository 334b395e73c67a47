// glTF 2.0 reading and writing on small hand-made documents whose triangles are known: byte
// strides, normalized integers, sparse accessors, strips and fans, the node hierarchy with a
// mirroring transform, files without a scene, refusals that name the JSON path, and the writer's
// round trips (a mesh written and read back; an update's new vertices carrying every attribute).
// The real assets and the Khronos validator are exercised by tests/io/test_gltf_files.py.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harmonia/gltf.h"
#include "harmonia/io.h"
#include "harmonia/types.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

using nlohmann::json;

// Little-endian bytes of values of one type, appended to a buffer.
template <typename T>
void put(std::string& bytes, std::initializer_list<T> values) {
  for (const T value : values) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    bytes.append(raw, sizeof(T));
  }
}

std::string base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t chunk = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) chunk |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) chunk |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += kAlphabet[(chunk >> 18) & 63];
    out += kAlphabet[(chunk >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(chunk >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[chunk & 63] : '=';
  }
  return out;
}

// A document whose one buffer is `bytes`, as a data URI.
json document_with(const std::string& bytes) {
  return {{"asset", {{"version", "2.0"}}},
          {"buffers", json::array({{{"byteLength", bytes.size()},
                                    {"uri", "data:application/octet-stream;base64," + base64(bytes)}}})}};
}

GltfDocument parse(const json& document) {
  return GltfDocument::parse(document.dump(), "test.gltf", {});
}

// A unit square as a strip (0,1,2,3) and a fan over the same corners, positions with a byte stride
// of 16 (a float of padding after each), one mesh placed by two nodes: one as it is and one
// translated by (10, 0, 0) and mirrored in x (scale -1, 1, 1).
json strip_and_fan_document() {
  std::string bytes;
  // Positions, stride 16: (0,0,0) (1,0,0) (0,1,0) (1,1,0).
  put<float>(bytes, {0, 0, 0, 99, 1, 0, 0, 99, 0, 1, 0, 99, 1, 1, 0, 99});
  put<std::uint16_t>(bytes, {0, 1, 2, 3});  // Strip order.
  put<std::uint16_t>(bytes, {0, 1, 3, 2});  // Fan order.
  json document = document_with(bytes);
  document["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", 64}, {"byteStride", 16}},
                                         {{"buffer", 0}, {"byteOffset", 64}, {"byteLength", 16}}});
  document["accessors"] = json::array(
      {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
        {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
       {{"bufferView", 1}, {"componentType", 5123}, {"count", 4}, {"type", "SCALAR"}},
       {{"bufferView", 1}, {"byteOffset", 8}, {"componentType", 5123}, {"count", 4}, {"type", "SCALAR"}}});
  document["meshes"] = json::array({{{"primitives", json::array({
      {{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"mode", 5}},
      {{"attributes", {{"POSITION", 0}}}, {"indices", 2}, {"mode", 6}},
  })}}});
  document["nodes"] = json::array({{{"mesh", 0}},
                                   {{"children", {2}}, {"translation", {10, 0, 0}}},
                                   {{"mesh", 0}, {"scale", {-1, 1, 1}}}});
  document["scenes"] = json::array({{{"nodes", {0, 1}}}});
  document["scene"] = 0;
  return document;
}

// The normal of face `face` of `mesh` (not normalized).
Eigen::Vector3d normal_of(const Mesh& mesh, int face) {
  const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(face, 0));
  const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(face, 1));
  const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(face, 2));
  return (b - a).cross(c - a);
}

TEST(Gltf, StripsAndFansBecomeTrianglesFacingOneWayPlacedByEveryNode) {
  const GltfTriangles triangles = parse(strip_and_fan_document()).scene_triangles();
  // Two instances x (strip of 2 triangles + fan of 2 triangles); each part has its 4 vertices.
  ASSERT_EQ(triangles.mesh.face_count(), 8);
  ASSERT_EQ(triangles.mesh.vertex_count(), 16);
  ASSERT_EQ(triangles.parts.size(), 4u);
  // Every triangle of the unit square faces +z: the strip's second triangle is turned to keep the
  // winding, and the mirrored instance's triangles are turned back to face out.
  for (int face = 0; face < 8; ++face) {
    EXPECT_NEAR(normal_of(triangles.mesh, face).z(), 1.0, 1e-12) << "face " << face;
    EXPECT_NEAR(normal_of(triangles.mesh, face).head<2>().norm(), 0.0, 1e-12);
  }
  // The second instance: x -> 10 - x.
  const GltfPart& mirrored = triangles.parts[2];
  EXPECT_EQ(mirrored.node, 2);
  EXPECT_TRUE(mirrored.mirrored);
  EXPECT_EQ(triangles.mesh.vertices(mirrored.first_vertex + 1, 0), 9.0);
  EXPECT_EQ(triangles.mesh.vertices(mirrored.first_vertex + 3, 1), 1.0);
}

TEST(Gltf, SparseAccessorsAndNormalizedIntegersAreDecoded) {
  std::string bytes;
  // Positions as normalized unsigned shorts: (0,0,0) (65535,0,0) (0,65535,0).
  put<std::uint16_t>(bytes, {0, 0, 0, 65535, 0, 0, 0, 65535, 0});
  bytes.append(2, '\0');                  // To a 4-byte boundary (20 bytes).
  put<std::uint32_t>(bytes, {2});         // Sparse index: vertex 2.
  put<std::uint16_t>(bytes, {0, 32768, 65535});  // Its new value, (0, 0.5000076, 1).
  bytes.append(2, '\0');
  json document = document_with(bytes);
  document["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", 18}},
                                         {{"buffer", 0}, {"byteOffset", 20}, {"byteLength", 4}},
                                         {{"buffer", 0}, {"byteOffset", 24}, {"byteLength", 6}}});
  document["accessors"] = json::array({{{"bufferView", 0},
                                        {"componentType", 5123},
                                        {"normalized", true},
                                        {"count", 3},
                                        {"type", "VEC3"},
                                        {"sparse",
                                         {{"count", 1},
                                          {"indices", {{"bufferView", 1}, {"componentType", 5125}}},
                                          {"values", {{"bufferView", 2}}}}}}});
  document["meshes"] = json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}}})}}});
  const GltfTriangles triangles = parse(document).scene_triangles();  // No scene: meshes as they are.
  ASSERT_EQ(triangles.mesh.vertex_count(), 3);
  EXPECT_EQ(triangles.mesh.vertices(1, 0), 1.0);
  EXPECT_EQ(triangles.mesh.vertices(2, 1), 32768.0 / 65535.0);
  EXPECT_EQ(triangles.mesh.vertices(2, 2), 1.0);
  EXPECT_EQ(triangles.parts.front().node, -1);
}

TEST(Gltf, MalformedDocumentsAreRefusedWithTheJsonPath) {
  json document = strip_and_fan_document();
  document["accessors"][0]["count"] = 12;  // The view holds 4 elements of stride 16.
  try {
    (void)parse(document).scene_triangles();
    FAIL() << "an accessor longer than its view was accepted";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), Status::parse_error);
    EXPECT_NE(std::string(error.what()).find("meshes[0].primitives[0].attributes.POSITION: accessor 0 "
                                             "has 12 elements, buffer view 0 holds 4"),
              std::string::npos)
        << error.what();
  }
  json cyclic = strip_and_fan_document();
  cyclic["nodes"][2]["children"] = {1};
  EXPECT_THROW((void)parse(cyclic).scene_triangles(), Error);
  json bad_index = strip_and_fan_document();
  bad_index["meshes"][0]["primitives"][0]["indices"] = 9;
  try {
    (void)parse(bad_index).scene_triangles();
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("meshes[0].primitives[0].indices"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW((void)GltfDocument::parse("{\"asset\": {\"version\": \"1.0\"}}", "old.gltf", {}), Error);
  EXPECT_THROW((void)GltfDocument::parse("glTF\x02\0\0\0", "short.glb", {}), Error);
}

TEST(Gltf, AMeshWrittenAsGlbReadsBackWithItsFaces) {
  testing::ScratchFolder scratch("gltf");
  Mesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.5, 1;
  mesh.faces.resize(3, 3);
  mesh.faces << 0, 1, 2, 0, 2, 3, 1, 3, 2;
  for (const char* name : {"m.glb", "m.gltf"}) {
    write_mesh(scratch.file(name), mesh);
    const Mesh back = read_mesh(scratch.file(name));
    EXPECT_EQ(back.faces, mesh.faces) << name;
    EXPECT_EQ(back.vertices, mesh.vertices) << name;  // Every coordinate is a float.
  }
  EXPECT_TRUE(std::filesystem::exists(scratch.file("m.bin")));
}

TEST(Gltf, UpdatesSplitVerticesCarryingEveryAttribute) {
  testing::ScratchFolder scratch("gltf");
  // One triangle pair sharing an edge, with a COLOR_0 per vertex and an existing TEXCOORD_0.
  std::string bytes;
  put<float>(bytes, {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});              // POSITION
  put<std::uint8_t>(bytes, {10, 11, 12, 255, 20, 21, 22, 255, 30, 31, 32, 255, 40, 41, 42, 255});  // COLOR_0
  put<float>(bytes, {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f});  // TEXCOORD_0
  put<std::uint8_t>(bytes, {0, 1, 2, 2, 1, 3});                           // indices (bytes)
  json document = document_with(bytes);
  document["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", 48}},
                                         {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 16}},
                                         {{"buffer", 0}, {"byteOffset", 64}, {"byteLength", 32}},
                                         {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 6}}});
  document["accessors"] = json::array(
      {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
       {{"bufferView", 1}, {"componentType", 5121}, {"normalized", true}, {"count", 4}, {"type", "VEC4"}},
       {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
       {{"bufferView", 3}, {"componentType", 5121}, {"count", 6}, {"type", "SCALAR"}}});
  document["meshes"] = json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}, {"COLOR_0", 1}, {"TEXCOORD_0", 2}}}, {"indices", 3}}})}}});
  document["materials"] = json::array({{{"name", "kept"}, {"extras", {{"note", 7}}}}});
  document["meshes"][0]["primitives"][0]["material"] = 0;
  const GltfDocument source = parse(document);
  const GltfTriangles triangles = source.scene_triangles();
  // A layout with a seam along the shared edge: the second triangle is moved right by 2.
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv(2, 6);
  corner_uv << 0, 0, 1, 0, 0, 1,  //
      2, 1, 3, 0, 3, 1;
  const std::vector<GltfPrimitiveUpdate> updates = texcoord_updates(triangles, corner_uv, {0, 1});
  ASSERT_EQ(updates.size(), 1u);
  EXPECT_EQ(updates[0].source_vertex, (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3}));
  write_gltf(scratch.file("out.glb"), source, updates);
  EXPECT_THROW(write_gltf(scratch.file("bad.glb"), source, updates, {0, false}), Error);
  EXPECT_FALSE(std::filesystem::exists(scratch.file("bad.glb")));

  // Read back as raw JSON and bytes (not through the reader under test).
  const std::string glb = testing::file_bytes(scratch.file("out.glb"));
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  const json written = json::parse(glb.substr(20, json_length));
  const std::string binary = glb.substr(20 + json_length + 8);
  const json& primitive = written["meshes"][0]["primitives"][0];
  EXPECT_EQ(written["materials"], document["materials"]);
  EXPECT_EQ(primitive["material"], 0);
  ASSERT_TRUE(primitive["attributes"].contains("TEXCOORD_1"));
  ASSERT_TRUE(primitive["attributes"].contains("_CHART"));
  const auto bytes_of = [&](int accessor, int element, int size) {
    const json& a = written["accessors"][accessor];
    const json& view = written["bufferViews"][a["bufferView"].get<int>()];
    const int stride = view.value("byteStride", size);
    return binary.substr(view.value("byteOffset", 0) + a.value("byteOffset", 0) + element * stride, size);
  };
  const int color = primitive["attributes"]["COLOR_0"];
  const int uv0 = primitive["attributes"]["TEXCOORD_0"];
  const int uv1 = primitive["attributes"]["TEXCOORD_1"];
  EXPECT_EQ(written["accessors"][color]["count"], 6);
  EXPECT_EQ(written["accessors"][color]["normalized"], true);
  const std::vector<int> source_of = {0, 1, 2, 2, 1, 3};
  for (int vertex = 0; vertex < 6; ++vertex) {
    EXPECT_EQ(bytes_of(color, vertex, 4), bytes.substr(48 + 4 * source_of[vertex], 4)) << vertex;
    EXPECT_EQ(bytes_of(uv0, vertex, 8), bytes.substr(64 + 8 * source_of[vertex], 8)) << vertex;
  }
  // The new set in glTF's convention: v = 1 - v. Vertex 3 is (2, 1) -> (2, 0).
  float uv[2];
  std::memcpy(uv, bytes_of(uv1, 3, 8).data(), 8);
  EXPECT_EQ(uv[0], 2.0f);
  EXPECT_EQ(uv[1], 0.0f);
  // Six vertices still fit bytes: the indices keep the input's type.
  EXPECT_EQ(written["accessors"][primitive["indices"].get<int>()]["componentType"], 5121);

  // The same layout without its seam, the two triangles on two atlas pages: the shared vertices
  // are split by page all the same, and each vertex carries its page in `_PAGE`.
  corner_uv.row(1) << 0, 1, 1, 0, 1, 1;
  EXPECT_EQ(texcoord_updates(triangles, corner_uv, {0, 1})[0].source_vertex.size(), 6u);
  EXPECT_EQ(texcoord_updates(triangles, corner_uv, {0, 0})[0].source_vertex.size(), 4u);
  const std::vector<GltfPrimitiveUpdate> paged = texcoord_updates(triangles, corner_uv, {0, 0}, {0, 1});
  ASSERT_EQ(paged[0].source_vertex.size(), 6u);
  EXPECT_EQ(paged[0].page, (std::vector<int>{0, 0, 0, 1, 1, 1}));
  write_gltf(scratch.file("paged.glb"), source, paged);
  const std::string paged_glb = testing::file_bytes(scratch.file("paged.glb"));
  std::memcpy(&json_length, paged_glb.data() + 12, 4);
  const json paged_json = json::parse(paged_glb.substr(20, json_length));
  const json& paged_primitive = paged_json["meshes"][0]["primitives"][0];
  ASSERT_TRUE(paged_primitive["attributes"].contains("_PAGE"));
  const json& page_accessor = paged_json["accessors"][paged_primitive["attributes"]["_PAGE"].get<int>()];
  EXPECT_EQ(page_accessor["type"], "SCALAR");
  EXPECT_EQ(page_accessor["count"], 6);
  EXPECT_THROW((void)texcoord_updates(triangles, corner_uv, {0, 0}, {0}), Error);
}

TEST(Gltf, CompressedDocumentsAreWrittenBackPlainWithTheirTriangles) {
  // Seeds of the fuzz corpus encoded with Draco's and meshoptimizer's own encoders.
  testing::ScratchFolder scratch("gltf");
  const std::filesystem::path corpus = testing::assets_dir().parent_path() / "fuzz" / "corpus" / "gltf";
  for (const char* name : {"draco.gltf", "meshopt.gltf"}) {
    const GltfDocument source = GltfDocument::read(corpus / name);
    const GltfTriangles triangles = source.scene_triangles();
    ASSERT_GT(triangles.mesh.face_count(), 0) << name;
    write_gltf(scratch.file("plain.glb"), source, position_updates(triangles, triangles.mesh.vertices));
    const std::string glb = testing::file_bytes(scratch.file("plain.glb"));
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    const json written = json::parse(glb.substr(20, json_length));
    EXPECT_FALSE(written.contains("extensionsRequired")) << name << ": " << written.dump();
    const GltfTriangles back = GltfDocument::read(scratch.file("plain.glb")).scene_triangles();
    EXPECT_EQ(back.mesh.faces, triangles.mesh.faces) << name;
    // Positions go back through each node's inverse and forward again, as floats.
    const double size = triangles.mesh.vertices.cwiseAbs().maxCoeff();
    EXPECT_LT((back.mesh.vertices - triangles.mesh.vertices).cwiseAbs().maxCoeff(), 4 * 0x1p-24 * size) << name;
  }
}

}  // namespace
}  // namespace harmonia
