#pragma once
// glTF accessors decoded into dense arrays: byte strides removed, sparse substitutions applied,
// an accessor without a buffer view read as zeros (glTF 2.0, section 3.6). Every range is checked,
// and a problem is refused with the JSON path of whatever asked for the accessor.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/gltf_contents.h"

namespace harmonia::detail {

// glTF's component types (the OpenGL enums).
enum GltfComponentType : int {
  kByte = 5120,
  kUnsignedByte = 5121,
  kShort = 5122,
  kUnsignedShort = 5123,
  kUnsignedInt = 5125,
  kFloat = 5126,
};

[[nodiscard]] int component_size(int component_type);

struct AccessorData {
  int component_type = kFloat;
  std::string type;        // SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3, MAT4.
  bool normalized = false;
  int rows = 1;            // Components per column (the vector size for SCALAR/VECn).
  int columns = 1;         // 1 except for matrices.
  std::int64_t count = 0;
  int element_size = 0;    // Bytes per element, with glTF's 4-byte column alignment for matrices.
  Bytes data;              // count x element_size bytes, elements packed one after another.

  [[nodiscard]] int components() const { return rows * columns; }
  // Byte offset of component `component` (column-major) inside an element.
  [[nodiscard]] int component_offset(int component) const;
  // Component `component` of element `element` as a number: normalized integers mapped to
  // [-1, 1] or [0, 1] as glTF 2.0 section 3.11 says, other integers as they are.
  [[nodiscard]] double value(std::int64_t element, int component) const;
};

// Reads accessors[accessor]; `path` names what refers to it (for messages).
[[nodiscard]] AccessorData read_accessor(const GltfContents& contents, std::int64_t accessor,
                                         std::string_view path);

// An accessor's element count, after every check read_accessor makes before it reads the bytes.
[[nodiscard]] std::int64_t accessor_count(const GltfContents& contents, std::int64_t accessor,
                                          std::string_view path);

// Reads an index accessor (unsigned byte, short or int scalars), each index checked to be below
// `vertex_count`.
[[nodiscard]] std::vector<std::uint32_t> read_indices(const GltfContents& contents,
                                                      std::int64_t accessor,
                                                      std::int64_t vertex_count,
                                                      std::string_view path);

}  // namespace harmonia::detail
