// A glTF document's triangles: the default scene's node hierarchy walked to place each mesh in
// world coordinates (glTF 2.0, section 3.5), and what `info` says about the document.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "harmonia/gltf.h"
#include "harmonia/types.h"
#include "io/gltf_primitives.h"
#include "io/io_support.h"

namespace harmonia {

using detail::GltfContents;

namespace {

struct MeshInstance {
  int mesh = 0;
  int node = -1;
  Eigen::Matrix4d world = Eigen::Matrix4d::Identity();
};

// A node's local matrix: `matrix` (column-major), or translation * rotation * scale.
Eigen::Matrix4d local_matrix(const GltfContents& contents, const nlohmann::json& node,
                             const std::string& path) {
  const auto numbers = [&](const char* key, std::size_t count) -> std::vector<double> {
    const auto found = node.find(key);
    if (found == node.end()) return {};
    if (!found->is_array() || found->size() != count) {
      contents.refuse(path + "." + key, "must be an array of " + std::to_string(count) + " numbers");
    }
    std::vector<double> values;
    for (const nlohmann::json& value : *found) {
      if (!value.is_number() || !std::isfinite(value.get<double>())) {
        contents.refuse(path + "." + key, "must hold finite numbers");
      }
      values.push_back(value.get<double>());
    }
    return values;
  };
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
  if (const std::vector<double> m = numbers("matrix", 16); !m.empty()) {
    for (int column = 0; column < 4; ++column)
      for (int row = 0; row < 4; ++row) matrix(row, column) = m[static_cast<std::size_t>(4 * column + row)];
    return matrix;
  }
  if (const std::vector<double> t = numbers("translation", 3); !t.empty()) {
    matrix.block<3, 1>(0, 3) = Eigen::Vector3d(t[0], t[1], t[2]);
  }
  Eigen::Matrix3d linear = Eigen::Matrix3d::Identity();
  if (const std::vector<double> r = numbers("rotation", 4); !r.empty()) {
    Eigen::Quaterniond rotation(r[3], r[0], r[1], r[2]);  // glTF stores x, y, z, w.
    if (rotation.norm() > 0.0) linear = rotation.normalized().toRotationMatrix();
  }
  if (const std::vector<double> s = numbers("scale", 3); !s.empty()) {
    linear = linear * Eigen::Vector3d(s[0], s[1], s[2]).asDiagonal();
  }
  matrix.block<3, 3>(0, 0) = linear;
  return matrix;
}

int default_scene(const GltfContents& contents) {
  const nlohmann::json& scenes = detail::top_array(contents, "scenes");
  if (scenes.empty()) return -1;
  const std::int64_t scene = detail::index_member(contents, contents.json, "scene", "", 0);
  (void)detail::element(contents, "scenes", scene, "scene");
  return static_cast<int>(scene);
}

// Every node of the default scene that places a mesh, with its world matrix, in the order of a
// depth-first walk from the scene's roots.
std::vector<MeshInstance> scene_instances(const GltfContents& contents) {
  std::vector<MeshInstance> instances;
  const int scene = default_scene(contents);
  if (scene < 0) return instances;
  const nlohmann::json& nodes = detail::top_array(contents, "nodes");
  std::vector<bool> reached(nodes.size(), false);
  const std::string scene_path = "scenes[" + std::to_string(scene) + "]";
  const nlohmann::json& scene_object = detail::element(contents, "scenes", scene, "scene");
  std::vector<std::pair<std::int64_t, Eigen::Matrix4d>> stack;
  if (const auto roots = scene_object.find("nodes"); roots != scene_object.end()) {
    if (!roots->is_array()) contents.refuse(scene_path + ".nodes", "must be an array");
    for (auto root = roots->rbegin(); root != roots->rend(); ++root) {
      if (!root->is_number_integer()) contents.refuse(scene_path + ".nodes", "must hold node indices");
      stack.emplace_back(root->get<std::int64_t>(), Eigen::Matrix4d::Identity());
    }
  }
  while (!stack.empty()) {
    const auto [index, parent] = stack.back();
    stack.pop_back();
    const std::string path = "nodes[" + std::to_string(index) + "]";
    const nlohmann::json& node = detail::element(contents, "nodes", index, scene_path + ".nodes");
    if (reached[static_cast<std::size_t>(index)]) {
      contents.refuse(path, "is reached twice from the scene (glTF nodes form trees)");
    }
    reached[static_cast<std::size_t>(index)] = true;
    const Eigen::Matrix4d world = parent * local_matrix(contents, node, path);
    if (const std::int64_t mesh = detail::index_member(contents, node, "mesh", path); mesh >= 0) {
      (void)detail::element(contents, "meshes", mesh, path + ".mesh");
      instances.push_back({static_cast<int>(mesh), static_cast<int>(index), world});
    }
    if (const auto children = node.find("children"); children != node.end()) {
      if (!children->is_array()) contents.refuse(path + ".children", "must be an array");
      for (auto child = children->rbegin(); child != children->rend(); ++child) {
        if (!child->is_number_integer() || child->get<std::int64_t>() < 0) {
          contents.refuse(path + ".children", "must hold node indices");
        }
        (void)detail::element(contents, "nodes", child->get<std::int64_t>(), path + ".children");
        stack.emplace_back(child->get<std::int64_t>(), world);
      }
    }
  }
  return instances;
}

int primitives_of(const GltfContents& contents, int mesh) {
  const nlohmann::json& object =
      detail::element(contents, "meshes", mesh, "meshes[" + std::to_string(mesh) + "]");
  const auto primitives = object.find("primitives");
  if (primitives == object.end() || !primitives->is_array()) {
    contents.refuse("meshes[" + std::to_string(mesh) + "].primitives", "missing");
  }
  return static_cast<int>(primitives->size());
}

// Appends one primitive placed by `instance` to `out`.
void append_primitive(const GltfContents& contents, const MeshInstance& instance, int primitive,
                      GltfTriangles& out, std::vector<Eigen::Vector3d>& positions,
                      std::vector<Eigen::Vector3i>& faces) {
  const int mode = detail::primitive_mode(contents, instance.mesh, primitive);
  if (mode == 0) {
    ++out.skipped_point_primitives;
    return;
  }
  if (!detail::makes_triangles(mode)) {
    ++out.skipped_line_primitives;
    return;
  }
  const detail::PrimitiveTriangles triangles =
      detail::primitive_triangles(contents, instance.mesh, primitive);
  const auto position =
      detail::primitive_attribute(contents, instance.mesh, primitive, "POSITION");
  const std::string path = detail::primitive_path(instance.mesh, primitive) + ".attributes.POSITION";
  if (position->rows != 3 || position->columns != 1) contents.refuse(path, "must be VEC3");
  GltfPart part;
  part.mesh = instance.mesh;
  part.primitive = primitive;
  part.node = instance.node;
  part.first_vertex = static_cast<int>(positions.size());
  part.vertex_count = static_cast<int>(position->count);
  part.first_face = static_cast<int>(faces.size());
  part.face_count = static_cast<int>(triangles.triangles.size());
  part.source_triangle = triangles.source_triangle;
  for (std::int64_t vertex = 0; vertex < position->count; ++vertex) {
    const Eigen::Vector4d local(position->value(vertex, 0), position->value(vertex, 1),
                                position->value(vertex, 2), 1.0);
    if (!local.allFinite()) {
      contents.refuse(path, "vertex " + std::to_string(vertex) + " is not finite");
    }
    positions.push_back((instance.world * local).head<3>());
  }
  // A mirroring transform turns the front faces to the back: reverse the winding (section 3.5.3).
  const bool mirrored = instance.world.block<3, 3>(0, 0).determinant() < 0.0;
  part.mirrored = mirrored;
  part.world = instance.world;
  for (const auto& triangle : triangles.triangles) {
    const Eigen::Vector3i corners(part.first_vertex + static_cast<int>(triangle[0]),
                                  part.first_vertex + static_cast<int>(triangle[1]),
                                  part.first_vertex + static_cast<int>(triangle[2]));
    faces.push_back(mirrored ? Eigen::Vector3i(corners[0], corners[2], corners[1]) : corners);
  }
  out.parts.push_back(std::move(part));
}

GltfTriangles gather(const GltfContents& contents, const std::vector<MeshInstance>& instances,
                     int only_primitive) {
  GltfTriangles out;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3i> faces;
  for (const MeshInstance& instance : instances) {
    const int count = primitives_of(contents, instance.mesh);
    for (int primitive = 0; primitive < count; ++primitive) {
      if (only_primitive >= 0 && primitive != only_primitive) continue;
      append_primitive(contents, instance, primitive, out, positions, faces);
    }
  }
  out.mesh.vertices.resize(static_cast<Eigen::Index>(positions.size()), 3);
  for (std::size_t v = 0; v < positions.size(); ++v) {
    out.mesh.vertices.row(static_cast<Eigen::Index>(v)) = positions[v].transpose();
  }
  out.mesh.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    out.mesh.faces.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
  }
  return out;
}

}  // namespace

