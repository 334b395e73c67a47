// Mesh input/output, good paths: every reader on small hand-made files whose arrays are known, the
// binary formats in both byte orders (written byte by byte here), exact round trips through every
// writer, atomic replacement, and a corpus mesh with known counts.
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;

fs::path asset(const std::string& name) { return testing::assets_dir() / "io" / name; }

// A fresh folder per test, removed afterwards.
class IoTest : public ::testing::Test {
 protected:
  fs::path file(const std::string& name) const { return scratch_.path() / name; }
  fs::path write_bytes(const std::string& name, const std::string& bytes) const {
    std::ofstream(file(name), std::ios::binary) << bytes;
    return file(name);
  }
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(scratch_.path()), {}));
  }

  testing::ScratchFolder scratch_{"io"};
};

Eigen::MatrixX3i faces_of(std::initializer_list<std::array<int, 3>> rows) {
  Eigen::MatrixX3i faces(static_cast<Eigen::Index>(rows.size()), 3);
  Eigen::Index r = 0;
  for (const auto& row : rows) faces.row(r++) << row[0], row[1], row[2];
  return faces;
}

Eigen::MatrixX3d vertices_of(std::initializer_list<std::array<double, 3>> rows) {
  Eigen::MatrixX3d vertices(static_cast<Eigen::Index>(rows.size()), 3);
  Eigen::Index r = 0;
  for (const auto& row : rows) vertices.row(r++) << row[0], row[1], row[2];
  return vertices;
}

// The same bits in every entry (EXPECT_EQ on doubles would accept nothing less anyway, but this
// also tells -0.0 from 0.0).
template <typename Matrix>
bool bitwise_equal(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(typename Matrix::Scalar) * a.size()) == 0;
}

// A mesh whose coordinates need all 17 significant digits (or are extreme) to survive printing.
Mesh awkward_mesh() {
  Mesh mesh = hemisphere(3);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    mesh.vertices.row(v) *= std::numbers::pi / 3.0;
    mesh.vertices(v, 0) += 0.1 * static_cast<double>(v) / 7.0;
  }
  mesh.vertices.row(0) << 1e-300, -1.7976931348623157e308, 4.9406564584124654e-324;
  mesh.vertices.row(1) << -0.0, 0.1, 1.0 / 3.0;
  return mesh;
}

// --- OBJ ---------------------------------------------------------------------------------------

TEST(ReadObj, AcceptsEveryCornerFormAndSkipsOtherStatements) {
  const Mesh mesh = read_obj(asset("cube_forms.obj"));
  EXPECT_TRUE(bitwise_equal(mesh.vertices, vertices_of({{0, 0, 0},
                                                        {1, 0, 0},
                                                        {1, 1, 0},
                                                        {0, 1, 0},
                                                        {0, 0, 1},
                                                        {1, 0, 1},
                                                        {1, 1, 1},
                                                        {0, 1, 1}})));
  // Each quad (a b c d) becomes the fan (a b c), (a c d).
  EXPECT_EQ(mesh.faces, faces_of({{0, 3, 2},
                                  {0, 2, 1},
                                  {4, 5, 6},
                                  {4, 6, 7},
                                  {0, 1, 5},
                                  {0, 5, 4},
                                  {1, 2, 6},
                                  {1, 6, 5},
                                  {2, 3, 7},
                                  {2, 7, 6},
                                  {3, 0, 4},
                                  {3, 4, 7}}));
}

TEST(ReadObj, NegativeIndicesCountBackFromTheLatestVertex) {
  const Mesh mesh = read_obj(asset("relative.obj"));
  EXPECT_EQ(mesh.vertex_count(), 4);
  EXPECT_EQ(mesh.faces, faces_of({{0, 1, 2}, {1, 3, 2}}));
}

