// Writing a glTF document with some primitives re-made (harmonia/gltf.h, write_gltf).
//
// The output is the input's JSON with three kinds of change and no other:
//   1. each updated primitive gets new accessors: every attribute and morph-target delta copied
//      through the new vertices' source map, new texture coordinates, positions or chart ids, and
//      new indices (widened only when the new vertex count needs it);
//   2. accessors and buffer views that only the replaced primitives used are dropped, and the
//      references to those that remain renumbered;
//   3. the binary data is laid out afresh as one buffer holding every remaining buffer view, each
//      on a 4-byte boundary: compressed views (EXT_meshopt_compression) are written decoded, and
//      the Draco data of rewritten primitives is gone with them.

#include <algorithm>
#include <cctype>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>

#include "harmonia/gltf.h"
#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "io/gltf_accessors.h"
#include "io/gltf_primitives.h"

namespace harmonia {

using detail::AccessorData;
using detail::Bytes;
using detail::GltfContents;
using nlohmann::json;

namespace {

constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;

[[noreturn]] void refuse(const std::filesystem::path& path, const std::string& problem) {
  throw Error(Status::invalid_input, path.string() + ": not written: " + problem);
}

std::size_t round_up_to_4(std::size_t bytes) { return (bytes + 3) / 4 * 4; }

// Extensions whose objects refer to no accessor, buffer view or buffer, or only to ones this
// writer renumbers itself. With any other extension in the file, nothing is dropped (an unknown
// extension may refer to what looks unused).
bool extension_is_understood(const std::string& name) {
  static const std::array<std::string_view, 7> kPrefixes = {
      "KHR_materials_", "KHR_texture_", "KHR_lights_", "EXT_texture_", "MSFT_texture_",
      "KHR_xmp", "EXT_lights_"};
  static const std::array<std::string_view, 4> kNames = {
      "KHR_mesh_quantization", "KHR_draco_mesh_compression", "EXT_meshopt_compression",
      "EXT_mesh_gpu_instancing"};
  for (const std::string_view prefix : kPrefixes)
    if (name.starts_with(prefix)) return true;
  return std::find(kNames.begin(), kNames.end(), name) != kNames.end();
}

// Visits every place of the document that refers to an accessor, and every one that refers to a
// buffer view, with a reference to the index there (so that a visitor can renumber it).
template <typename AccessorVisitor, typename ViewVisitor>
void visit_references(json& document, AccessorVisitor&& on_accessor, ViewVisitor&& on_view) {
  const auto visit_index = [](json& holder, const char* key, auto&& visitor) {
    if (holder.is_object()) {
      const auto found = holder.find(key);
      if (found != holder.end() && found->is_number_integer()) visitor(*found);
    }
  };
  const auto each = [&document](const char* key, auto&& visit) {
    const auto found = document.find(key);
    if (found == document.end() || !found->is_array()) return;
    for (json& item : *found)
      if (item.is_object()) visit(item);
  };
  each("meshes", [&](json& mesh) {
    const auto primitives = mesh.find("primitives");
    if (primitives == mesh.end() || !primitives->is_array()) return;
    for (json& primitive : *primitives) {
      if (!primitive.is_object()) continue;
      if (auto attributes = primitive.find("attributes"); attributes != primitive.end() && attributes->is_object()) {
        for (json& accessor : *attributes)
          if (accessor.is_number_integer()) on_accessor(accessor);
      }
      visit_index(primitive, "indices", on_accessor);
      if (auto targets = primitive.find("targets"); targets != primitive.end() && targets->is_array()) {
        for (json& target : *targets) {
          if (!target.is_object()) continue;
          for (json& accessor : target)
            if (accessor.is_number_integer()) on_accessor(accessor);
        }
      }
      if (auto extensions = primitive.find("extensions"); extensions != primitive.end() && extensions->is_object()) {
        if (auto draco = extensions->find("KHR_draco_mesh_compression"); draco != extensions->end()) {
          visit_index(*draco, "bufferView", on_view);
        }
      }
    }
  });
  each("skins", [&](json& skin) { visit_index(skin, "inverseBindMatrices", on_accessor); });
  each("animations", [&](json& animation) {
    const auto samplers = animation.find("samplers");
    if (samplers == animation.end() || !samplers->is_array()) return;
    for (json& sampler : *samplers) {
      visit_index(sampler, "input", on_accessor);
      visit_index(sampler, "output", on_accessor);
    }
  });
  each("nodes", [&](json& node) {
    const auto extensions = node.find("extensions");
    if (extensions == node.end() || !extensions->is_object()) return;
    const auto instancing = extensions->find("EXT_mesh_gpu_instancing");
    if (instancing == extensions->end() || !instancing->is_object()) return;
    if (auto attributes = instancing->find("attributes"); attributes != instancing->end() && attributes->is_object()) {
      for (json& accessor : *attributes)
        if (accessor.is_number_integer()) on_accessor(accessor);
    }
  });
  each("accessors", [&](json& accessor) {
    visit_index(accessor, "bufferView", on_view);
    if (auto sparse = accessor.find("sparse"); sparse != accessor.end() && sparse->is_object()) {
      if (auto indices = sparse->find("indices"); indices != sparse->end()) visit_index(*indices, "bufferView", on_view);
      if (auto values = sparse->find("values"); values != sparse->end()) visit_index(*values, "bufferView", on_view);
    }
  });
  each("images", [&](json& image) { visit_index(image, "bufferView", on_view); });
}

// Refuses a document that refers to an accessor or buffer view it does not have (the reader checks
// only what it reads: a skin's matrices or an image's view may still be out of range).
void check_references(const std::filesystem::path& path, const GltfContents& contents) {
  json document = contents.json;
  const auto count = [&](const char* key) {
    const auto found = document.find(key);
    return found != document.end() && found->is_array() ? static_cast<std::int64_t>(found->size()) : 0;
  };
  const std::int64_t accessors = count("accessors"), views = count("bufferViews");
  const auto check = [&](const json& index, std::int64_t size, const char* what) {
    const std::int64_t value = index.get<std::int64_t>();
    if (value < 0 || value >= size) {
      refuse(path, contents.name + " refers to " + what + " " + std::to_string(value) + ", but it has " +
                       std::to_string(size));
    }
  };
  visit_references(
      document, [&](json& index) { check(index, accessors, "accessor"); },
      [&](json& index) { check(index, views, "buffer view"); });
}

// The accessors and buffer views the document refers to (an accessor's views count only when the
// accessor itself is referred to).
struct Referenced {
  std::set<std::int64_t> accessors, views;
};

Referenced referenced(const json& document_in) {
  json document = document_in;  // visit_references hands out mutable references.
  Referenced out;
  visit_references(
      document, [&](json& index) { out.accessors.insert(index.get<std::int64_t>()); },
      [](json&) {});
  // Views: of the referenced accessors, of images and of Draco primitives.
  json only_used = document;
  if (auto accessors = only_used.find("accessors"); accessors != only_used.end() && accessors->is_array()) {
    for (std::size_t i = 0; i < accessors->size(); ++i)
      if (!out.accessors.count(static_cast<std::int64_t>(i))) (*accessors)[i] = json::object();
  }
  visit_references(only_used, [](json&) {},
                   [&](json& index) { out.views.insert(index.get<std::int64_t>()); });
  return out;
}

// A new accessor's data, with the layout it will have in its buffer view.
struct NewAccessor {
  json object;      // The accessor's JSON, "bufferView" still to be set.
  Bytes bytes;      // The buffer view's bytes.
  int byte_stride;  // 0: tightly packed; else the vertex stride (4-byte aligned elements).
  int target;       // ARRAY_BUFFER or ELEMENT_ARRAY_BUFFER.
};

// min and max of each component, as glTF writes them (raw values for integer components).
void set_bounds(json& object, const AccessorData& data, const Bytes& packed, int stride) {
  const int components = data.components();
  std::vector<double> low(static_cast<std::size_t>(components), std::numeric_limits<double>::infinity());
  std::vector<double> high(static_cast<std::size_t>(components), -std::numeric_limits<double>::infinity());
  AccessorData raw = data;
  raw.normalized = false;
  raw.data = packed;
  raw.element_size = stride;
  for (std::int64_t element = 0; element < raw.count; ++element) {
    for (int c = 0; c < components; ++c) {
      const double value = raw.value(element, c);
      low[static_cast<std::size_t>(c)] = std::min(low[static_cast<std::size_t>(c)], value);
      high[static_cast<std::size_t>(c)] = std::max(high[static_cast<std::size_t>(c)], value);
    }
  }
  const bool integral = data.component_type != detail::kFloat;
  json min = json::array(), max = json::array();
  for (int c = 0; c < components; ++c) {
    if (integral) {
      min.push_back(static_cast<std::int64_t>(low[static_cast<std::size_t>(c)]));
      max.push_back(static_cast<std::int64_t>(high[static_cast<std::size_t>(c)]));
    } else {
      min.push_back(low[static_cast<std::size_t>(c)]);
      max.push_back(high[static_cast<std::size_t>(c)]);
    }
  }
  object["min"] = std::move(min);
  object["max"] = std::move(max);
}

// `data` copied through `source` (new element i = data's element source[i]), as a vertex
// attribute: elements on 4-byte boundaries. `original` is the accessor JSON whose name, type and
// other members carry over.
NewAccessor gathered_attribute(const AccessorData& data, const json& original,
                               const std::vector<std::uint32_t>& source, bool needs_bounds) {
  NewAccessor out;
  const std::size_t stride = round_up_to_4(static_cast<std::size_t>(data.element_size));
  out.bytes.assign(stride * source.size(), 0);
  for (std::size_t i = 0; i < source.size(); ++i) {
    std::memcpy(out.bytes.data() + i * stride, data.data.data() + source[i] * data.element_size,
                static_cast<std::size_t>(data.element_size));
  }
  out.byte_stride = stride == static_cast<std::size_t>(data.element_size) ? 0 : static_cast<int>(stride);
  out.target = kArrayBuffer;
  out.object = original;
  for (const char* key : {"bufferView", "byteOffset", "sparse", "min", "max"}) out.object.erase(key);
  out.object["count"] = source.size();
  if (needs_bounds || original.contains("min") || original.contains("max")) {
    AccessorData shape = data;
    shape.count = static_cast<std::int64_t>(source.size());
    set_bounds(out.object, shape, out.bytes, static_cast<int>(stride));
  }
  return out;
}

// A float attribute of `columns` components per row, from doubles.
NewAccessor float_attribute(const Eigen::MatrixXd& values, const char* type, bool bounds) {
  NewAccessor out;
  const auto rows = static_cast<std::size_t>(values.rows());
  const auto columns = static_cast<std::size_t>(values.cols());
  out.bytes.resize(rows * columns * sizeof(float));
  for (std::size_t row = 0; row < rows; ++row) {
    for (std::size_t column = 0; column < columns; ++column) {
      const float value = static_cast<float>(values(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(column)));
      std::memcpy(out.bytes.data() + (row * columns + column) * sizeof(float), &value, sizeof value);
    }
  }
  out.byte_stride = 0;
  out.target = kArrayBuffer;
  out.object = {{"componentType", detail::kFloat}, {"count", rows}, {"type", type}};
  if (bounds) {
    AccessorData shape;
    shape.component_type = detail::kFloat;
    shape.rows = static_cast<int>(columns);
    shape.count = static_cast<std::int64_t>(rows);
    shape.element_size = static_cast<int>(columns * sizeof(float));
    set_bounds(out.object, shape, out.bytes, shape.element_size);
  }
  return out;
}

// Triangle indices in the narrowest of the input's own type and wider ones that holds them (a
// type's largest value is primitive restart in some APIs, so it is never used as an index). The
// input's type counts only where it is an index type: a Draco primitive's declared accessors are
// never read, so readers accept any type there and the output must not inherit it.
NewAccessor index_accessor(const GltfPrimitiveUpdate& update, int input_type,
                           std::size_t vertex_count) {
  const bool input_is_index_type = input_type == detail::kUnsignedByte ||
                                   input_type == detail::kUnsignedShort ||
                                   input_type == detail::kUnsignedInt;
  int type = input_is_index_type ? input_type : detail::kUnsignedShort;
  if (type == detail::kUnsignedByte && vertex_count > 255) type = detail::kUnsignedShort;
  if (type == detail::kUnsignedShort && vertex_count > 65535) type = detail::kUnsignedInt;
  const int size = detail::component_size(type);
  NewAccessor out;
  const auto count = static_cast<std::size_t>(update.triangles.size());
  out.bytes.resize(round_up_to_4(count * static_cast<std::size_t>(size)), 0);
  const std::uint32_t* indices = update.triangles.data();
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t index = indices[i];
    std::memcpy(out.bytes.data() + i * size, &index, static_cast<std::size_t>(size));  // Little-endian.
  }
  out.bytes.resize(count * static_cast<std::size_t>(size));
  out.byte_stride = 0;
  out.target = kElementArrayBuffer;
  out.object = {{"componentType", type}, {"count", count}, {"type", "SCALAR"}};
  return out;
}

void check_update(const std::filesystem::path& path, const GltfContents& contents,
                  const GltfPrimitiveUpdate& update) {
  const std::string where = detail::primitive_path(update.mesh, update.primitive);
  if (update.mesh < 0 || update.mesh >= static_cast<int>(detail::top_array(contents, "meshes").size())) {
    refuse(path, "an update names mesh " + std::to_string(update.mesh) + ", which the document lacks");
  }
  (void)detail::primitive_object(contents, update.mesh, update.primitive);
  if (!detail::makes_triangles(detail::primitive_mode(contents, update.mesh, update.primitive))) {
    refuse(path, where + " holds points or lines, not triangles");
  }
  const detail::PrimitiveTriangles triangles =
      detail::primitive_triangles(contents, update.mesh, update.primitive);
  const std::size_t count = update.source_vertex.size();
  for (std::size_t i = 0; i < count; ++i) {
    if (update.source_vertex[i] >= triangles.vertex_count) {
      refuse(path, where + ": new vertex " + std::to_string(i) + " copies vertex " +
                       std::to_string(update.source_vertex[i]) + ", but the primitive has " +
                       std::to_string(triangles.vertex_count));
    }
  }
  for (Eigen::Index t = 0; t < update.triangles.rows(); ++t) {
    for (int c = 0; c < 3; ++c) {
      if (update.triangles(t, c) >= count) {
        refuse(path, where + ": triangle " + std::to_string(t) + " refers to vertex " +
                         std::to_string(update.triangles(t, c)) + " of " + std::to_string(count));
      }
    }
  }
  const auto rows_fit = [&](Eigen::Index rows, const char* what) {
    if (rows != 0 && rows != static_cast<Eigen::Index>(count)) {
      refuse(path, where + ": " + what + " has " + std::to_string(rows) + " rows for " +
                       std::to_string(count) + " vertices");
    }
  };
  rows_fit(update.texcoord.rows(), "the texture coordinates");
  rows_fit(update.positions.rows(), "the positions");
  rows_fit(static_cast<Eigen::Index>(update.chart.size()), "the chart ids");
  rows_fit(static_cast<Eigen::Index>(update.page.size()), "the pages");
  if (!update.texcoord.allFinite() || !update.positions.allFinite()) {
    refuse(path, where + ": a texture coordinate or position is not finite");
  }
}

// The writer's state: the output JSON and the bytes of every output buffer view.
class GltfAssembly {
 public:
  GltfAssembly(const GltfContents& contents) : contents_(contents), document_(contents.json) {
    const std::size_t views = detail::top_array(contents, "bufferViews").size();
    view_source_.resize(views, -1);
    for (std::size_t v = 0; v < views; ++v) view_source_[v] = static_cast<std::int64_t>(v);
  }

