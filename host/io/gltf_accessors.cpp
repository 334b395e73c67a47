// Decoding glTF accessors (glTF 2.0, sections 3.6 and 3.11) into dense arrays, every range checked.

#include "io/gltf_accessors.h"

#include <algorithm>
#include <cstring>

#include "io/io_support.h"

namespace harmonia::detail {

int component_size(int component_type) {
  switch (component_type) {
    case kByte:
    case kUnsignedByte: return 1;
    case kShort:
    case kUnsignedShort: return 2;
    case kUnsignedInt:
    case kFloat: return 4;
    default: return 0;
  }
}

namespace {

// The most bytes an accessor without a buffer view (zeros, perhaps with sparse values or Draco
// data) may make: 64 times the document's size (Draco compresses meshes some 10 to 30 times), at
// least 1 MiB and at most 256 MiB. A count beyond it is refused rather than allocated, so that a
// small file cannot make a large allocation.
std::int64_t most_bytes_without_view(const GltfContents& contents) {
  constexpr std::int64_t kLeast = std::int64_t{1} << 20, kMost = std::int64_t{1} << 28;
  return std::clamp(64 * static_cast<std::int64_t>(contents.input_bytes), kLeast, kMost);
}

// Rows and columns of an accessor type; {0, 0} for an unknown one.
std::pair<int, int> shape_of(const std::string& type) {
  if (type == "SCALAR") return {1, 1};
  if (type == "VEC2") return {2, 1};
  if (type == "VEC3") return {3, 1};
  if (type == "VEC4") return {4, 1};
  if (type == "MAT2") return {2, 2};
  if (type == "MAT3") return {3, 3};
  if (type == "MAT4") return {4, 4};
  return {0, 0};
}

// Bytes between a matrix's columns: each column starts on a 4-byte boundary (section 3.6.2.4).
int column_stride(int rows, int columns, int size) {
  return columns == 1 ? rows * size : (rows * size + 3) / 4 * 4;
}

template <typename T>
T load(const std::uint8_t* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof value);
  return value;
}

// Where a buffer view's elements lie: its bytes, and the distance between elements.
struct ViewLayout {
  std::span<const std::uint8_t> bytes;
  std::int64_t stride = 0;
  std::int64_t holds = 0;  // Whole elements from `offset` to the view's end.
};

ViewLayout view_layout(const GltfContents& contents, std::int64_t view, std::int64_t offset,
                       int element_size, bool vertex_stride_allowed, const std::string& path,
                       const std::string& what) {
  ViewLayout layout;
  layout.bytes = contents.view_bytes(static_cast<int>(view), path);
  const nlohmann::json& view_object = element(contents, "bufferViews", view, path);
  const std::string view_path = "bufferViews[" + std::to_string(view) + "]";
  layout.stride = index_member(contents, view_object, "byteStride", view_path, 0);
  if (layout.stride != 0 && !vertex_stride_allowed) layout.stride = 0;
  if (layout.stride != 0 && layout.stride < element_size) {
    contents.refuse(path, what + " elements are " + std::to_string(element_size) +
                              " bytes but buffer view " + std::to_string(view) +
                              " has byteStride " + std::to_string(layout.stride));
  }
  if (layout.stride == 0) layout.stride = element_size;
  const std::int64_t size = static_cast<std::int64_t>(layout.bytes.size());
  layout.holds = offset > size - element_size ? 0 : (size - offset - element_size) / layout.stride + 1;
  return layout;
}

// `count` elements of `element_size` bytes from a buffer view, `stride` apart from `offset`.
void copy_elements(const GltfContents& contents, std::int64_t view, std::int64_t offset,
                   std::int64_t count, int element_size, bool vertex_stride_allowed,
                   std::uint8_t* out, const std::string& path, const std::string& what) {
  const ViewLayout layout =
      view_layout(contents, view, offset, element_size, vertex_stride_allowed, path, what);
  if (count > layout.holds) {
    contents.refuse(path, what + " has " + std::to_string(count) + " elements, buffer view " +
                              std::to_string(view) + " holds " + std::to_string(layout.holds));
  }
  for (std::int64_t i = 0; i < count; ++i) {
    std::memcpy(out + i * element_size, layout.bytes.data() + offset + i * layout.stride,
                static_cast<std::size_t>(element_size));
  }
}

void apply_sparse(const GltfContents& contents, const nlohmann::json& sparse, AccessorData& data,
                  const std::string& path, const std::string& what) {
  const std::string sparse_what = what + " (sparse)";
  if (!sparse.is_object()) contents.refuse(path, sparse_what + " must be an object");
  const std::int64_t count = index_member(contents, sparse, "count", path);
  if (count < 1 || count > data.count) {
    contents.refuse(path, sparse_what + " count must be 1.." + std::to_string(data.count));
  }
  const auto indices = sparse.find("indices");
  const auto values = sparse.find("values");
  if (indices == sparse.end() || values == sparse.end() || !indices->is_object() ||
      !values->is_object()) {
    contents.refuse(path, sparse_what + " needs indices and values");
  }
  const int index_type = static_cast<int>(index_member(contents, *indices, "componentType", path));
  if (index_type != kUnsignedByte && index_type != kUnsignedShort && index_type != kUnsignedInt) {
    contents.refuse(path, sparse_what + " indices must be unsigned integers");
  }
  const int index_size = component_size(index_type);
  Bytes index_bytes(static_cast<std::size_t>(count * index_size));
  copy_elements(contents, index_member(contents, *indices, "bufferView", path),
                index_member(contents, *indices, "byteOffset", path, 0), count, index_size, false,
                index_bytes.data(), path, sparse_what + " indices");
  Bytes value_bytes(static_cast<std::size_t>(count * data.element_size));
  copy_elements(contents, index_member(contents, *values, "bufferView", path),
                index_member(contents, *values, "byteOffset", path, 0), count, data.element_size,
                false, value_bytes.data(), path, sparse_what + " values");
  std::int64_t previous = -1;
  for (std::int64_t k = 0; k < count; ++k) {
    const std::uint8_t* at = index_bytes.data() + k * index_size;
    const std::int64_t index = index_size == 1   ? *at
                               : index_size == 2 ? load<std::uint16_t>(at)
                                                 : load<std::uint32_t>(at);
    if (index >= data.count || index <= previous) {
      contents.refuse(path, sparse_what + " index " + std::to_string(index) + " at " +
                                std::to_string(k) + " is not increasing and below " +
                                std::to_string(data.count));
    }
    previous = index;
    std::memcpy(data.data.data() + index * data.element_size,
                value_bytes.data() + k * data.element_size,
                static_cast<std::size_t>(data.element_size));
  }
}

}  // namespace