TEST_F(IoTest, ObjPentagonBecomesAFanOfThreeTriangles) {
  const Mesh mesh = read_obj(write_bytes("pentagon.obj",
                                         "v 1 0 0\nv 0.3 0.95 0\nv -0.8 0.6 0\nv -0.8 -0.6 0\n"
                                         "v 0.3 -0.95 0\nf 1 2 3 4 5\n"));
  EXPECT_EQ(mesh.faces, faces_of({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
}

TEST(ReadTexturedObj, ReadsTextureCoordinatesAndCornerIndices) {
  const TexturedMesh textured = read_textured_obj(asset("square_textured.obj"));
  EXPECT_EQ(textured.mesh.vertex_count(), 4);
  EXPECT_EQ(textured.mesh.faces, faces_of({{0, 1, 2}, {0, 2, 3}}));
  Eigen::MatrixX2d uv(5, 2);
  uv << 0, 0, 0.5, 0, 0.5, 0.5, 0, 0.5, 0.25, 0.75;
  EXPECT_TRUE(bitwise_equal(textured.uv, uv));
  // Second face "1/5 3/-3 4/-2": texture 5 and, with 5 read so far, -3 -> 3rd and -2 -> 4th.
  EXPECT_EQ(textured.uv_faces, faces_of({{0, 1, 2}, {4, 2, 3}}));
}

// --- What exporters write and the readers people use accept (tests/assets/io/variants) --------
// Each file is a minimized form of a real one of ../shared/data/wild (Blender, MeshLab and Rhino
// exports, trimesh's loader tests); each is read as trimesh reads it, to the vertices and faces
// written out here by hand.

struct VariantFile {
  const char* name;
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> faces;
};

void PrintTo(const VariantFile& variant, std::ostream* out) { *out << variant.name; }

class ReaderVariant : public ::testing::TestWithParam<VariantFile> {};

TEST_P(ReaderVariant, ReadsToTheVerticesAndFacesTheFileHolds) {
  const VariantFile& variant = GetParam();
  const Mesh mesh = read_mesh(asset(std::string("variants/") + variant.name));
  Eigen::MatrixX3d vertices(static_cast<Eigen::Index>(variant.vertices.size()), 3);
  for (std::size_t v = 0; v < variant.vertices.size(); ++v)
    vertices.row(static_cast<Eigen::Index>(v)) << variant.vertices[v][0], variant.vertices[v][1], variant.vertices[v][2];
  Eigen::MatrixX3i faces(static_cast<Eigen::Index>(variant.faces.size()), 3);
  for (std::size_t f = 0; f < variant.faces.size(); ++f)
    faces.row(static_cast<Eigen::Index>(f)) << variant.faces[f][0], variant.faces[f][1], variant.faces[f][2];
  EXPECT_TRUE(bitwise_equal(mesh.vertices, vertices)) << mesh.vertices;
  EXPECT_EQ(mesh.faces, faces);
}

constexpr std::array<double, 3> kOrigin{0, 0, 0}, kX{1, 0, 0}, kXY{1, 1, 0}, kY{0, 1, 0};

const VariantFile reader_variants[] = {
    // The last line has no final newline: complete all the same.
    {"no_final_newline.obj", {kOrigin, kX, kY, kXY}, {{0, 1, 2}, {1, 3, 2}}},
    {"no_final_newline.off", {kOrigin, kX, kXY, kY}, {{0, 1, 2}, {0, 2, 3}}},
    {"no_final_newline.ply", {kOrigin, kX, kXY, kY}, {{0, 1, 2}, {0, 2, 3}}},
    // Corners `1//`, `1/1/`, `-1/`: the vertex alone.
    {"empty_slots.obj", {kOrigin, kX, kXY, kY}, {{0, 1, 2}, {0, 2, 3}}},
    // Faces before the vertices they name (positive indices read against the whole file).
    {"forward_references.obj", {kOrigin, kX, kY, kXY}, {{0, 1, 2}, {1, 3, 2}}},
    // A quad continued on the next line by a backslash.
    {"continued_polygon.obj", {kOrigin, kX, kXY, kY}, {{0, 1, 2}, {0, 2, 3}}},
    // Per-face lists and colours beyond what the header declares, vertex lines short of theirs.
    {"extra_values.ply", {kOrigin, kX, kXY, kY}, {{0, 1, 2}, {0, 2, 3}}},
    // "OFF4 2 0", colours after the face indices.
    {"glued_header.off", {kOrigin, kX, kXY, kY}, {{0, 1, 2}, {0, 2, 3}}},
    // Keywords in capitals.
    {"capitals.stl", {kOrigin, kX, kY}, {{0, 1, 2}}},
    // The facets without the closing 'endsolid'.
    {"no_endsolid.stl", {kOrigin, kX, kY}, {{0, 1, 2}}},
};
INSTANTIATE_TEST_SUITE_P(Exports, ReaderVariant, ::testing::ValuesIn(reader_variants));

TEST(ReaderVariants, EveryVariantAssetIsCovered) {
  EXPECT_EQ(static_cast<std::size_t>(std::distance(fs::directory_iterator(asset("variants")), {})),
            std::size(reader_variants));
}

// --- OFF ---------------------------------------------------------------------------------------

TEST(ReadOff, CommentsBlankLinesCountsOnTheirOwnLineAndAQuad) {
  const Mesh mesh = read_off(asset("pyramid.off"));
  EXPECT_TRUE(bitwise_equal(
      mesh.vertices, vertices_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}})));
  EXPECT_EQ(mesh.faces,
            faces_of({{0, 3, 2}, {0, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}));
}

TEST(ReadOff, ColourAndNormalVariantsKeepOnlyPositions) {
  const Eigen::MatrixX3d square = vertices_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  for (const char* name : {"triangle_pair_colour.off", "triangle_pair_normal.off"}) {
    const Mesh mesh = read_mesh(asset(name));
    EXPECT_TRUE(bitwise_equal(mesh.vertices, square)) << name;
    EXPECT_EQ(mesh.faces, faces_of({{0, 1, 2}, {0, 2, 3}})) << name;
  }
}

TEST_F(IoTest, OffWithoutHeaderKeywordAndCountsOnTheSameLine) {
  const Mesh plain = read_off(write_bytes("plain.off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  EXPECT_EQ(plain.faces, faces_of({{0, 1, 2}}));
  const Mesh inline_counts =
      read_off(write_bytes("inline.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 2 1 0\n"));
  EXPECT_EQ(inline_counts.faces, faces_of({{2, 1, 0}}));
}

// --- PLY ---------------------------------------------------------------------------------------

TEST(ReadPly, AsciiSkipsOtherPropertiesListsAndElements) {
  const Mesh mesh = read_ply(asset("pyramid_ascii.ply"));
  EXPECT_TRUE(bitwise_equal(
      mesh.vertices, vertices_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}})));
  EXPECT_EQ(mesh.faces,
            faces_of({{0, 3, 2}, {0, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}));
}

// Appends the bytes of `value` in the requested byte order.
template <typename T>
void put(std::string& out, T value, std::endian order) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (order != std::endian::native) std::reverse(raw, raw + sizeof(T));
  out.append(reinterpret_cast<const char*>(raw), sizeof(T));
}

