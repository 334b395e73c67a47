// Reading a glTF primitive's attributes and triangles (glTF 2.0, section 3.7.2).

#include "io/gltf_primitives.h"

#include <numeric>

namespace harmonia::detail {

std::string primitive_path(int mesh, int primitive) {
  return "meshes[" + std::to_string(mesh) + "].primitives[" + std::to_string(primitive) + "]";
}

const nlohmann::json& primitive_object(const GltfContents& contents, int mesh, int primitive) {
  const std::string mesh_path = "meshes[" + std::to_string(mesh) + "]";
  const nlohmann::json& mesh_object = element(contents, "meshes", mesh, mesh_path);
  const auto primitives = mesh_object.find("primitives");
  if (primitives == mesh_object.end() || !primitives->is_array()) {
    contents.refuse(mesh_path + ".primitives", "missing (every mesh has an array of them)");
  }
  if (primitive < 0 || primitive >= static_cast<int>(primitives->size())) {
    contents.refuse(mesh_path, "has no primitive " + std::to_string(primitive));
  }
  const nlohmann::json& object = (*primitives)[static_cast<std::size_t>(primitive)];
  const std::string path = primitive_path(mesh, primitive);
  if (!object.is_object()) contents.refuse(path, "must be an object");
  const auto attributes = object.find("attributes");
  if (attributes == object.end() || !attributes->is_object()) {
    contents.refuse(path + ".attributes", "missing (every primitive has an attributes object)");
  }
  return object;
}

std::int64_t vertex_count(const GltfContents& contents, int mesh, int primitive) {
  const nlohmann::json& attributes = primitive_object(contents, mesh, primitive)["attributes"];
  const std::string path = primitive_path(mesh, primitive) + ".attributes";
  if (!attributes.contains("POSITION")) contents.refuse(path, "has no POSITION");
  return accessor_count(contents, index_member(contents, attributes, "POSITION", path), path + ".POSITION");
}

namespace {

// Every attribute of a vertex has one element per vertex (glTF 2.0, section 3.7.2.1).
std::shared_ptr<const AccessorData> one_per_vertex(const GltfContents& contents, int mesh, int primitive,
                                                   std::shared_ptr<const AccessorData> data,
                                                   const std::string& path) {
  const std::int64_t vertices = vertex_count(contents, mesh, primitive);
  if (data->count != vertices) {
    contents.refuse(path, "has " + std::to_string(data->count) + " elements, but POSITION has " +
                              std::to_string(vertices) + " (one per vertex)");
  }
  return data;
}

}  // namespace

std::shared_ptr<const AccessorData> primitive_attribute(const GltfContents& contents, int mesh,
                                                        int primitive, const std::string& name) {
  const nlohmann::json& object = primitive_object(contents, mesh, primitive);
  const nlohmann::json& attributes = object["attributes"];
  if (!attributes.contains(name)) return nullptr;
  if (const auto draco = contents.decoded_draco.find({mesh, primitive});
      draco != contents.decoded_draco.end()) {
    if (const auto found = draco->second.attributes.find(name);
        found != draco->second.attributes.end()) {
      return one_per_vertex(contents, mesh, primitive, found->second,
                            primitive_path(mesh, primitive) + ".attributes." + name);
    }
  }
  const std::string path = primitive_path(mesh, primitive) + ".attributes";
  return one_per_vertex(contents, mesh, primitive,
                        std::make_shared<AccessorData>(read_accessor(
                            contents, index_member(contents, attributes, name, path), path + "." + name)),
                        path + "." + name);
}

std::shared_ptr<const AccessorData> target_attribute(const GltfContents& contents, int mesh,
                                                     int primitive, int target,
                                                     const std::string& name) {
  const nlohmann::json& object = primitive_object(contents, mesh, primitive);
  const std::string path = primitive_path(mesh, primitive) + ".targets[" + std::to_string(target) + "]";
  const auto targets = object.find("targets");
  if (targets == object.end() || !targets->is_array() || target < 0 ||
      target >= static_cast<int>(targets->size())) {
    contents.refuse(path, "no such morph target");
  }
  const nlohmann::json& target_object = (*targets)[static_cast<std::size_t>(target)];
  if (!target_object.is_object()) contents.refuse(path, "must be an object");
  if (!target_object.contains(name)) return nullptr;
  return one_per_vertex(contents, mesh, primitive,
                        std::make_shared<AccessorData>(read_accessor(
                            contents, index_member(contents, target_object, name, path), path + "." + name)),
                        path + "." + name);
}

int primitive_mode(const GltfContents& contents, int mesh, int primitive) {
  const nlohmann::json& object = primitive_object(contents, mesh, primitive);
  const std::string path = primitive_path(mesh, primitive);
  const std::int64_t mode = index_member(contents, object, "mode", path, 4);
  if (mode > 6) contents.refuse(path + ".mode", "is " + std::to_string(mode) + " (0..6)");
  return static_cast<int>(mode);
}

PrimitiveTriangles primitive_triangles(const GltfContents& contents, int mesh, int primitive) {
  const nlohmann::json& object = primitive_object(contents, mesh, primitive);
  const std::string path = primitive_path(mesh, primitive);
  PrimitiveTriangles out;
  out.mode = primitive_mode(contents, mesh, primitive);
  const nlohmann::json& attributes = object["attributes"];
  if (!attributes.contains("POSITION")) contents.refuse(path + ".attributes", "has no POSITION");
  out.vertex_count = vertex_count(contents, mesh, primitive);

  std::vector<std::uint32_t> corners;
  const auto draco = contents.decoded_draco.find({mesh, primitive});
  if (draco != contents.decoded_draco.end()) {
    corners = draco->second.indices;
    for (const std::uint32_t index : corners) {
      if (index >= out.vertex_count) contents.refuse(path, "Draco index out of range");
    }
  } else if (const std::int64_t indices = index_member(contents, object, "indices", path);
             indices >= 0) {
    corners = read_indices(contents, indices, out.vertex_count, path + ".indices");
  } else {
    corners.resize(static_cast<std::size_t>(out.vertex_count));
    std::iota(corners.begin(), corners.end(), 0u);
  }

  const auto add = [&out](std::uint32_t a, std::uint32_t b, std::uint32_t c, int number,
                          bool drop_degenerate) {
    if (drop_degenerate && (a == b || b == c || a == c)) return;
    out.triangles.push_back({a, b, c});
    out.source_triangle.push_back(number);
  };
  const std::size_t n = corners.size();
  if (out.mode == 4) {
    if (n % 3 != 0) {
      contents.refuse(path, std::to_string(n) + " corners is not a whole number of triangles");
    }
    for (std::size_t t = 0; t < n / 3; ++t) {
      add(corners[3 * t], corners[3 * t + 1], corners[3 * t + 2], static_cast<int>(t), false);
    }
  } else if (out.mode == 5) {  // Strip: every other triangle reversed to keep one winding.
    for (std::size_t i = 0; i + 2 < n; ++i) {
      const std::size_t odd = i % 2;
      add(corners[i], corners[i + 1 + odd], corners[i + 2 - odd], static_cast<int>(i), true);
    }
  } else if (out.mode == 6) {  // Fan around the first corner.
    for (std::size_t i = 0; i + 2 < n; ++i) {
      add(corners[i + 1], corners[i + 2], corners[0], static_cast<int>(i), true);
    }
  }
  return out;
}

}  // namespace harmonia::detail