  json& document() { return document_; }

  // Appends an accessor with its own new buffer view; returns the accessor's index.
  std::int64_t add(NewAccessor accessor) {
    json& views = array("bufferViews");
    json view = {{"buffer", 0}, {"byteLength", accessor.bytes.size()}, {"target", accessor.target}};
    if (accessor.byte_stride > 0) view["byteStride"] = accessor.byte_stride;
    views.push_back(std::move(view));
    view_source_.push_back(-1);
    new_view_bytes_[static_cast<std::int64_t>(views.size()) - 1] = std::move(accessor.bytes);
    accessor.object["bufferView"] = views.size() - 1;
    json& accessors = array("accessors");
    accessors.push_back(std::move(accessor.object));
    return static_cast<std::int64_t>(accessors.size()) - 1;
  }

  // Drops what the input referred to and the output no longer does, renumbering the rest.
  void drop_unused(const Referenced& before) {
    const Referenced after = referenced(document_);
    std::set<std::int64_t> dropped_accessors, dropped_views;
    for (const std::int64_t a : before.accessors)
      if (!after.accessors.count(a)) dropped_accessors.insert(a);
    // A view stays while anything left refers to it (an accessor the input did not use either).
    json probe = document_;
    if (auto accessors = probe.find("accessors"); accessors != probe.end() && accessors->is_array()) {
      for (const std::int64_t a : dropped_accessors) (*accessors)[static_cast<std::size_t>(a)] = json::object();
    }
    std::set<std::int64_t> still_viewed;
    visit_references(probe, [](json&) {}, [&](json& index) { still_viewed.insert(index.get<std::int64_t>()); });
    for (const std::int64_t v : before.views)
      if (!still_viewed.count(v)) dropped_views.insert(v);
    const auto renumber = [](json& array, const std::set<std::int64_t>& dropped) {
      std::vector<std::int64_t> new_index(array.size(), -1);
      json kept = json::array();
      for (std::size_t i = 0; i < array.size(); ++i) {
        if (dropped.count(static_cast<std::int64_t>(i))) continue;
        new_index[i] = static_cast<std::int64_t>(kept.size());
        kept.push_back(std::move(array[i]));
      }
      array = std::move(kept);
      return new_index;
    };
    const std::vector<std::int64_t> accessor_index = renumber(array("accessors"), dropped_accessors);
    const std::vector<std::int64_t> view_index = renumber(array("bufferViews"), dropped_views);
    std::vector<std::int64_t> kept_sources(array("bufferViews").size());
    std::map<std::int64_t, Bytes> kept_new;
    for (std::size_t old = 0; old < view_index.size(); ++old) {
      if (view_index[old] < 0) continue;
      kept_sources[static_cast<std::size_t>(view_index[old])] = view_source_[old];
      if (const auto found = new_view_bytes_.find(static_cast<std::int64_t>(old)); found != new_view_bytes_.end()) {
        kept_new[view_index[old]] = std::move(found->second);
      }
    }
    view_source_ = std::move(kept_sources);
    new_view_bytes_ = std::move(kept_new);
    visit_references(
        document_, [&](json& index) { index = accessor_index[index.get<std::size_t>()]; },
        [&](json& index) { index = view_index[index.get<std::size_t>()]; });
  }