int AccessorData::component_offset(int component) const {
  const int size = component_size(component_type);
  return component / rows * column_stride(rows, columns, size) + component % rows * size;
}

double AccessorData::value(std::int64_t element, int component) const {
  const std::uint8_t* at = data.data() + element * element_size + component_offset(component);
  switch (component_type) {
    case kFloat: return load<float>(at);
    case kUnsignedInt: return load<std::uint32_t>(at);
    case kByte: {
      const double raw = static_cast<std::int8_t>(*at);
      return normalized ? std::max(raw / 127.0, -1.0) : raw;
    }
    case kUnsignedByte: return normalized ? *at / 255.0 : *at;
    case kShort: {
      const double raw = load<std::int16_t>(at);
      return normalized ? std::max(raw / 32767.0, -1.0) : raw;
    }
    case kUnsignedShort: {
      const double raw = load<std::uint16_t>(at);
      return normalized ? raw / 65535.0 : raw;
    }
    default: return 0.0;
  }
}

namespace {

// An accessor's shape, every member checked and its count checked against the bytes it may use,
// before anything is allocated from it.
struct CheckedShape {
  AccessorData data;  // Without its bytes.
  std::int64_t view = -1, offset = 0;
};

CheckedShape checked_shape(const GltfContents& contents, std::int64_t accessor, const std::string& path) {
  const std::string what = "accessor " + std::to_string(accessor);
  const nlohmann::json& object = element(contents, "accessors", accessor, path);
  CheckedShape shape;
  AccessorData& data = shape.data;
  data.component_type = static_cast<int>(index_member(contents, object, "componentType", path));
  if (component_size(data.component_type) == 0) {
    contents.refuse(path, what + " has an unknown componentType " +
                              std::to_string(data.component_type));
  }
  data.type = string_member(contents, object, "type", path);
  std::tie(data.rows, data.columns) = shape_of(data.type);
  if (data.rows == 0) {
    contents.refuse(path, what + " has an unknown type " + printable(data.type, 20));
  }
  data.normalized = bool_member(contents, object, "normalized", path);
  data.count = index_member(contents, object, "count", path);
  if (data.count < 1) contents.refuse(path, what + " needs a count of at least 1");
  const int size = component_size(data.component_type);
  data.element_size = data.columns * column_stride(data.rows, data.columns, size);
  shape.view = index_member(contents, object, "bufferView", path);
  shape.offset = index_member(contents, object, "byteOffset", path, 0);
  // An absurd count in a file refers to bytes that are not there: refuse it before allocating.
  if (shape.view >= 0) {
    const std::int64_t holds =
        view_layout(contents, shape.view, shape.offset, data.element_size, true, path, what).holds;
    if (data.count > holds) {
      contents.refuse(path, what + " has " + std::to_string(data.count) + " elements, buffer view " +
                                std::to_string(shape.view) + " holds " + std::to_string(holds));
    }
  } else if (data.count > most_bytes_without_view(contents) / data.element_size) {
    contents.refuse(path, what + " has " + std::to_string(data.count) +
                              " elements and no buffer view (more than its file could describe)");
  }
  return shape;
}

}  // namespace

