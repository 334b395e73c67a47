// Mesh input/output, error paths: every broken file gives a harmonia::Error with the right Status
// and a message naming the file, the line (text) or byte offset (binary), and the problem — never a
// crash, a hang, or an allocation sized by an untrusted header count.
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <string>

#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;

// Runs `action`, which must throw harmonia::Error; returns the status and message.
struct Failure {
  Status status = Status::ok;
  std::string message;
};

Failure failure_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& error) {
    return {error.status(), error.what()};
  }
  ADD_FAILURE() << "no harmonia::Error was thrown";
  return {};
}

// --- Broken files kept as assets: file, the expected message tail "NAME:LINE: problem" ----------

struct BrokenFile {
  const char* name;
  const char* message;
};

void PrintTo(const BrokenFile& broken, std::ostream* out) { *out << broken.name; }

class BrokenAsset : public ::testing::TestWithParam<BrokenFile> {};

TEST_P(BrokenAsset, FailsWithFileLineAndProblem) {
  const fs::path path = testing::assets_dir() / "io" / "broken" / GetParam().name;
  ASSERT_TRUE(fs::exists(path)) << path;
  const bool textured = std::string(GetParam().name).find("texture") != std::string::npos;
  const Failure failure = failure_of([&] {
    if (textured) {
      (void)read_textured_obj(path);
    } else {
      (void)read_mesh(path);
    }
  });
  EXPECT_EQ(failure.status, Status::parse_error) << failure.message;
  // The message starts with the full path as given, then the location and the problem.
  EXPECT_EQ(failure.message, (path.parent_path() / GetParam().message).string());
}

const BrokenFile broken_obj[] = {
    {"empty.obj", "empty.obj:1: the file is empty"},
    {"index_zero.obj",
     "index_zero.obj:5: face 1: vertex index 0 (corner 0) is invalid: OBJ indices start at 1"},
    {"index_out_of_range.obj",
     "index_out_of_range.obj:5: face 0: vertex index 7 (corner 2) is out "
     "of range: 3 vertices in the file"},
    {"negative_out_of_range.obj",
     "negative_out_of_range.obj:4: face 0: vertex index -4 (corner 2) "
     "is out of range: 3 vertices defined so far"},
    {"huge_index.obj", "huge_index.obj:4: integer '99999999999999999999' is out of range"},
    {"nan_vertex.obj", "nan_vertex.obj:2: vertex 1 has a non-finite y coordinate"},
    {"inf_vertex.obj", "inf_vertex.obj:3: vertex 2 has a non-finite z coordinate"},
    {"garbage_number.obj",
     "garbage_number.obj:2: expected the y coordinate of vertex 1, found '0.5x'"},
    {"huge_number.obj",
     "huge_number.obj:2: number '1e999' (the x coordinate of vertex 1) is out of range"},
    {"two_vertex_face.obj",
     "two_vertex_face.obj:5: face 1 has 2 vertices; a face needs at least 3"},
    {"no_faces.obj", "no_faces.obj:3: no faces in the file (2 vertices read)"},
    {"truncated.obj",
     "truncated.obj:3: expected the z coordinate of vertex 2, found the end of the line"},
    {"malformed_corner.obj",
     "malformed_corner.obj:4: face 0: malformed corner '/1' (expected v, "
     "v/vt, v//vn or v/vt/vn)"},
    {"missing_texture_index.obj",
     "missing_texture_index.obj:5: face 0: corner 1 has no texture "
     "index (read_textured_obj needs 'f v/vt ...')"},
    {"texture_index_out_of_range.obj",
     "texture_index_out_of_range.obj:6: face 0: texture index 3 "
     "(corner 2) is out of range: 2 texture coordinates in the file"},
};
INSTANTIATE_TEST_SUITE_P(Obj, BrokenAsset, ::testing::ValuesIn(broken_obj));