  // Lays every buffer view out in one buffer; returns its bytes.
  Bytes pack_buffer() {
    Bytes buffer;
    json& views = array("bufferViews");
    for (std::size_t v = 0; v < views.size(); ++v) {
      std::span<const std::uint8_t> bytes;
      if (view_source_[v] >= 0) {
        bytes = contents_.view_bytes(static_cast<int>(view_source_[v]), "bufferViews");
      } else {
        const Bytes& made = new_view_bytes_.at(static_cast<std::int64_t>(v));
        bytes = {made.data(), made.size()};
      }
      buffer.resize(round_up_to_4(buffer.size()), 0);
      json& view = views[v];
      view["buffer"] = 0;
      if (buffer.empty()) view.erase("byteOffset"); else view["byteOffset"] = buffer.size();
      view["byteLength"] = bytes.size();
      if (auto extensions = view.find("extensions"); extensions != view.end() && extensions->is_object()) {
        extensions->erase("EXT_meshopt_compression");  // Written decoded.
        if (extensions->empty()) view.erase("extensions");
      }
      buffer.insert(buffer.end(), bytes.begin(), bytes.end());
    }
    buffer.resize(round_up_to_4(buffer.size()), 0);
    return buffer;
  }

 private:
  json& array(const char* key) {
    if (!document_.contains(key)) document_[key] = json::array();
    return document_[key];
  }