GltfTriangles GltfDocument::scene_triangles() const {
  return detail::refusing_malformed_json(*contents_, [&] {
    const GltfContents& contents = *contents_;
    if (default_scene(contents) >= 0) return gather(contents, scene_instances(contents), -1);
    std::vector<MeshInstance> each_mesh;
    for (int mesh = 0; mesh < mesh_count(); ++mesh) {
      each_mesh.push_back({mesh, -1, Eigen::Matrix4d::Identity()});
    }
    return gather(contents, each_mesh, -1);
  });
}

GltfTriangles GltfDocument::mesh_triangles(int mesh, int primitive) const {
  return detail::refusing_malformed_json(*contents_, [&] {
    const GltfContents& contents = *contents_;
    (void)detail::element(contents, "meshes", mesh, "mesh " + std::to_string(mesh));
    MeshInstance placed{mesh, -1, Eigen::Matrix4d::Identity()};
    for (const MeshInstance& instance : scene_instances(contents)) {
      if (instance.mesh == mesh) {
        placed = instance;
        break;
      }
    }
    return gather(contents, {placed}, primitive);
  });
}

int GltfDocument::mesh_count() const {
  return static_cast<int>(detail::top_array(*contents_, "meshes").size());
}

int GltfDocument::primitive_count(int mesh) const {
  return detail::refusing_malformed_json(*contents_, [&] { return primitives_of(*contents_, mesh); });
}

