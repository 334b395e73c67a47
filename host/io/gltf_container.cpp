// The glTF container: a `.glb` file's chunks or a `.gltf` file's JSON text, its buffers (the GLB
// binary chunk, base64 data URIs, files beside the document) and its buffer views compressed with
// EXT_meshopt_compression, decoded once here so that every later reader sees plain bytes.
//
// The JSON is parsed with nlohmann/json. (Debian's tinygltf 2.7 was tried first: it refuses every
// EXT_meshopt_compression file, whose fallback buffer has a byteLength and no data.)

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <optional>
#include <cstring>
#include <string>

#include "harmonia/types.h"
#include "io/gltf_contents.h"
#include "io/io_support.h"

namespace harmonia::detail {

void GltfContents::refuse(std::string_view path, std::string_view problem) const {
  std::string message = name + ": ";
  if (!path.empty()) message += std::string(path) + ": ";
  throw Error(Status::parse_error, message + std::string(problem));
}

std::int64_t index_member(const GltfContents& contents, const nlohmann::json& object,
                          std::string_view key, std::string_view path, std::int64_t fallback) {
  const auto found = object.find(key);
  if (found == object.end()) return fallback;
  if (!found->is_number_integer() || found->get<std::int64_t>() < 0) {
    contents.refuse(std::string(path) + "." + std::string(key),
                    "must be an integer >= 0, not " + printable(found->dump(), 40));
  }
  return found->get<std::int64_t>();
}

std::string string_member(const GltfContents& contents, const nlohmann::json& object,
                          std::string_view key, std::string_view path, const std::string& fallback) {
  const auto found = object.find(key);
  if (found == object.end()) return fallback;
  if (!found->is_string()) {
    contents.refuse(std::string(path) + (path.empty() ? "" : ".") + std::string(key),
                    "must be a string, not " + printable(found->dump(), 40));
  }
  return found->get<std::string>();
}

bool bool_member(const GltfContents& contents, const nlohmann::json& object, std::string_view key,
                 std::string_view path, bool fallback) {
  const auto found = object.find(key);
  if (found == object.end()) return fallback;
  if (!found->is_boolean()) {
    contents.refuse(std::string(path) + (path.empty() ? "" : ".") + std::string(key),
                    "must be true or false, not " + printable(found->dump(), 40));
  }
  return found->get<bool>();
}

const nlohmann::json& top_array(const GltfContents& contents, std::string_view key) {
  static const nlohmann::json empty = nlohmann::json::array();
  const auto found = contents.json.find(key);
  if (found == contents.json.end()) return empty;
  if (!found->is_array()) contents.refuse(key, "must be an array");
  return *found;
}

const nlohmann::json& element(const GltfContents& contents, std::string_view key,
                              std::int64_t index, std::string_view path) {
  const nlohmann::json& array = top_array(contents, key);
  if (index < 0 || index >= static_cast<std::int64_t>(array.size())) {
    contents.refuse(path, "refers to " + std::string(key) + "[" + std::to_string(index) +
                              "], but the file has " + std::to_string(array.size()));
  }
  const nlohmann::json& object = array[static_cast<std::size_t>(index)];
  if (!object.is_object()) {
    contents.refuse(std::string(key) + "[" + std::to_string(index) + "]", "must be an object");
  }
  return object;
}

std::span<const std::uint8_t> GltfContents::view_bytes(int view, std::string_view path) const {
  if (const auto decoded = decoded_views.find(view); decoded != decoded_views.end()) {
    return decoded->second;
  }
  const std::string view_path = "bufferViews[" + std::to_string(view) + "]";
  const nlohmann::json& object = element(*this, "bufferViews", view, path);
  const std::int64_t buffer = index_member(*this, object, "buffer", view_path);
  if (buffer < 0) refuse(view_path, "has no buffer");
  const std::int64_t offset = index_member(*this, object, "byteOffset", view_path, 0);
  const std::int64_t length = index_member(*this, object, "byteLength", view_path);
  if (length < 0) refuse(view_path, "has no byteLength");
  (void)element(*this, "buffers", buffer, view_path + ".buffer");
  const Bytes& data = buffers[static_cast<std::size_t>(buffer)];
  if (static_cast<std::uint64_t>(offset) > data.size() ||
      static_cast<std::uint64_t>(length) > data.size() - static_cast<std::uint64_t>(offset)) {
    refuse(view_path, "bytes " + std::to_string(offset) + " to " + std::to_string(offset + length) +
                          " lie outside buffer " + std::to_string(buffer) + " (" +
                          std::to_string(data.size()) + " bytes)");
  }
  return {data.data() + offset, static_cast<std::size_t>(length)};
}

namespace {

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

// A relative URI's percent-escapes decoded ("my%20file.bin" -> "my file.bin").
std::string decoded_uri(std::string_view uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hex_digit(uri[i + 1]) >= 0 && hex_digit(uri[i + 2]) >= 0) {
      out.push_back(static_cast<char>(hex_digit(uri[i + 1]) * 16 + hex_digit(uri[i + 2])));
      i += 2;
    } else {
      out.push_back(uri[i]);
    }
  }
  return out;
}

namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;     // "JSON"
constexpr std::uint32_t kBinaryChunk = 0x004E4942;   // "BIN\0"

std::uint32_t read_u32(std::string_view bytes, std::size_t offset) {
  std::uint32_t value = 0;
  std::memcpy(&value, bytes.data() + offset, 4);
  return value;  // GLB is little-endian, as is every machine harmonia builds for.
}

struct Container {
  std::string_view json_text;
  std::optional<std::string_view> binary_chunk;
};

// Splits a GLB file into its JSON chunk and its optional binary chunk (glTF 2.0, section 4.4).
Container split_glb(std::string_view bytes, std::string_view name) {
  if (bytes.size() < 20) throw_at_byte(name, bytes.size(), "a GLB file is at least 20 bytes");
  if (const std::uint32_t version = read_u32(bytes, 4); version != 2) {
    throw_at_byte(name, 4, "GLB version " + std::to_string(version) + " (only 2 is glTF 2.0)");
  }
  const std::uint32_t length = read_u32(bytes, 8);
  if (length > bytes.size()) {
    throw_at_byte(name, 8, "the header says " + std::to_string(length) +
                               " bytes but the file has " + std::to_string(bytes.size()));
  }
  Container container;
  std::size_t offset = 12;
  int chunk = 0;
  while (offset + 8 <= length) {
    const std::uint32_t chunk_length = read_u32(bytes, offset);
    const std::uint32_t chunk_type = read_u32(bytes, offset + 4);
    if (chunk_length > length - offset - 8) {
      throw_at_byte(name, offset, "chunk " + std::to_string(chunk) + " of " +
                                      std::to_string(chunk_length) + " bytes runs past the end");
    }
    const std::string_view data = bytes.substr(offset + 8, chunk_length);
    if (chunk == 0) {
      if (chunk_type != kJsonChunk) throw_at_byte(name, offset, "the first chunk is not JSON");
      container.json_text = data;
    } else if (chunk == 1 && chunk_type == kBinaryChunk) {
      container.binary_chunk = data;
    }  // Chunks of other types are skipped, as the specification asks.
    offset += 8 + ((chunk_length + 3u) & ~3u);
    ++chunk;
  }
  if (chunk == 0) throw_at_byte(name, 12, "no JSON chunk");
  return container;
}

int base64_value(unsigned char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+' || c == '-') return 62;
  if (c == '/' || c == '_') return 63;
  return -1;
}

// Decodes base64 (RFC 4648, also the URL-safe alphabet; padding optional). Empty on bad input.
std::optional<Bytes> decode_base64(std::string_view text) {
  Bytes out;
  out.reserve(text.size() / 4 * 3);
  std::uint32_t bits = 0;
  int bit_count = 0;
  for (const char c : text) {
    if (c == '=') break;
    const int value = base64_value(static_cast<unsigned char>(c));
    if (value < 0) return std::nullopt;
    bits = (bits << 6) | static_cast<std::uint32_t>(value);
    bit_count += 6;
    if (bit_count >= 8) {
      bit_count -= 8;
      out.push_back(static_cast<std::uint8_t>((bits >> bit_count) & 0xFF));
    }
  }
  return out;
}



// The bytes a URI names: a base64 data URI, or a file relative to `folder`.
Bytes load_uri(const GltfContents& contents, std::string_view uri, std::string_view path,
               const std::filesystem::path& folder) {
  if (uri.starts_with("data:")) {
    const std::size_t marker = uri.find(";base64,");
    if (marker == std::string_view::npos) contents.refuse(path, "a data URI that is not base64");
    std::optional<Bytes> bytes = decode_base64(uri.substr(marker + 8));
    if (!bytes) contents.refuse(path, "a data URI with characters that are not base64");
    return std::move(*bytes);
  }
  if (uri.find("://") != std::string_view::npos) {
    contents.refuse(path, "refers to " + printable(uri, 60) +
                              ", which is not a file beside the document");
  }
  if (folder.empty()) contents.refuse(path, "refers to the file " + printable(uri, 60));
  const std::string file = read_whole_file(folder / decoded_uri(uri));
  return Bytes(file.begin(), file.end());
}

bool is_meshopt_fallback(const nlohmann::json& buffer) {
  const auto extensions = buffer.find("extensions");
  if (extensions == buffer.end() || !extensions->is_object()) return false;
  const auto meshopt = extensions->find("EXT_meshopt_compression");
  if (meshopt == extensions->end() || !meshopt->is_object()) return false;
  const auto fallback = meshopt->find("fallback");
  return fallback != meshopt->end() && fallback->is_boolean() && fallback->get<bool>();
}