  const GltfContents& contents_;
  json document_;
  std::vector<std::int64_t> view_source_;       // Output view -> input view (-1: a new one).
  std::map<std::int64_t, Bytes> new_view_bytes_;  // Output view -> its bytes, for new views.
};

void remove_extension_if_unused(json& document, const std::string& name, bool used) {
  if (used) return;
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    const auto list = document.find(key);
    if (list == document.end() || !list->is_array()) continue;
    json kept = json::array();
    for (const json& item : *list)
      if (!(item.is_string() && item.get<std::string>() == name)) kept.push_back(item);
    if (kept.empty()) document.erase(key); else *list = std::move(kept);
  }
}

bool any_primitive_has_extension(const json& document, const char* name) {
  const auto meshes = document.find("meshes");
  if (meshes == document.end() || !meshes->is_array()) return false;
  for (const json& mesh : *meshes) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (const json& primitive : mesh["primitives"]) {
      if (primitive.is_object() && primitive.contains("extensions") && primitive["extensions"].is_object() &&
          primitive["extensions"].contains(name)) {
        return true;
      }
    }
  }
  return false;
}

// A relative path as a URI reference: every byte but the unreserved ones and '/' percent-encoded
// (RFC 3986), so that spaces, '#', '%' and non-ASCII names stay one relative path.
std::string uri_of(const std::string& relative) {
  static const char* kHex = "0123456789ABCDEF";
  std::string encoded;
  for (const char c : relative) {
    const auto byte = static_cast<unsigned char>(c);
    if (std::isalnum(byte) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      encoded += c;
    } else {
      encoded += '%';
      encoded += kHex[byte >> 4];
      encoded += kHex[byte & 15];
    }
  }
  return encoded;
}

