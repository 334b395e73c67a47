// Mesh writers: OBJ (optionally with texture coordinates), OFF and binary little-endian PLY. The
// whole file is formatted in memory with std::to_chars, whose shortest round-trip form makes every
// coordinate read back to the same double, and then written atomically (io/atomic_file.h).
// A mesh that could not be read back (an index out of range, a non-finite coordinate) is refused.

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "harmonia/gltf.h"
#include "harmonia/io.h"
#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "io/obj_layout_lines.h"

namespace harmonia {
namespace {

[[noreturn]] void refuse(const std::filesystem::path& path, const std::string& problem) {
  throw Error(Status::invalid_input, path.string() + ": not written: " + problem);
}

void check_finite(const std::filesystem::path& path,
                  const Eigen::Ref<const Eigen::MatrixXd>& values, std::string_view what) {
  for (Eigen::Index row = 0; row < values.rows(); ++row) {
    if (!values.row(row).allFinite()) {
      refuse(path, std::string(what) + " " + std::to_string(row) + " is not finite");
    }
  }
}

void check_indices(const std::filesystem::path& path, const Eigen::MatrixX3i& faces,
                   Eigen::Index count, std::string_view what, std::string_view plural) {
  for (Eigen::Index face = 0; face < faces.rows(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int index = faces(face, corner);
      if (index < 0 || index >= count) {
        refuse(path, "face " + std::to_string(face) + " refers to " + std::string(what) + " " +
                         std::to_string(index) + ", but there are " + std::to_string(count) + " " +
                         std::string(plural));
      }
    }
  }
}

void check_mesh(const std::filesystem::path& path, const Mesh& mesh) {
  check_finite(path, mesh.vertices, "vertex");
  check_indices(path, mesh.faces, mesh.vertices.rows(), "vertex", "vertices");
}

void append_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void append_number(std::string& out, int value) {
  char buffer[16];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void append_vertices(std::string& out, const Eigen::MatrixX3d& vertices) {
  for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
    out += "v ";
    append_number(out, vertices(v, 0));
    out += ' ';
    append_number(out, vertices(v, 1));
    out += ' ';
    append_number(out, vertices(v, 2));
    out += '\n';
  }
}

void append_texture_coordinates(std::string& out, const Eigen::MatrixX2d& uv) {
  for (Eigen::Index t = 0; t < uv.rows(); ++t) {
    out += "vt ";
    append_number(out, uv(t, 0));
    out += ' ';
    append_number(out, uv(t, 1));
    out += '\n';
  }
}

// Faces "f a b c" or, with texture indices, "f a/ta b/tb c/tc" (OBJ counts from 1).
void append_obj_faces(std::string& out, const Eigen::MatrixX3i& faces) {
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    out += 'f';
    for (int corner = 0; corner < 3; ++corner) {
      out += ' ';
      append_number(out, faces(f, corner) + 1);
    }
    out += '\n';
  }
}

std::string format_off(const Mesh& mesh) {
  std::string out = "OFF\n";
  append_number(out, mesh.vertex_count());
  out += ' ';
  append_number(out, mesh.face_count());
  out += " 0\n";
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    append_number(out, mesh.vertices(v, 0));
    out += ' ';
    append_number(out, mesh.vertices(v, 1));
    out += ' ';
    append_number(out, mesh.vertices(v, 2));
    out += '\n';
  }
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    out += '3';
    for (int corner = 0; corner < 3; ++corner) {
      out += ' ';
      append_number(out, mesh.faces(f, corner));
    }
    out += '\n';
  }
  return out;
}

template <typename T>
void append_little_endian(std::string& out, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  }
  out.append(raw, sizeof(T));
}

// Doubles for the positions, so that nothing is rounded on the way out.
std::string format_ply(const Mesh& mesh) {
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by harmonia\n";
  out += "element vertex " + std::to_string(mesh.vertex_count()) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  out += "element face " + std::to_string(mesh.face_count()) + "\n";
  out += "property list uchar int vertex_indices\nend_header\n";
  out.reserve(out.size() + 24 * mesh.vertices.rows() + 13 * mesh.faces.rows());
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    for (int axis = 0; axis < 3; ++axis) append_little_endian(out, mesh.vertices(v, axis));
  }
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    append_little_endian(out, std::uint8_t{3});
    for (int corner = 0; corner < 3; ++corner) {
      append_little_endian(out, static_cast<std::int32_t>(mesh.faces(f, corner)));
    }
  }
  return out;
}

}  // namespace

void write_mesh(const std::filesystem::path& path, const Mesh& mesh) {
  const MeshFormat format = format_from_extension(path);
  check_mesh(path, mesh);
  switch (format) {
    case MeshFormat::obj: {
      std::string out;
      append_vertices(out, mesh.vertices);
      append_obj_faces(out, mesh.faces);
      detail::write_file_atomically(path, out);
      return;
    }
    case MeshFormat::off: detail::write_file_atomically(path, format_off(mesh)); return;
    case MeshFormat::ply: detail::write_file_atomically(path, format_ply(mesh)); return;
    case MeshFormat::gltf: write_gltf(path, GltfDocument::from_mesh(mesh), {}); return;
    case MeshFormat::stl: break;
  }
  throw Error(Status::io_error, path.string() +
                                    ": writing STL is not offered (use .obj, .off or "
                                    ".ply)");
}

namespace {

// The checks and the text of a map's OBJ, with an asset's parts kept when `kept` is given.
void write_layout_obj(const std::filesystem::path& path, const TexturedMesh& textured,
                      const detail::KeptAsset* kept) {
  check_mesh(path, textured.mesh);
  check_finite(path, textured.uv, "texture coordinate");
  if (textured.uv_faces.rows() != textured.mesh.faces.rows()) {
    refuse(path, "uv_faces has " + std::to_string(textured.uv_faces.rows()) +
                     " rows but the mesh has " + std::to_string(textured.mesh.faces.rows()) +
                     " faces");
  }
  check_indices(path, textured.uv_faces, textured.uv.rows(), "texture coordinate",
                "texture coordinates");
  std::string out;
  if (kept != nullptr) {
    detail::check_kept_asset(path, textured.mesh.faces.rows(), *kept);
    detail::append_material_libraries(out, kept->asset, path);
  }
  append_vertices(out, textured.mesh.vertices);
  append_texture_coordinates(out, textured.uv);
  if (kept != nullptr) detail::append_normals(out, kept->asset);
  detail::append_layout_faces(out, textured.mesh.faces, textured.uv_faces, kept, {});
  detail::write_file_atomically(path, out);
}

}  // namespace

void write_obj(const std::filesystem::path& path, const TexturedMesh& textured) {
  write_layout_obj(path, textured, nullptr);
}

void write_obj(const std::filesystem::path& path, const TexturedMesh& textured,
               const ObjAsset& asset, const Eigen::VectorXi& asset_face) {
  const detail::KeptAsset kept{asset, asset_face};
  write_layout_obj(path, textured, &kept);
}

void write_obj(const std::filesystem::path& path, const Mesh& mesh, const Eigen::MatrixX2d& uv) {
  if (uv.rows() != mesh.vertices.rows()) {
    refuse(path, "uv has " + std::to_string(uv.rows()) + " rows but the mesh has " +
                     std::to_string(mesh.vertices.rows()) + " vertices");
  }
  write_layout_obj(path, TexturedMesh{mesh, uv, mesh.faces}, nullptr);
}

void check_writable(const std::filesystem::path& path) { detail::check_writable(path); }

void remove_unfinished_outputs() noexcept { detail::remove_unfinished_outputs(); }

}  // namespace harmonia
