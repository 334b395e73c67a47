// GltfDocument: reading a `.gltf` or `.glb` file into memory (io/gltf_container.cpp does the work).

#include <algorithm>
#include <cctype>
#include <cstring>

#include "harmonia/gltf.h"
#include "harmonia/types.h"
#include "io/gltf_contents.h"
#include "io/io_support.h"

namespace harmonia {

GltfDocument::GltfDocument(std::shared_ptr<const detail::GltfContents> contents)
    : contents_(std::move(contents)) {}

GltfDocument GltfDocument::read(const std::filesystem::path& path) {
  const std::string bytes = detail::read_whole_file(path);
  return parse(bytes, path.string(), path.parent_path().empty() ? "." : path.parent_path());
}

GltfDocument GltfDocument::parse(std::string_view bytes, std::string_view name,
                                 const std::filesystem::path& folder) {
  try {
    return GltfDocument(std::make_shared<const detail::GltfContents>(
        detail::parse_gltf_container(bytes, name, folder)));
  } catch (const nlohmann::json::exception& error) {  // A value of a kind no check expected.
    throw Error(Status::parse_error, std::string(name) + ": a JSON value of the wrong kind (" + error.what() + ")");
  }
}

GltfDocument GltfDocument::from_mesh(const Mesh& mesh, const std::string& name) {
  auto contents = std::make_shared<detail::GltfContents>();
  contents->name = name;
  const auto vertices = static_cast<std::size_t>(mesh.vertex_count());
  const auto corners = static_cast<std::size_t>(mesh.face_count()) * 3;
  detail::Bytes bytes(vertices * 12 + corners * 4);
  Eigen::Vector3d low = Eigen::Vector3d::Constant(0.0), high = low;
  for (std::size_t v = 0; v < vertices; ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      const float value = static_cast<float>(mesh.vertices(static_cast<Eigen::Index>(v), axis));
      std::memcpy(bytes.data() + v * 12 + axis * 4, &value, 4);
      low[axis] = v == 0 ? value : std::min<double>(low[axis], value);
      high[axis] = v == 0 ? value : std::max<double>(high[axis], value);
    }
  }
  for (std::size_t c = 0; c < corners; ++c) {
    const auto index = static_cast<std::uint32_t>(mesh.faces(static_cast<Eigen::Index>(c / 3), static_cast<int>(c % 3)));
    std::memcpy(bytes.data() + vertices * 12 + c * 4, &index, 4);
  }
  using nlohmann::json;
  json primitive = {{"attributes", {{"POSITION", 0}}}};
  json accessors = json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", vertices},
                                 {"type", "VEC3"}, {"min", {low[0], low[1], low[2]}},
                                 {"max", {high[0], high[1], high[2]}}}});
  json views = json::array({{{"buffer", 0}, {"byteLength", vertices * 12}, {"target", 34962}}});
  if (corners > 0) {
    primitive["indices"] = 1;
    accessors.push_back({{"bufferView", 1}, {"componentType", 5125}, {"count", corners}, {"type", "SCALAR"}});
    views.push_back({{"buffer", 0}, {"byteOffset", vertices * 12}, {"byteLength", corners * 4}, {"target", 34963}});
  }
  contents->json = {
      {"asset", {{"version", "2.0"}, {"generator", "harmonia"}}},
      {"scene", 0},
      {"scenes", json::array({{{"nodes", {0}}}})},
      {"nodes", json::array({{{"mesh", 0}}})},
      {"meshes", json::array({{{"primitives", json::array({primitive})}}})},
      {"accessors", std::move(accessors)},
      {"bufferViews", std::move(views)},
      {"buffers", json::array({{{"byteLength", bytes.size()}}})},
  };
  contents->buffers.push_back(std::move(bytes));
  return GltfDocument(std::move(contents));
}

const std::string& GltfDocument::name() const { return contents_->name; }

bool is_gltf_path(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".gltf" || extension == ".glb";
}

}  // namespace harmonia