// The files the input document names beside itself (external buffers and images), resolved.
std::vector<std::filesystem::path> files_referred_to(const GltfContents& contents) {
  std::vector<std::filesystem::path> files;
  const std::filesystem::path folder = std::filesystem::path(contents.name).parent_path();
  for (const char* key : {"buffers", "images"}) {
    const auto list = contents.json.find(key);
    if (list == contents.json.end() || !list->is_array()) continue;
    for (const json& item : *list) {
      if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
      const std::string uri = item["uri"].get<std::string>();
      if (uri.starts_with("data:") || uri.find("://") != std::string::npos) continue;
      std::error_code error;
      const std::filesystem::path file =
          std::filesystem::weakly_canonical((folder.empty() ? "." : folder) / detail::decoded_uri(uri), error);
      if (!error) files.push_back(file);
    }
  }
  return files;
}

// Image files named relative to the input stay reachable from the output's folder.
void rebase_image_uris(json& document, const std::filesystem::path& input_folder,
                       const std::filesystem::path& output_folder) {
  std::error_code error;
  const std::filesystem::path from = std::filesystem::weakly_canonical(input_folder, error);
  const std::filesystem::path to = std::filesystem::weakly_canonical(output_folder, error);
  if (error || from == to) return;
  const auto images = document.find("images");
  if (images == document.end() || !images->is_array()) return;
  for (json& image : *images) {
    if (!image.is_object() || !image.contains("uri") || !image["uri"].is_string()) continue;
    const std::string uri = image["uri"].get<std::string>();
    if (uri.starts_with("data:") || uri.find("://") != std::string::npos || uri.starts_with("/")) continue;
    std::string relative = std::filesystem::relative(from / uri, to, error).generic_string();
    if (error || relative.empty()) continue;
    image["uri"] = uri_of(relative);
  }
}