int GltfDocument::texcoord_sets(int mesh, int primitive) const {
  return detail::refusing_malformed_json(*contents_, [&] {
    const nlohmann::json& attributes =
        detail::primitive_object(*contents_, mesh, primitive)["attributes"];
    int sets = 0;
    while (attributes.contains("TEXCOORD_" + std::to_string(sets))) ++sets;
    return sets;
  });
}

Eigen::MatrixX2d GltfDocument::texcoords(int mesh, int primitive, int set) const {
  return detail::refusing_malformed_json(*contents_, [&] {
    const std::string name = "TEXCOORD_" + std::to_string(set);
    const std::shared_ptr<const detail::AccessorData> data =
        detail::primitive_attribute(*contents_, mesh, primitive, name);
    if (!data) contents_->refuse(detail::primitive_path(mesh, primitive) + ".attributes", "has no " + name);
    if (data->type != "VEC2") {
      contents_->refuse(detail::primitive_path(mesh, primitive) + ".attributes." + name,
                        "is " + data->type + ", not VEC2");
    }
    Eigen::MatrixX2d uv(data->count, 2);
    for (std::int64_t v = 0; v < data->count; ++v) {
      uv(v, 0) = data->value(v, 0);
      uv(v, 1) = 1.0 - data->value(v, 1);  // glTF's v points down
    }
    return uv;
  });
}

Eigen::Matrix<double, Eigen::Dynamic, 6> corner_texcoords(const GltfDocument& document, const GltfTriangles& triangles,
                                                          int set) {
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv(triangles.mesh.faces.rows(), 6);
  for (const GltfPart& part : triangles.parts) {
    const Eigen::MatrixX2d uv = document.texcoords(part.mesh, part.primitive, set);
    for (int f = part.first_face; f < part.first_face + part.face_count; ++f) {
      for (int k = 0; k < 3; ++k) {
        // The part's vertices are the primitive's, in order, from first_vertex on.
        const int vertex = triangles.mesh.faces(f, k) - part.first_vertex;
        corner_uv(f, 2 * k) = uv(vertex, 0);
        corner_uv(f, 2 * k + 1) = uv(vertex, 1);
      }
    }
  }
  return corner_uv;
}