const BrokenFile broken_off[] = {
    {"empty.off", "empty.off:1: the file is empty"},
    {"bad_header.off",
     "bad_header.off:1: expected the OFF header ('OFF', 'COFF', 'NOFF', ...), found 'OFX'"},
    {"four_d.off", "four_d.off:1: '4OFF' files (4D or n-dimensional) are not supported"},
    {"absurd_counts.off",
     "absurd_counts.off:2: the header claims 1000000000000 vertices and 1 "
     "faces, more than a file of 28 bytes can hold"},
    {"absurd_faces.off",
     "absurd_faces.off:2: the header claims 3 vertices and 1000000000000 "
     "faces, more than a file of 48 bytes can hold"},
    {"negative_count.off", "negative_count.off:2: the vertex count is negative (-3)"},
    {"truncated_vertices.off",
     "truncated_vertices.off:4: the file ends after 2 of 4 vertices (truncated)"},
    {"truncated_faces.off", "truncated_faces.off:7: the file ends after 1 of 2 faces (truncated)"},
    {"truncated_face_line.off",
     "truncated_face_line.off:8: expected corner 2 of face 1, found the end of the line"},
    {"index_out_of_range.off",
     "index_out_of_range.off:7: face 0: vertex index 4 (corner 2) is out "
     "of range: 4 vertices"},
    {"negative_index.off",
     "negative_index.off:8: face 1: vertex index -1 (corner 1) is out of range: 4 vertices"},
    {"nan_vertex.off", "nan_vertex.off:5: vertex 2 has a non-finite z coordinate"},
    {"two_vertex_face.off",
     "two_vertex_face.off:8: face 1 has 2 vertices; a face needs at least 3"},
    {"no_faces.off", "no_faces.off:2: no faces: the header declares 0 faces"},
    {"garbage_number.off",
     "garbage_number.off:4: expected the y coordinate of vertex 1, found 'zero'"},
};
INSTANTIATE_TEST_SUITE_P(Off, BrokenAsset, ::testing::ValuesIn(broken_off));

const BrokenFile broken_ply[] = {
    {"empty.ply", "empty.ply:1: the file is empty"},
    {"not_ply.ply", "not_ply.ply:1: not a PLY file: the first line must be 'ply', found 'plx'"},
    {"truncated_header.ply", "truncated_header.ply:4: the file ends inside the header (truncated)"},
    {"unknown_type.ply", "unknown_type.ply:4: unknown property type 'float128'"},
    {"unknown_format.ply", "unknown_format.ply:2: unknown PLY format 'binary_middle_endian'"},
    {"missing_z.ply", "missing_z.ply:3: element 'vertex': no scalar property 'z'"},
    {"no_face_element.ply", "no_face_element.ply:7: no faces: the header declares none"},
    {"absurd_count.ply",
     "absurd_count.ply:3: element 'vertex': the header claims 1000000000000 "
     "elements, more than the remaining 26 bytes of the file can hold"},
    {"truncated.ply", "truncated.ply:13: the file ends before face 1 (truncated)"},
    {"index_out_of_range.ply",
     "index_out_of_range.ply:14: face 1: vertex index 3 (corner 2) is out "
     "of range: 3 vertices"},
    {"nan_vertex.ply", "nan_vertex.ply:12: vertex 2 has a non-finite x coordinate"},
    {"two_vertex_face.ply",
     "two_vertex_face.ply:14: face 1 has 2 vertices; a face needs at least 3"},
    {"garbage_number.ply",
     "garbage_number.ply:11: expected the y coordinate of vertex 1, found 'a'"},
};
INSTANTIATE_TEST_SUITE_P(Ply, BrokenAsset, ::testing::ValuesIn(broken_ply));