// A binary PLY of the square pyramid with mixed types: float x, short "quality", double y, float z,
// an unrelated "edge" element with a list, and faces with a uint count and ushort indices plus a
// leading int "flags". The big-endian file calls the index list "vertex_index", the other accepted
// name.
std::string binary_pyramid(std::endian order) {
  std::string out = "ply\nformat ";
  out += order == std::endian::little ? "binary_little_endian" : "binary_big_endian";
  out +=
      " 1.0\nelement vertex 5\nproperty float x\nproperty short quality\nproperty double y\n"
      "property float z\nelement edge 1\nproperty list uchar int ends\n"
      "element face 5\nproperty int flags\nproperty list uint ushort ";
  out += order == std::endian::little ? "vertex_indices" : "vertex_index";
  out += "\nend_header\n";
  const double positions[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
  for (const auto& p : positions) {
    put(out, static_cast<float>(p[0]), order);
    put(out, std::int16_t{-7}, order);
    put(out, p[1], order);
    put(out, static_cast<float>(p[2]), order);
  }
  put(out, std::uint8_t{2}, order);
  put(out, std::int32_t{0}, order);
  put(out, std::int32_t{4}, order);
  const std::vector<std::vector<std::uint16_t>> faces = {
      {0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  for (const auto& face : faces) {
    put(out, std::int32_t{0x01020304}, order);
    put(out, static_cast<std::uint32_t>(face.size()), order);
    for (const std::uint16_t index : face) put(out, index, order);
  }
  return out;
}

TEST_F(IoTest, BinaryPlyInBothByteOrders) {
  for (const std::endian order : {std::endian::little, std::endian::big}) {
    const Mesh mesh = read_ply(write_bytes("pyramid.ply", binary_pyramid(order)));
    EXPECT_TRUE(bitwise_equal(
        mesh.vertices, vertices_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}})));
    EXPECT_EQ(mesh.faces,
              faces_of({{0, 3, 2}, {0, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}));
  }
}

// --- STL ---------------------------------------------------------------------------------------

TEST(ReadStl, AsciiMergesCornersAtTheSamePosition) {
  const Mesh mesh = read_stl(asset("square_ascii.stl"));
  // Six corners, four positions: numbered by first appearance.
  EXPECT_TRUE(
      bitwise_equal(mesh.vertices, vertices_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}})));
  EXPECT_EQ(mesh.faces, faces_of({{0, 1, 2}, {0, 2, 3}}));
}