int GltfDocument::find_mesh(const std::string& name) const {
  return detail::refusing_malformed_json(*contents_, [&] {
    const nlohmann::json& meshes = detail::top_array(*contents_, "meshes");
    std::string known;
    for (std::size_t mesh = 0; mesh < meshes.size(); ++mesh) {
      const std::string mesh_name =
          meshes[mesh].is_object()
              ? detail::string_member(*contents_, meshes[mesh], "name", "meshes[" + std::to_string(mesh) + "]")
              : std::string();
      if (mesh_name == name) return static_cast<int>(mesh);
      if (mesh < 12) known += (known.empty() ? "" : ", ") + std::to_string(mesh) + (mesh_name.empty() ? "" : " '" + detail::printable(mesh_name, 30) + "'");
    }
    char* end = nullptr;
    const long index = std::strtol(name.c_str(), &end, 10);
    if (!name.empty() && *end == '\0' && index >= 0 && index < static_cast<long>(meshes.size())) {
      return static_cast<int>(index);
    }
    throw Error(Status::invalid_input,
                contents_->name + ": no mesh named or numbered '" + detail::printable(name, 40) +
                    "' (the file has " + std::to_string(meshes.size()) + " meshes" +
                    (known.empty() ? "" : ": " + known) + (meshes.size() > 12 ? ", ..." : "") + ")");
  });
}

GltfSummary GltfDocument::summary() const {
  return detail::refusing_malformed_json(*contents_, [&] {
    const GltfContents& contents = *contents_;
    GltfSummary summary;
    const auto strings = [&](const char* key) {
      std::vector<std::string> out;
      if (const auto found = contents.json.find(key); found != contents.json.end() && found->is_array()) {
        for (const nlohmann::json& value : *found)
          if (value.is_string()) out.push_back(value.get<std::string>());
      }
      return out;
    };
    summary.extensions_used = strings("extensionsUsed");
    summary.extensions_required = strings("extensionsRequired");
    summary.scenes = static_cast<int>(detail::top_array(contents, "scenes").size());
    summary.default_scene = default_scene(contents);
    summary.nodes = static_cast<int>(detail::top_array(contents, "nodes").size());
    summary.materials = static_cast<int>(detail::top_array(contents, "materials").size());
    summary.textures = static_cast<int>(detail::top_array(contents, "textures").size());
    summary.images = static_cast<int>(detail::top_array(contents, "images").size());
    summary.skins = static_cast<int>(detail::top_array(contents, "skins").size());
    summary.animations = static_cast<int>(detail::top_array(contents, "animations").size());
    const std::vector<MeshInstance> instances = scene_instances(contents);
    for (int mesh = 0; mesh < mesh_count(); ++mesh) {
      GltfMeshSummary mesh_summary;
      const nlohmann::json& object = detail::element(contents, "meshes", mesh, "meshes");
      mesh_summary.name = detail::string_member(contents, object, "name", "meshes[" + std::to_string(mesh) + "]");
      mesh_summary.instances = static_cast<int>(std::count_if(
          instances.begin(), instances.end(), [mesh](const MeshInstance& i) { return i.mesh == mesh; }));
      for (int primitive = 0; primitive < primitive_count(mesh); ++primitive) {
        const nlohmann::json& primitive_object = detail::primitive_object(contents, mesh, primitive);
        GltfPrimitiveSummary primitive_summary;
        primitive_summary.mode = detail::primitive_mode(contents, mesh, primitive);
        for (const auto& [name, accessor] : primitive_object["attributes"].items()) {
          primitive_summary.attributes.push_back(name);
        }
        if (const auto targets = primitive_object.find("targets"); targets != primitive_object.end() && targets->is_array()) {
          primitive_summary.morph_targets = static_cast<int>(targets->size());
        }
        primitive_summary.draco = contents.decoded_draco.count({mesh, primitive}) > 0;
        if (detail::makes_triangles(primitive_summary.mode)) {
          const detail::PrimitiveTriangles triangles = detail::primitive_triangles(contents, mesh, primitive);
          primitive_summary.vertices = static_cast<int>(triangles.vertex_count);
          primitive_summary.triangles = static_cast<int>(triangles.triangles.size());
        } else if (primitive_object["attributes"].contains("POSITION")) {
          const nlohmann::json& position = detail::element(
              contents, "accessors", detail::index_member(contents, primitive_object["attributes"], "POSITION", "attributes"),
              detail::primitive_path(mesh, primitive));
          primitive_summary.vertices = static_cast<int>(std::max<std::int64_t>(
              0, detail::index_member(contents, position, "count", detail::primitive_path(mesh, primitive))));
        }
        mesh_summary.primitives.push_back(std::move(primitive_summary));
      }
      summary.meshes.push_back(std::move(mesh_summary));
    }
    return summary;
  });
}

}  // namespace harmonia