const BrokenFile broken_stl[] = {
    {"empty.stl", "empty.stl: byte 0: the file is empty"},
    {"short.stl",
     "short.stl: byte 10: the file ends inside the 84-byte header of a binary STL (it "
     "has 10 bytes)"},
    {"truncated_ascii.stl", "truncated_ascii.stl:5: the file ends inside facet 0 (truncated)"},
    {"nan_ascii.stl", "nan_ascii.stl:5: corner 1 of facet 0 has a non-finite coordinate"},
    {"bad_keyword.stl", "bad_keyword.stl:9: expected 'facet' or 'endsolid', found 'facets'"},
    {"two_vertex_facet.stl",
     "two_vertex_facet.stl:6: facet 0 has 2 vertices; a face needs at least 3"},
    {"no_facets.stl", "no_facets.stl:2: no faces in the file"},
    {"garbage_number.stl",
     "garbage_number.stl:5: expected the y coordinate of corner 1 of facet 0, found 'zero'"},
};
INSTANTIATE_TEST_SUITE_P(Stl, BrokenAsset, ::testing::ValuesIn(broken_stl));

TEST(BrokenAssets, EveryAssetIsCovered) {
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry :
       fs::directory_iterator(testing::assets_dir() / "io" / "broken")) {
    ++files;
  }
  EXPECT_EQ(files, std::size(broken_obj) + std::size(broken_off) + std::size(broken_ply) +
                       std::size(broken_stl));
}

// --- Broken files written here (binary content) -------------------------------------------------

class BrokenBinary : public ::testing::Test {
 protected:
  fs::path write_bytes(const std::string& name, const std::string& bytes) const {
    std::ofstream(scratch_.path() / name, std::ios::binary) << bytes;
    return scratch_.path() / name;
  }
  // Reads `name` (written with `bytes`) and returns the failure, checking it is a parse error.
  std::string parse_failure(const std::string& name, const std::string& bytes) const {
    const fs::path path = write_bytes(name, bytes);
    const Failure failure = failure_of([&] { (void)read_mesh(path); });
    EXPECT_EQ(failure.status, Status::parse_error) << failure.message;
    return failure.message;
  }
  std::string prefix(const std::string& name) const { return (scratch_.path() / name).string(); }

  testing::ScratchFolder scratch_{"io-broken"};
};

// The start of an ELF executable: what "binary garbage given to a text reader" looks like.
const std::string elf_bytes = [] {
  const char raw[] =
      "\x7f"
      "ELF\x02\x01\x01 \x00\x00\x00\x03\x00>\x00\n\x01\x00";
  return std::string(raw, sizeof raw - 1);  // Keep the embedded NUL bytes.
}();

TEST_F(BrokenBinary, BinaryGarbageGivenToTextReaders) {
  EXPECT_EQ(parse_failure("garbage.obj", elf_bytes),
            prefix("garbage.obj") +
                ":1: '\\x7fELF\\x02\\x01\\x01' is not an OBJ statement (is this a binary file?)");
  EXPECT_EQ(parse_failure("garbage.off", elf_bytes),
            prefix("garbage.off") +
                ":1: expected the OFF header ('OFF', 'COFF', 'NOFF', ...), "
                "found '\\x7fELF\\x02\\x01\\x01'");
  EXPECT_EQ(
      parse_failure("garbage.ply", elf_bytes),
      prefix("garbage.ply") +
          ":1: not a PLY file: the first line must be 'ply', found '\\x7fELF\\x02\\x01\\x01'");
}

template <typename T>
void put(std::string& out, T value, std::endian order) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (order != std::endian::native) std::reverse(raw, raw + sizeof(T));
  out.append(reinterpret_cast<const char*>(raw), sizeof(T));
}

// Header of a binary PLY: 3 float vertices and `faces` faces with a (uchar, int) index list.
std::string ply_header(std::endian order, const std::string& faces = "1",
                       const std::string& extra_vertex_property = "",
                       const std::string& index_type = "int") {
  return std::string("ply\nformat ") +
         (order == std::endian::little ? "binary_little_endian" : "binary_big_endian") +
         " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n" +
         extra_vertex_property + "element face " + faces + "\nproperty list uchar " + index_type +
         " vertex_indices\nend_header\n";
}