// A binary STL of `triangles` (corner positions), little-endian float32 as the format demands.
std::string binary_stl(const std::vector<std::array<std::array<float, 3>, 3>>& triangles,
                       const std::string& header_text) {
  std::string out = header_text;
  out.resize(80, ' ');
  put(out, static_cast<std::uint32_t>(triangles.size()), std::endian::little);
  for (const auto& triangle : triangles) {
    for (int k = 0; k < 3; ++k) put(out, 0.0f, std::endian::little);  // normal
    for (const auto& corner : triangle) {
      for (const float coordinate : corner) put(out, coordinate, std::endian::little);
    }
    put(out, std::uint16_t{0}, std::endian::little);
  }
  return out;
}

TEST_F(IoTest, BinaryStlMergesCornersEvenWhenTheHeaderSaysSolid) {
  // A tetrahedron: 12 corners, 4 positions; the header starts with "solid" as some exporters do.
  const std::array<float, 3> a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0}, d{0, 0, 1.5f};
  const std::string bytes = binary_stl({{a, c, b}, {a, b, d}, {b, c, d}, {c, a, d}}, "solid tet");
  const Mesh mesh = read_mesh(write_bytes("tet.stl", bytes));
  EXPECT_TRUE(
      bitwise_equal(mesh.vertices, vertices_of({{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1.5}})));
  EXPECT_EQ(mesh.faces, faces_of({{0, 1, 2}, {0, 2, 3}, {2, 1, 3}, {1, 0, 3}}));
}

// --- Writers -----------------------------------------------------------------------------------

TEST_F(IoTest, EveryWriterRoundTripsBitForBit) {
  const Mesh mesh = awkward_mesh();
  for (const char* name : {"mesh.obj", "mesh.off", "mesh.ply", "MESH.OBJ"}) {
    write_mesh(file(name), mesh);
    const Mesh back = read_mesh(file(name));
    EXPECT_TRUE(bitwise_equal(back.vertices, mesh.vertices)) << name;
    EXPECT_EQ(back.faces, mesh.faces) << name;
  }
}

