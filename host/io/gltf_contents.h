#pragma once
// What a GltfDocument holds (harmonia/gltf.h): the document's JSON as read, and its binary data
// decoded, with the checked access every reader and the writer go through.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace harmonia::detail {

using Bytes = std::vector<std::uint8_t>;
struct AccessorData;

// A primitive compressed with KHR_draco_mesh_compression, decoded: its attributes (by glTF name,
// in the types their accessors declare) and its triangle indices.
struct DracoPrimitive {
  std::map<std::string, std::shared_ptr<const AccessorData>> attributes;
  std::vector<std::uint32_t> indices;
};

struct GltfContents {
  std::string name;     // The file name messages use.
  std::size_t input_bytes = 0;  // The document's size with its buffers (bounds what it may make).
  nlohmann::json json;  // The document as read.
  // Every buffer's bytes (at least its byteLength), except a buffer that is only the fallback of
  // EXT_meshopt_compression (empty).
  std::vector<Bytes> buffers;
  // Buffer views compressed with EXT_meshopt_compression, decoded (byteLength bytes each).
  std::map<int, Bytes> decoded_views;
  // Primitives compressed with KHR_draco_mesh_compression, decoded, by (mesh, primitive).
  std::map<std::pair<int, int>, DracoPrimitive> decoded_draco;

  // The bytes of buffer view `view` (decoded when it was compressed). `path` names what asked,
  // for the message when the view is out of range.
  [[nodiscard]] std::span<const std::uint8_t> view_bytes(int view, std::string_view path) const;
  // Throws Error(parse_error, "NAME: PATH: problem").
  [[noreturn]] void refuse(std::string_view path, std::string_view problem) const;
};

// JSON helpers that refuse a missing or mistyped member with its path.
// The object's member `key` as an integer >= 0, or `fallback` when absent.
[[nodiscard]] std::int64_t index_member(const GltfContents& contents, const nlohmann::json& object,
                                        std::string_view key, std::string_view path,
                                        std::int64_t fallback = -1);
// The object's member `key` as a string or a boolean, or `fallback` when absent; refused with its
// path when it has another type.
[[nodiscard]] std::string string_member(const GltfContents& contents, const nlohmann::json& object,
                                        std::string_view key, std::string_view path,
                                        const std::string& fallback = {});
[[nodiscard]] bool bool_member(const GltfContents& contents, const nlohmann::json& object,
                               std::string_view key, std::string_view path, bool fallback = false);
// Runs `work`, refusing any JSON value of an unexpected kind that it met as a parse error of the
// document (the checked helpers above name the path; this is the net under everything else).
template <typename Work>
auto refusing_malformed_json(const GltfContents& contents, Work&& work) -> decltype(work()) {
  try {
    return work();
  } catch (const nlohmann::json::exception& error) {
    contents.refuse("", std::string("a JSON value of the wrong kind (") + error.what() + ")");
  }
}
// The array `key` of the document (an empty array when absent).
[[nodiscard]] const nlohmann::json& top_array(const GltfContents& contents, std::string_view key);
// top_array(key)[index], refused with `path` when out of range.
[[nodiscard]] const nlohmann::json& element(const GltfContents& contents, std::string_view key,
                                            std::int64_t index, std::string_view path);

// A relative URI's percent-escapes decoded ("my%20file.bin" -> "my file.bin").
[[nodiscard]] std::string decoded_uri(std::string_view uri);

// Decodes every primitive compressed with KHR_draco_mesh_compression (io/gltf_draco.cpp).
void decode_draco_primitives(GltfContents& contents);

// Parses the container: GLB chunks or JSON text, the buffers (GLB binary chunk, base64 data URIs,
// files beside the document) and the meshopt-compressed buffer views.
[[nodiscard]] GltfContents parse_gltf_container(std::string_view bytes, std::string_view name,
                                                const std::filesystem::path& folder);

}  // namespace harmonia::detail