void put_triangle_vertices(std::string& out, std::endian order, float nan_at_y_of_1 = 0.0f) {
  const float positions[3][3] = {{0, 0, 0}, {1, nan_at_y_of_1, 0}, {0, 1, 0}};
  for (const auto& p : positions) {
    for (const float c : p) put(out, c, order);
  }
}

TEST_F(BrokenBinary, PlyTruncatedInsideAFace) {
  const std::string header = ply_header(std::endian::little);
  std::string bytes = header;
  put_triangle_vertices(bytes, std::endian::little);
  put(bytes, std::uint8_t{3}, std::endian::little);
  put(bytes, std::int32_t{0}, std::endian::little);
  put(bytes, std::int32_t{1}, std::endian::little);  // The third index is missing.
  EXPECT_EQ(parse_failure("truncated.ply", bytes),
            prefix("truncated.ply") + ": byte " + std::to_string(header.size() + 36 + 1 + 8) +
                ": the file ends inside corner 2 of face 0 (truncated)");
}

TEST_F(BrokenBinary, PlyAbsurdFaceCountIsRejectedFromTheHeader) {
  std::string bytes = ply_header(std::endian::little, "1000000000000");
  put_triangle_vertices(bytes, std::endian::little);
  // The face element is declared on header line 7.
  EXPECT_EQ(parse_failure("absurd.ply", bytes),
            prefix("absurd.ply") +
                ":7: element 'face': the header claims 1000000000000 elements, "
                "more than the remaining 36 bytes of the file can hold");
}

TEST_F(BrokenBinary, PlyBigEndianIndexOutOfRange) {
  const std::string header = ply_header(std::endian::big);
  std::string bytes = header;
  put_triangle_vertices(bytes, std::endian::big);
  put(bytes, std::uint8_t{3}, std::endian::big);
  for (const std::int32_t index : {0, 9, 2}) put(bytes, index, std::endian::big);
  EXPECT_EQ(parse_failure("index.ply", bytes),
            prefix("index.ply") + ": byte " + std::to_string(header.size() + 36 + 1 + 4) +
                ": face 0: vertex index 9 (corner 1) is out of range: 3 vertices");
}

TEST_F(BrokenBinary, PlyNegativeIndex) {
  const std::string header = ply_header(std::endian::little);
  std::string bytes = header;
  put_triangle_vertices(bytes, std::endian::little);
  put(bytes, std::uint8_t{3}, std::endian::little);
  for (const std::int32_t index : {0, 1, -1}) put(bytes, index, std::endian::little);
  EXPECT_EQ(parse_failure("negative.ply", bytes),
            prefix("negative.ply") + ": byte " + std::to_string(header.size() + 36 + 1 + 8) +
                ": face 0: vertex index -1 (corner 2) is out of range: 3 vertices");
}

TEST_F(BrokenBinary, PlyNonFiniteCoordinate) {
  const std::string header = ply_header(std::endian::big);
  std::string bytes = header;
  put_triangle_vertices(bytes, std::endian::big, std::numeric_limits<float>::quiet_NaN());
  put(bytes, std::uint8_t{3}, std::endian::big);
  for (const std::int32_t index : {0, 1, 2}) put(bytes, index, std::endian::big);
  // Vertex 1's y is the 5th float.
  EXPECT_EQ(parse_failure("nan.ply", bytes), prefix("nan.ply") + ": byte " +
                                                 std::to_string(header.size() + 16) +
                                                 ": vertex 1 has a non-finite y coordinate");
}

TEST_F(BrokenBinary, PlyAbsurdListLengthInAnotherProperty) {
  const std::string header =
      ply_header(std::endian::little, "1", "property list uint float extra\n");
  std::string bytes = header;
  for (int k = 0; k < 3; ++k) put(bytes, 0.0f, std::endian::little);
  put(bytes, std::uint32_t{4000000000u}, std::endian::little);
  bytes += std::string(64, '\0');
  EXPECT_EQ(parse_failure("list.ply", bytes),
            prefix("list.ply") + ": byte " + std::to_string(header.size() + 12) +
                ": list property 'extra' of vertex 0 claims 4000000000 entries, more than the "
                "rest of the file holds (truncated?)");
}

