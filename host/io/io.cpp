// Choosing a mesh format by file extension, and read_mesh (write_mesh is in io_write.cpp).

#include "harmonia/io.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "harmonia/gltf.h"
#include "harmonia/types.h"

namespace harmonia {

MeshFormat format_from_extension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".obj") return MeshFormat::obj;
  if (extension == ".off") return MeshFormat::off;
  if (extension == ".ply") return MeshFormat::ply;
  if (extension == ".stl") return MeshFormat::stl;
  if (extension == ".gltf" || extension == ".glb") return MeshFormat::gltf;
  throw Error(Status::io_error, path.string() + ": unknown mesh format '" + extension +
                                    "' (expected .obj, .off, .ply, .stl, .gltf or .glb)");
}

Mesh read_mesh(const std::filesystem::path& path) {
  switch (format_from_extension(path)) {
    case MeshFormat::obj: return read_obj(path);
    case MeshFormat::off: return read_off(path);
    case MeshFormat::ply: return read_ply(path);
    case MeshFormat::stl: return read_stl(path);
    case MeshFormat::gltf: return GltfDocument::read(path).scene_triangles().mesh;
  }
  throw Error(Status::io_error, path.string() + ": unknown mesh format");
}

}  // namespace harmonia
