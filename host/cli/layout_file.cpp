#include "cli/layout_file.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <vector>

#include "cli/common.h"
#include "harmonia/io.h"

namespace harmonia::cli {

namespace {

bool extension_is_obj(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".obj";
}

// True if the OBJ has at least one `vt` line; then its texture indices define the layout.
bool obj_has_texture_coordinates(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::string line;
  while (std::getline(file, line)) {
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line.compare(start, 2, "vt") != 0) continue;
    if (start + 2 < line.size() && (line[start + 2] == ' ' || line[start + 2] == '\t')) return true;
  }
  return false;
}

}  // namespace

Layout load_layout(const std::string& path) {
  if (extension_is_obj(path) && obj_has_texture_coordinates(path)) {
    try {
      TexturedMesh textured = read_textured_obj(path);
      return {std::move(textured.uv), std::move(textured.uv_faces)};
    } catch (const Error& failure) {
      const std::string message = failure.what();
      throw CliFailure(ExitCode::input,
                       message.find(path) == std::string::npos ? path + ": " + message : message);
    }
  }
  const Mesh flat = load_mesh(path);
  return {flat.vertices.leftCols<2>(), flat.faces};
}

void require_layout_of(const Mesh& mesh3d, const std::string& mesh_path, const Layout& layout,
                       const std::string& layout_path) {
  if (layout.uv_faces.rows() != mesh3d.faces.rows()) {
    throw CliFailure(ExitCode::input,
                     layout_path + " has " + std::to_string(layout.uv_faces.rows()) +
                         " faces but " + mesh_path + " has " + std::to_string(mesh3d.faces.rows()) +
                         "; they are not the same mesh");
  }
  std::vector<int> vertex_of_uv(layout.uv.rows(), -1);
  std::vector<int> first_face_of_uv(layout.uv.rows(), -1);
  for (int face = 0; face < mesh3d.face_count(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int uv_index = layout.uv_faces(face, corner);
      const int vertex = mesh3d.faces(face, corner);
      if (uv_index < 0 || uv_index >= layout.uv.rows()) {
        throw CliFailure(ExitCode::input, layout_path + ": face " + std::to_string(face) +
                                              " uses UV " + std::to_string(uv_index) +
                                              ", which does not exist");
      }
      if (vertex_of_uv[uv_index] < 0) {
        vertex_of_uv[uv_index] = vertex;
        first_face_of_uv[uv_index] = face;
      } else if (vertex_of_uv[uv_index] != vertex) {
        throw CliFailure(ExitCode::input,
                         "faces of " + layout_path + " do not match " + mesh_path + ": UV " +
                             std::to_string(uv_index) + " is 3D vertex " +
                             std::to_string(vertex_of_uv[uv_index]) + " in face " +
                             std::to_string(first_face_of_uv[uv_index]) + " but vertex " +
                             std::to_string(vertex) + " in face " + std::to_string(face));
      }
    }
  }
}

}  // namespace harmonia::cli