TEST_F(BrokenBinary, PlyFaceWithTwoVertices) {
  const std::string header = ply_header(std::endian::little);
  std::string bytes = header;
  put_triangle_vertices(bytes, std::endian::little);
  put(bytes, std::uint8_t{2}, std::endian::little);
  for (const std::int32_t index : {0, 1, 2}) put(bytes, index, std::endian::little);
  EXPECT_EQ(parse_failure("two.ply", bytes),
            prefix("two.ply") + ": byte " + std::to_string(header.size() + 36) +
                ": face 0 has 2 vertices; a face needs at least 3");
}

TEST_F(BrokenBinary, PlyFloatingPointIndicesAreRejectedFromTheHeader) {
  std::string bytes = ply_header(std::endian::little, "1", "", "float");
  put_triangle_vertices(bytes, std::endian::little);
  bytes += std::string(13, '\0');
  EXPECT_EQ(
      parse_failure("float_index.ply", bytes),
      prefix("float_index.ply") + ":7: element 'face': 'vertex_indices' must have integer entries");
}

// A binary STL with the given triangle count in the header and `triangles` records of data.
std::string stl_bytes(std::uint32_t declared, int triangles, int nan_triangle = -1,
                      int nan_corner = -1) {
  std::string out(80, ' ');
  put(out, declared, std::endian::little);
  for (int t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) put(out, 0.0f, std::endian::little);
    for (int corner = 0; corner < 3; ++corner) {
      const bool bad = t == nan_triangle && corner == nan_corner;
      put(out, static_cast<float>(corner == 1), std::endian::little);
      put(out, bad ? std::numeric_limits<float>::infinity() : static_cast<float>(corner == 2),
          std::endian::little);
      put(out, static_cast<float>(t), std::endian::little);
    }
    put(out, std::uint16_t{0}, std::endian::little);
  }
  return out;
}

TEST_F(BrokenBinary, StlTruncatedAbsurdEmptyAndNonFinite) {
  EXPECT_EQ(parse_failure("truncated.stl", stl_bytes(2, 1)),
            prefix("truncated.stl") +
                ": byte 80: the header claims 2 triangles, which take 184 "
                "bytes, but the file has 134 (truncated, or not an STL file)");
  EXPECT_EQ(parse_failure("absurd.stl", stl_bytes(0xffffffffu, 0)),
            prefix("absurd.stl") +
                ": byte 80: the header claims 4294967295 triangles, which take "
                "214748364834 bytes, but the file has 84 (truncated, or not an "
                "STL file)");
  EXPECT_EQ(parse_failure("none.stl", stl_bytes(0, 0)),
            prefix("none.stl") + ": byte 80: no faces: the header declares 0 triangles");
  // Triangle 1 starts at 84 + 50; its corner 2 at 12 (normal) + 2 * 12 further.
  EXPECT_EQ(parse_failure("inf.stl", stl_bytes(2, 2, 1, 2)),
            prefix("inf.stl") + ": byte 170: triangle 1: corner 2 has a non-finite coordinate");
}

// --- Files that cannot be opened or written -----------------------------------------------------

TEST_F(BrokenBinary, UnknownExtensionMissingFileAndFolder) {
  const Failure unknown =
      failure_of([&] { (void)read_mesh(write_bytes("mesh.xyz", "v 0 0 0\n")); });
  EXPECT_EQ(unknown.status, Status::io_error);
  EXPECT_EQ(
      unknown.message,
      prefix("mesh.xyz") + ": unknown mesh format '.xyz' (expected .obj, .off, .ply, .stl, .gltf or .glb)");

  const Failure missing = failure_of([&] { (void)read_obj(scratch_.path() / "missing.obj"); });
  EXPECT_EQ(missing.status, Status::io_error);
  EXPECT_EQ(missing.message, prefix("missing.obj") + ": cannot open: No such file or directory");

  fs::create_directory(scratch_.path() / "folder.off");
  const Failure folder = failure_of([&] { (void)read_mesh(scratch_.path() / "folder.off"); });
  EXPECT_EQ(folder.status, Status::io_error);
  EXPECT_EQ(folder.message, prefix("folder.off") + ": cannot read: it is a directory");
}