void load_buffers(GltfContents& contents, const std::optional<std::string_view>& binary_chunk,
                  const std::filesystem::path& folder) {
  const nlohmann::json& buffers = top_array(contents, "buffers");
  contents.buffers.resize(buffers.size());
  for (std::size_t index = 0; index < buffers.size(); ++index) {
    const std::string path = "buffers[" + std::to_string(index) + "]";
    const nlohmann::json& buffer = buffers[index];
    if (!buffer.is_object()) contents.refuse(path, "must be an object");
    const std::int64_t length = index_member(contents, buffer, "byteLength", path);
    if (length < 1) contents.refuse(path, "needs a byteLength of at least 1");
    const auto uri = buffer.find("uri");
    Bytes data;
    if (uri != buffer.end()) {
      if (!uri->is_string()) contents.refuse(path + ".uri", "must be a string");
      data = load_uri(contents, uri->get<std::string>(), path + ".uri", folder);
    } else if (index == 0 && binary_chunk) {
      data.assign(binary_chunk->begin(), binary_chunk->end());
    } else if (is_meshopt_fallback(buffer)) {
      continue;  // No data: every view of it is compressed and decoded from another buffer.
    } else {
      contents.refuse(path, "has no uri and is not the GLB binary chunk");
    }
    if (static_cast<std::uint64_t>(length) > data.size()) {
      contents.refuse(path, "byteLength is " + std::to_string(length) + " but its data holds " +
                                std::to_string(data.size()) + " bytes");
    }
    contents.buffers[index] = std::move(data);
  }
}

// Decodes one buffer view compressed with EXT_meshopt_compression (its extension object
// `meshopt`) into `byteLength` bytes.
Bytes decode_meshopt_view(const GltfContents& contents, const nlohmann::json& meshopt,
                          std::int64_t byte_length, const std::string& path) {
  const std::string ext_path = path + ".extensions.EXT_meshopt_compression";
  if (!meshopt.is_object()) contents.refuse(ext_path, "must be an object");
  const std::int64_t buffer = index_member(contents, meshopt, "buffer", ext_path);
  const std::int64_t offset = index_member(contents, meshopt, "byteOffset", ext_path, 0);
  const std::int64_t length = index_member(contents, meshopt, "byteLength", ext_path);
  const std::int64_t stride = index_member(contents, meshopt, "byteStride", ext_path);
  const std::int64_t count = index_member(contents, meshopt, "count", ext_path);
  if (buffer < 0 || length < 0 || stride < 1 || count < 0) {
    contents.refuse(ext_path, "needs buffer, byteLength, byteStride and count");
  }
  (void)element(contents, "buffers", buffer, ext_path + ".buffer");
  const Bytes& source = contents.buffers[static_cast<std::size_t>(buffer)];
  if (static_cast<std::uint64_t>(offset) > source.size() ||
      static_cast<std::uint64_t>(length) > source.size() - static_cast<std::uint64_t>(offset)) {
    contents.refuse(ext_path, "its bytes lie outside buffer " + std::to_string(buffer));
  }
  if (count > byte_length / stride || count * stride != byte_length) {
    contents.refuse(ext_path, "count x byteStride (" + std::to_string(count) + " x " +
                                  std::to_string(stride) + ") is not the view's byteLength " +
                                  std::to_string(byte_length));
  }
  const std::string mode = string_member(contents, meshopt, "mode", ext_path);
  const std::string filter = string_member(contents, meshopt, "filter", ext_path, "NONE");
  Bytes out(static_cast<std::size_t>(byte_length));
  const unsigned char* data = source.data() + offset;
  const auto size_t_of = [](std::int64_t value) { return static_cast<std::size_t>(value); };
  int status = -1;
  if (mode == "ATTRIBUTES") {
    if (stride % 4 != 0 || stride > 256) contents.refuse(ext_path, "byteStride must be 4..256, a multiple of 4");
    status = meshopt_decodeVertexBuffer(out.data(), size_t_of(count), size_t_of(stride), data,
                                        size_t_of(length));
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) contents.refuse(ext_path, "byteStride must be 2 or 4");
    if (mode == "TRIANGLES" && count % 3 != 0) contents.refuse(ext_path, "count must be a multiple of 3");
    status = mode == "TRIANGLES"
                 ? meshopt_decodeIndexBuffer(out.data(), size_t_of(count), size_t_of(stride), data,
                                             size_t_of(length))
                 : meshopt_decodeIndexSequence(out.data(), size_t_of(count), size_t_of(stride),
                                               data, size_t_of(length));
  } else {
    contents.refuse(ext_path + ".mode", "unknown mode " + printable(mode, 30));
  }
  if (status != 0) {
    contents.refuse(ext_path, "meshoptimizer " + std::to_string(MESHOPTIMIZER_VERSION / 100) +
                                  "." + std::to_string(MESHOPTIMIZER_VERSION % 100) +
                                  " cannot decode this data (corrupt, or a newer encoding)");
  }
  if (filter == "OCTAHEDRAL") {
    if (stride != 4 && stride != 8) contents.refuse(ext_path, "OCTAHEDRAL needs byteStride 4 or 8");
    meshopt_decodeFilterOct(out.data(), size_t_of(count), size_t_of(stride));
  } else if (filter == "QUATERNION") {
    if (stride != 8) contents.refuse(ext_path, "QUATERNION needs byteStride 8");
    meshopt_decodeFilterQuat(out.data(), size_t_of(count), size_t_of(stride));
  } else if (filter == "EXPONENTIAL") {
    if (stride % 4 != 0) contents.refuse(ext_path, "EXPONENTIAL needs a byteStride multiple of 4");
    meshopt_decodeFilterExp(out.data(), size_t_of(count), size_t_of(stride));
  } else if (filter != "NONE") {
    contents.refuse(ext_path + ".filter", "unknown filter " + printable(filter, 30));
  }
  return out;
}

