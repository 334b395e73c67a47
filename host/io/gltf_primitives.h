#pragma once
// A glTF mesh primitive's attributes and triangles, read through its accessors or, for a primitive
// compressed with KHR_draco_mesh_compression, from its decoded Draco data.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/gltf_accessors.h"
#include "io/gltf_contents.h"

namespace harmonia::detail {

// "meshes[M].primitives[P]".
[[nodiscard]] std::string primitive_path(int mesh, int primitive);

// meshes[mesh].primitives[primitive], checked to be an object with an attributes object.
[[nodiscard]] const nlohmann::json& primitive_object(const GltfContents& contents, int mesh,
                                                     int primitive);

// The primitive's vertex count: its POSITION accessor's, checked (before anything is allocated).
[[nodiscard]] std::int64_t vertex_count(const GltfContents& contents, int mesh, int primitive);

// The primitive's attribute `name` decoded, checked to have an element per vertex; null when it
// has none.
[[nodiscard]] std::shared_ptr<const AccessorData> primitive_attribute(
    const GltfContents& contents, int mesh, int primitive, const std::string& name);

// A morph target's attribute `name` decoded; null when the target has none.
[[nodiscard]] std::shared_ptr<const AccessorData> target_attribute(const GltfContents& contents,
                                                                   int mesh, int primitive,
                                                                   int target,
                                                                   const std::string& name);

// The primitive's mode (0..6; 4 when absent).
[[nodiscard]] int primitive_mode(const GltfContents& contents, int mesh, int primitive);

struct PrimitiveTriangles {
  int mode = 4;
  std::int64_t vertex_count = 0;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  // For each triangle, its number among the triangles the mode makes (glTF 2.0, section 3.7.2.1)
  // before the zero-area triangles that stitch strips and fans were left out.
  std::vector<int> source_triangle;
};

// The triangles of a primitive of mode 4, 5 or 6.
[[nodiscard]] PrimitiveTriangles primitive_triangles(const GltfContents& contents, int mesh,
                                                     int primitive);

// True for the modes that make triangles.
[[nodiscard]] constexpr bool makes_triangles(int mode) { return mode >= 4 && mode <= 6; }

}  // namespace harmonia::detail