TEST_F(BrokenBinary, WritersRefuseUnwritableTargetsAndLeaveOldFilesIntact) {
  const Mesh mesh = hemisphere(2);
  const Failure no_folder =
      failure_of([&] { write_mesh(scratch_.path() / "no" / "mesh.obj", mesh); });
  EXPECT_EQ(no_folder.status, Status::io_error);
  EXPECT_EQ(no_folder.message.rfind(prefix("no/mesh.obj") + ": cannot write: cannot create", 0), 0u)
      << no_folder.message;

  const Failure stl = failure_of([&] { write_mesh(scratch_.path() / "mesh.stl", mesh); });
  EXPECT_EQ(stl.status, Status::io_error);
  EXPECT_EQ(stl.message,
            prefix("mesh.stl") + ": writing STL is not offered (use .obj, .off or .ply)");

  // The target is a folder: refused before anything is written, the folder stays.
  fs::create_directory(scratch_.path() / "taken.obj");
  const Failure taken = failure_of([&] { write_mesh(scratch_.path() / "taken.obj", mesh); });
  EXPECT_EQ(taken.status, Status::io_error);
  EXPECT_EQ(taken.message, prefix("taken.obj") + ": cannot write: it is a directory");
  EXPECT_TRUE(fs::is_directory(scratch_.path() / "taken.obj"));

  // Invalid meshes are refused before anything is written; the old file is untouched.
  const std::string old_contents = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const fs::path existing = write_bytes("existing.obj", old_contents);
  Mesh not_finite = mesh;
  not_finite.vertices(4, 1) = std::numeric_limits<double>::quiet_NaN();
  const Failure nan = failure_of([&] { write_mesh(existing, not_finite); });
  EXPECT_EQ(nan.status, Status::invalid_input);
  EXPECT_EQ(nan.message, existing.string() + ": not written: vertex 4 is not finite");
  Mesh bad_index = mesh;
  bad_index.faces(3, 2) = mesh.vertex_count();
  const Failure index = failure_of([&] { write_mesh(existing, bad_index); });
  EXPECT_EQ(index.status, Status::invalid_input);
  EXPECT_EQ(index.message, existing.string() + ": not written: face 3 refers to vertex " +
                               std::to_string(mesh.vertex_count()) + ", but there are " +
                               std::to_string(mesh.vertex_count()) + " vertices");
  const Failure uv = failure_of([&] { write_obj(existing, mesh, Eigen::MatrixX2d::Zero(2, 2)); });
  EXPECT_EQ(uv.status, Status::invalid_input);
  EXPECT_EQ(uv.message, existing.string() + ": not written: uv has 2 rows but the mesh has " +
                            std::to_string(mesh.vertex_count()) + " vertices");

  TexturedMesh textured{mesh, Eigen::MatrixX2d::Zero(mesh.vertex_count(), 2), mesh.faces};
  textured.uv_faces.conservativeResize(mesh.face_count() - 1, 3);
  const Failure uv_faces = failure_of([&] { write_obj(existing, textured); });
  EXPECT_EQ(uv_faces.status, Status::invalid_input);
  EXPECT_EQ(uv_faces.message, existing.string() + ": not written: uv_faces has " +
                                  std::to_string(mesh.face_count() - 1) +
                                  " rows but the mesh has " + std::to_string(mesh.face_count()) +
                                  " faces");

  std::ifstream in(existing);
  const std::string contents((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  EXPECT_EQ(contents, old_contents);
  // Only existing.obj and the taken.obj folder remain: no temporary files were left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(scratch_.path()), {}), 2);
}

}  // namespace
}  // namespace harmonia