void decode_meshopt_views(GltfContents& contents) {
  const nlohmann::json& views = top_array(contents, "bufferViews");
  for (std::size_t index = 0; index < views.size(); ++index) {
    const std::string path = "bufferViews[" + std::to_string(index) + "]";
    const nlohmann::json& view = views[index];
    if (!view.is_object()) contents.refuse(path, "must be an object");
    const auto extensions = view.find("extensions");
    if (extensions == view.end() || !extensions->is_object()) continue;
    const auto meshopt = extensions->find("EXT_meshopt_compression");
    if (meshopt == extensions->end()) continue;
    const std::int64_t length = index_member(contents, view, "byteLength", path);
    contents.decoded_views[static_cast<int>(index)] =
        decode_meshopt_view(contents, *meshopt, length, path);
  }
}

// Refuses a required extension that harmonia cannot decode (the data could not be read right).
void check_required_extensions(const GltfContents& contents) {
  static constexpr std::array<std::string_view, 4> kDecoded = {
      "KHR_mesh_quantization", "EXT_meshopt_compression", "KHR_draco_mesh_compression",
      "KHR_texture_transform"};
  const auto required = contents.json.find("extensionsRequired");
  if (required == contents.json.end() || !required->is_array()) return;
  for (const nlohmann::json& name : *required) {
    if (!name.is_string()) continue;
    const std::string text = name.get<std::string>();
    // Extensions of textures, materials and lights do not change the geometry harmonia reads.
    const bool geometry = text.find("mesh") != std::string::npos ||
                          text.find("draco") != std::string::npos ||
                          text.find("meshopt") != std::string::npos;
    if (geometry && std::find(kDecoded.begin(), kDecoded.end(), text) == kDecoded.end()) {
      throw Error(Status::unsupported,
                  contents.name + ": requires the extension " + text + ", which harmonia cannot decode");
    }
  }
}

}  // namespace

GltfContents parse_gltf_container(std::string_view bytes, std::string_view name,
                                  const std::filesystem::path& folder) {
  GltfContents contents;
  contents.name = std::string(name);
  Container container;
  if (bytes.size() >= 4 && read_u32(bytes, 0) == kGlbMagic) {
    container = split_glb(bytes, name);
  } else {
    container.json_text = bytes;
  }
  try {
    contents.json = nlohmann::json::parse(container.json_text);
  } catch (const nlohmann::json::parse_error& error) {
    throw_at_byte(name, error.byte, "not valid JSON");
  } catch (const nlohmann::json::exception& error) {  // A number too large for a double, ...
    throw Error(Status::parse_error, std::string(name) + ": not valid JSON (" + error.what() + ")");
  }
  if (!contents.json.is_object()) contents.refuse("", "the document is not a JSON object");
  const auto asset = contents.json.find("asset");
  if (asset == contents.json.end() || !asset->is_object()) {
    contents.refuse("asset", "missing (every glTF file has one)");
  }
  const std::string version = string_member(contents, *asset, "version", "asset");
  if (!version.starts_with("2.")) {
    contents.refuse("asset.version", "is " + printable(version.empty() ? "missing" : version, 20) +
                                         "; harmonia reads glTF 2.x");
  }
  check_required_extensions(contents);
  load_buffers(contents, container.binary_chunk, folder);
  contents.input_bytes = bytes.size();
  for (const Bytes& buffer : contents.buffers) contents.input_bytes += buffer.size();
  decode_meshopt_views(contents);
  decode_draco_primitives(contents);
  return contents;
}

}  // namespace harmonia::detail