TEST_F(IoTest, PlyWriterWritesBinaryLittleEndianDoubles) {
  const Mesh mesh = awkward_mesh();
  write_mesh(file("mesh.ply"), mesh);
  std::ifstream in(file("mesh.ply"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(bytes.find("format binary_little_endian 1.0\n"), std::string::npos);
  const std::size_t data = bytes.find("end_header\n") + 11;
  // The data is 3 doubles per vertex, then (uchar 3, 3 int32) per face.
  EXPECT_EQ(bytes.size() - data, 24u * mesh.vertices.rows() + 13u * mesh.faces.rows());
  unsigned char first[8];
  std::memcpy(first, bytes.data() + data, 8);
  if (std::endian::native == std::endian::big) std::reverse(first, first + 8);
  double x0 = 0.0;
  std::memcpy(&x0, first, 8);
  EXPECT_EQ(x0, mesh.vertices(0, 0));
}

TEST_F(IoTest, TexturedObjRoundTripsWithSeamsAndPerVertexUv) {
  TexturedMesh textured;
  textured.mesh = awkward_mesh();
  const Eigen::Index uv_count = textured.mesh.vertices.rows() + 2;
  textured.uv = Eigen::MatrixX2d::Random(uv_count, 2) / 3.0;
  textured.uv_faces = textured.mesh.faces;
  textured.uv_faces(0, 0) = static_cast<int>(uv_count - 1);  // A seam: another uv for a corner.
  textured.uv_faces(1, 2) = static_cast<int>(uv_count - 2);
  write_obj(file("seams.obj"), textured);
  const TexturedMesh back = read_textured_obj(file("seams.obj"));
  EXPECT_TRUE(bitwise_equal(back.mesh.vertices, textured.mesh.vertices));
  EXPECT_EQ(back.mesh.faces, textured.mesh.faces);
  EXPECT_TRUE(bitwise_equal(back.uv, textured.uv));
  EXPECT_EQ(back.uv_faces, textured.uv_faces);

  const Eigen::MatrixX2d per_vertex = textured.mesh.vertices.leftCols(2) * 0.5;
  write_obj(file("per_vertex.obj"), textured.mesh, per_vertex);
  const TexturedMesh simple = read_textured_obj(file("per_vertex.obj"));
  EXPECT_TRUE(bitwise_equal(simple.uv, per_vertex));
  EXPECT_EQ(simple.uv_faces, textured.mesh.faces);
  // The plain reader ignores the texture part.
  EXPECT_EQ(read_obj(file("per_vertex.obj")).faces, textured.mesh.faces);
}

TEST_F(IoTest, WritingReplacesAnExistingFileAndLeavesNoTemporaryBehind) {
  write_bytes("mesh.obj", "old contents that are much longer than nothing at all\n");
  const Mesh mesh = hemisphere(2);
  write_mesh(file("mesh.obj"), mesh);
  EXPECT_EQ(read_obj(file("mesh.obj")).faces, mesh.faces);
  EXPECT_EQ(entries(), 1u);
}

TEST(MeshFormat, FromExtensionIgnoresCase) {
  EXPECT_EQ(format_from_extension("a/b.obj"), MeshFormat::obj);
  EXPECT_EQ(format_from_extension("b.OFF"), MeshFormat::off);
  EXPECT_EQ(format_from_extension("c.Ply"), MeshFormat::ply);
  EXPECT_EQ(format_from_extension("d.stl"), MeshFormat::stl);
}

// --- Corpus ------------------------------------------------------------------------------------

TEST(ReadObj, CorpusCamelheadHasTheDocumentedCounts) {
  const fs::path path = testing::shared_data_dir() / "disk" / "camelhead.obj";
  if (!fs::exists(path))
    HARMONIA_SKIP_WITHOUT_CORPUS("corpus not found at " << path << " (set HARMONIA_SHARED_DATA)");
  const Mesh mesh = read_obj(path);
  EXPECT_EQ(mesh.vertex_count(), 11381);
  EXPECT_EQ(mesh.face_count(), 22704);
  // Independent check of the last face against a naive reading of the file's last "f" line.
  std::ifstream in(path);
  std::string line, last_face;
  while (std::getline(in, line)) {
    if (line.rfind("f ", 0) == 0) last_face = line;
  }
  std::istringstream fields(last_face.substr(2));
  int a = 0, b = 0, c = 0;
  fields >> a >> b >> c;
  EXPECT_EQ(mesh.faces.row(mesh.face_count() - 1), Eigen::RowVector3i(a - 1, b - 1, c - 1));
  EXPECT_GE(mesh.faces.minCoeff(), 0);
  EXPECT_LT(mesh.faces.maxCoeff(), mesh.vertex_count());
}

}  // namespace
}  // namespace harmonia