std::int64_t accessor_count(const GltfContents& contents, std::int64_t accessor, std::string_view path) {
  return checked_shape(contents, accessor, std::string(path)).data.count;
}

AccessorData read_accessor(const GltfContents& contents, std::int64_t accessor,
                           std::string_view path_view) {
  const std::string path(path_view);
  const std::string what = "accessor " + std::to_string(accessor);
  CheckedShape shape = checked_shape(contents, accessor, path);
  AccessorData& data = shape.data;
  data.data.assign(static_cast<std::size_t>(data.count * data.element_size), 0);
  if (shape.view >= 0) {
    copy_elements(contents, shape.view, shape.offset, data.count, data.element_size, true,
                  data.data.data(), path, what);
  }
  const nlohmann::json& object = element(contents, "accessors", accessor, path);
  if (const auto sparse = object.find("sparse"); sparse != object.end()) {
    apply_sparse(contents, *sparse, data, path, what);
  }
  return std::move(data);
}

std::vector<std::uint32_t> read_indices(const GltfContents& contents, std::int64_t accessor,
                                        std::int64_t vertex_count, std::string_view path_view) {
  const std::string path(path_view);
  const AccessorData data = read_accessor(contents, accessor, path);
  if (data.rows != 1 || data.columns != 1 ||
      (data.component_type != kUnsignedByte && data.component_type != kUnsignedShort &&
       data.component_type != kUnsignedInt)) {
    contents.refuse(path, "accessor " + std::to_string(accessor) +
                              " must hold unsigned integer scalars to be indices");
  }
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(data.count));
  for (std::int64_t i = 0; i < data.count; ++i) {
    const std::uint8_t* at = data.data.data() + i * data.element_size;
    const std::uint32_t index = data.element_size == 1   ? *at
                                : data.element_size == 2 ? load<std::uint16_t>(at)
                                                         : load<std::uint32_t>(at);
    if (index >= vertex_count) {
      contents.refuse(path, "index " + std::to_string(i) + " of accessor " +
                                std::to_string(accessor) + " is " + std::to_string(index) +
                                ", but the primitive has " + std::to_string(vertex_count) +
                                " vertices");
    }
    indices[static_cast<std::size_t>(i)] = index;
  }
  return indices;
}

}  // namespace harmonia::detail