void append_u32(std::string& out, std::uint32_t value) {
  char bytes[4];
  std::memcpy(bytes, &value, 4);
  out.append(bytes, 4);
}

}  // namespace

int texcoord_set_for(const GltfDocument& document, int mesh, int primitive,
                     const GltfWriteOptions& options) {
  return detail::refusing_malformed_json(document.contents(), [&] {
    const int sets = document.texcoord_sets(mesh, primitive);
    const std::string where = document.name() + ": " + detail::primitive_path(mesh, primitive);
    const int chosen = options.texcoord < 0 ? sets : options.texcoord;
    if (chosen > sets) {
      throw Error(Status::invalid_input,
                  where + " has " + std::to_string(sets) + " texture-coordinate sets; TEXCOORD_" +
                      std::to_string(chosen) +
                      " would leave a gap (glTF numbers them from 0 without gaps)");
    }
    if (chosen < sets && !options.overwrite) {
      throw Error(Status::invalid_input,
                  where + " already has TEXCOORD_" + std::to_string(chosen) +
                      " (the overwrite option replaces it; by default the new set is TEXCOORD_" +
                      std::to_string(sets) + ")");
    }
    return chosen;
  });
}

void write_gltf(const std::filesystem::path& path, const GltfDocument& document,
                const std::vector<GltfPrimitiveUpdate>& updates, const GltfWriteOptions& options) {
  return detail::refusing_malformed_json(document.contents(), [&] {
    const GltfContents& contents = document.contents();
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension != ".glb" && extension != ".gltf") refuse(path, "a glTF file ends in .glb or .gltf");
    check_references(path, contents);
    std::set<std::pair<int, int>> updated;
    for (const GltfPrimitiveUpdate& update : updates) {
      check_update(path, contents, update);
      if (!updated.insert({update.mesh, update.primitive}).second) {
        refuse(path, detail::primitive_path(update.mesh, update.primitive) + " is updated twice");
      }
    }

    const Referenced before = referenced(contents.json);
    GltfAssembly assembly(contents);
    for (const GltfPrimitiveUpdate& update : updates) {
      const int mesh = update.mesh, primitive = update.primitive;
      const json& input_primitive = detail::primitive_object(contents, mesh, primitive);
      int set = -1;
      if (update.texcoord.rows() > 0) {
        try {
          set = texcoord_set_for(document, mesh, primitive, options);
        } catch (const Error& error) {
          refuse(path, error.what());
        }
      }
      const std::string texcoord_name = "TEXCOORD_" + std::to_string(set);
      json attributes = json::object();
      for (const auto& [name, accessor] : input_primitive["attributes"].items()) {
        if (name == texcoord_name || (name == "_CHART" && !update.chart.empty()) ||
            (name == "_PAGE" && !update.page.empty()))
          continue;
        if (name == "POSITION" && update.positions.rows() > 0) {
          attributes[name] = assembly.add(float_attribute(update.positions, "VEC3", true));
          continue;
        }
        const auto data = detail::primitive_attribute(contents, mesh, primitive, name);
        const json& original = detail::element(contents, "accessors", accessor.get<std::int64_t>(), "");
        attributes[name] = assembly.add(gathered_attribute(*data, original, update.source_vertex, name == "POSITION"));
      }
      if (set >= 0) {
        Eigen::MatrixXd flipped(update.texcoord.rows(), 2);
        flipped.col(0) = update.texcoord.col(0);
        flipped.col(1) = (1.0 - update.texcoord.col(1).array()).matrix();  // glTF's v points down.
        attributes[texcoord_name] = assembly.add(float_attribute(flipped, "VEC2", false));
      }
      if (!update.chart.empty()) {
        Eigen::MatrixXd charts(static_cast<Eigen::Index>(update.chart.size()), 1);
        for (std::size_t i = 0; i < update.chart.size(); ++i) charts(static_cast<Eigen::Index>(i), 0) = update.chart[i];
        attributes["_CHART"] = assembly.add(float_attribute(charts, "SCALAR", false));
      }
      if (!update.page.empty()) {
        Eigen::MatrixXd pages(static_cast<Eigen::Index>(update.page.size()), 1);
        for (std::size_t i = 0; i < update.page.size(); ++i) pages(static_cast<Eigen::Index>(i), 0) = update.page[i];
        attributes["_PAGE"] = assembly.add(float_attribute(pages, "SCALAR", false));
      }
      json output = input_primitive;
      output["attributes"] = std::move(attributes);
      if (auto targets = input_primitive.find("targets"); targets != input_primitive.end() && targets->is_array()) {
        json new_targets = json::array();
        for (std::size_t t = 0; t < targets->size(); ++t) {
          json new_target = json::object();
          for (const auto& [name, accessor] : (*targets)[t].items()) {
            const auto data = detail::target_attribute(contents, mesh, primitive, static_cast<int>(t), name);
            const json& original = detail::element(contents, "accessors", accessor.get<std::int64_t>(), "");
            new_target[name] = assembly.add(gathered_attribute(*data, original, update.source_vertex, name == "POSITION"));
          }
          new_targets.push_back(std::move(new_target));
        }
        output["targets"] = std::move(new_targets);
      }
      int input_index_type = 0;
      if (const auto indices = input_primitive.find("indices"); indices != input_primitive.end() && indices->is_number_integer()) {
        input_index_type = static_cast<int>(std::max<std::int64_t>(0, detail::index_member(
            contents, detail::element(contents, "accessors", indices->get<std::int64_t>(), ""), "componentType",
            detail::primitive_path(mesh, primitive) + ".indices")));
      }
      output["indices"] = assembly.add(index_accessor(update, input_index_type, update.source_vertex.size()));
      output.erase("mode");  // 4, triangles, is the default.
      if (auto extensions = output.find("extensions"); extensions != output.end() && extensions->is_object()) {
        extensions->erase("KHR_draco_mesh_compression");
        if (extensions->empty()) output.erase("extensions");
      }
      assembly.document()["meshes"][static_cast<std::size_t>(mesh)]["primitives"][static_cast<std::size_t>(primitive)] = std::move(output);
    }

    json& out = assembly.document();
    bool understood = true;
    if (const auto used = out.find("extensionsUsed"); used != out.end() && used->is_array()) {
      for (const json& name : *used)
        if (!name.is_string() || !extension_is_understood(name.get<std::string>())) understood = false;
    }
    if (understood) assembly.drop_unused(before);
    const Bytes buffer = assembly.pack_buffer();
    remove_extension_if_unused(out, "EXT_meshopt_compression", false);
    remove_extension_if_unused(out, "KHR_draco_mesh_compression",
                               any_primitive_has_extension(out, "KHR_draco_mesh_compression"));

    const bool binary = extension == ".glb";
    std::filesystem::path bin_path = path;
    bin_path.replace_extension(".bin");
    if (buffer.empty()) {
      out.erase("buffers");
    } else {
      json kept = json::object();
      if (const auto buffers = contents.json.find("buffers"); buffers != contents.json.end() && buffers->is_array() && !buffers->empty() && (*buffers)[0].is_object()) {
        for (const char* key : {"name", "extras"})
          if ((*buffers)[0].contains(key)) kept[key] = (*buffers)[0][key];
      }
      kept["byteLength"] = buffer.size();
      if (!binary) kept["uri"] = uri_of(bin_path.filename().string());
      out["buffers"] = json::array({kept});
    }
    const std::filesystem::path input_folder = std::filesystem::path(contents.name).parent_path();
    rebase_image_uris(out, input_folder.empty() ? "." : input_folder,
                      path.parent_path().empty() ? "." : path.parent_path());

    std::string text = out.dump();
    if (!binary && !buffer.empty()) {
      // OUT.bin must not replace a file the input needs (its own buffer when the input lies
      // beside OUT under that name), unless OUT is the input itself, rewritten in place.
      std::error_code error;
      const std::filesystem::path target = std::filesystem::weakly_canonical(bin_path, error);
      const bool in_place = std::filesystem::weakly_canonical(path, error) ==
                            std::filesystem::weakly_canonical(contents.name, error);
      for (const std::filesystem::path& file : files_referred_to(contents)) {
        if (file == target && !in_place) {
          refuse(path, "its binary data would go to " + bin_path.string() + ", a file " +
                           contents.name + " refers to; name the output otherwise");
        }
      }
    }
    if (!binary) {
      if (!buffer.empty()) {
        detail::write_file_atomically(bin_path, std::string_view(reinterpret_cast<const char*>(buffer.data()), buffer.size()));
      }
      detail::write_file_atomically(path, text);
      return;
    }
    text.resize(round_up_to_4(text.size()), ' ');
    std::string glb;
    const std::size_t total = 12 + 8 + text.size() + (buffer.empty() ? 0 : 8 + buffer.size());
    if (total > std::numeric_limits<std::uint32_t>::max()) refuse(path, "a GLB file holds at most 4 GiB");
    glb.reserve(total);
    append_u32(glb, 0x46546C67);
    append_u32(glb, 2);
    append_u32(glb, static_cast<std::uint32_t>(total));
    append_u32(glb, static_cast<std::uint32_t>(text.size()));
    append_u32(glb, 0x4E4F534A);
    glb += text;
    if (!buffer.empty()) {
      append_u32(glb, static_cast<std::uint32_t>(buffer.size()));
      append_u32(glb, 0x004E4942);
      glb.append(reinterpret_cast<const char*>(buffer.data()), buffer.size());
    }
    detail::write_file_atomically(path, glb);
  });
}

}  // namespace harmonia
