// Polygon File Format (PLY) reader: ascii, binary_little_endian and binary_big_endian. The vertex
// element must have scalar properties x, y, z (any numeric type); the face element must have a
// list property `vertex_indices` (or `vertex_index`) of any integer types. Every other property and
// element is read past and ignored. Element counts from the header are checked against the size of
// the file before anything is allocated for them.

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "harmonia/io.h"
#include "harmonia/types.h"
#include "io/binary_cursor.h"
#include "io/io_support.h"
#include "io/mesh_parsers.h"
#include "io/text_scanner.h"
#include "mesh/mesh_builder.h"

namespace harmonia {
namespace {

using detail::BinaryCursor;
using detail::TextScanner;

enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };
enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::float32;  // The item type for a list.
  bool is_list = false;
  PlyType count_type = PlyType::uint8;  // Lists only.
};

struct PlyElement {
  std::string name;
  std::int64_t count = 0;
  std::vector<PlyProperty> properties;
  std::int64_t line = 0;  // Header line of the "element" statement, for error messages.
};

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
};

std::optional<PlyType> type_from_name(std::string_view name) {
  if (name == "char" || name == "int8") return PlyType::int8;
  if (name == "uchar" || name == "uint8") return PlyType::uint8;
  if (name == "short" || name == "int16") return PlyType::int16;
  if (name == "ushort" || name == "uint16") return PlyType::uint16;
  if (name == "int" || name == "int32") return PlyType::int32;
  if (name == "uint" || name == "uint32") return PlyType::uint32;
  if (name == "float" || name == "float32") return PlyType::float32;
  if (name == "double" || name == "float64") return PlyType::float64;
  return std::nullopt;
}

std::uint64_t size_of(PlyType type) {
  switch (type) {
    case PlyType::int8:
    case PlyType::uint8: return 1;
    case PlyType::int16:
    case PlyType::uint16: return 2;
    case PlyType::int32:
    case PlyType::uint32:
    case PlyType::float32: return 4;
    case PlyType::float64: return 8;
  }
  return 8;
}

bool is_integer(PlyType type) { return type != PlyType::float32 && type != PlyType::float64; }

bool is_index_list(const PlyProperty& property) {
  return property.is_list && (property.name == "vertex_indices" || property.name == "vertex_index");
}

PlyType read_type(TextScanner& scanner) {
  const std::string found = scanner.token_here();
  const std::optional<PlyType> type = type_from_name(scanner.read_word());
  if (!type) scanner.fail("unknown property type '" + found + "'");
  return *type;
}

PlyHeader read_header(TextScanner& scanner) {
  const std::string found_first = scanner.token_here();
  if (scanner.read_word() != "ply") {
    scanner.fail("not a PLY file: the first line must be 'ply', found '" + found_first + "'");
  }
  scanner.expect_line_end("'ply'");
  PlyHeader header;
  bool has_format = false;
  for (;;) {
    scanner.next_line();
    if (!scanner.skip_empty_lines()) {
      scanner.fail_at_end("the file ends inside the header (truncated)");
    }
    const std::string found = scanner.token_here();
    const std::string_view keyword = scanner.read_word();
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") {
      scanner.expect_line_end("'end_header'");
      scanner.next_line();
      break;
    }
    if (keyword == "format") {
      const std::string format_found = scanner.token_here();
      const std::string_view format = scanner.read_word();
      if (format == "ascii")
        header.format = PlyFormat::ascii;
      else if (format == "binary_little_endian")
        header.format = PlyFormat::binary_little_endian;
      else if (format == "binary_big_endian")
        header.format = PlyFormat::binary_big_endian;
      else
        scanner.fail("unknown PLY format '" + format_found + "'");
      if (scanner.read_word() != "1.0") scanner.fail("unsupported PLY version (expected 1.0)");
      has_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      element.name = std::string(scanner.read_word());
      if (element.name.empty()) scanner.fail("an element needs a name");
      element.count = scanner.read_integer("the count of element '" + element.name + "'");
      if (element.count < 0) scanner.fail("element '" + element.name + "' has a negative count");
      element.line = scanner.line();
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) scanner.fail("a property before any element");
      PlyProperty property;
      if (scanner.token_here() == "list") {
        scanner.read_word();
        property.is_list = true;
        property.count_type = read_type(scanner);
        if (!is_integer(property.count_type))
          scanner.fail("a list count must have an integer type");
      }
      property.type = read_type(scanner);
      property.name = std::string(scanner.read_word());
      if (property.name.empty()) scanner.fail("a property needs a name");
      header.elements.back().properties.push_back(std::move(property));
    } else {
      scanner.fail("unknown header statement '" + found + "'");
    }
    scanner.expect_line_end("the '" + std::string(keyword) + "' statement");
  }
  if (!has_format) scanner.fail("the header has no 'format' line");
  return header;
}

// The fewest bytes one element can take: used to reject header counts the file cannot hold.
// A face's index list needs at least 3 entries, since smaller faces are errors anyway. An ASCII
// line needs only the values the reader takes from it (the rest may be missing, see AsciiValues),
// and at least a newline.
std::uint64_t min_element_bytes(const PlyElement& element, PlyFormat format) {
  std::uint64_t bytes = 0;
  for (const PlyProperty& property : element.properties) {
    const bool index_list = is_index_list(property) && element.name == "face";
    const std::uint64_t items = index_list ? 3 : 0;
    if (format == PlyFormat::ascii) {
      const bool coordinate = element.name == "vertex" && !property.is_list &&
                              (property.name == "x" || property.name == "y" || property.name == "z");
      if (coordinate || index_list) bytes += 2 * (1 + items);  // A digit and a separator per value.
    } else {
      bytes += property.is_list ? size_of(property.count_type) + items * size_of(property.type)
                                : size_of(property.type);
    }
  }
  return std::max<std::uint64_t>(bytes, 1);
}

// Values of an ASCII PLY: one element per line.
class AsciiValues {
 public:
  explicit AsciiValues(TextScanner& scanner) : scanner_(scanner) {}
  void begin(const std::string& element) {
    if (!scanner_.skip_empty_lines()) {
      scanner_.fail_at_end("the file ends before " + element + " (truncated)");
    }
  }
  double scalar(PlyType, const std::string& what) { return scanner_.read_double(what); }
  std::int64_t integer(PlyType, const std::string& what) { return scanner_.read_integer(what); }
  // A property the reader does not need. ASCII PLY keeps one element per line, and the readers
  // people use (trimesh, Blender) take what they need from each line and ignore the rest: a line
  // that ends before such a property, or holds values after the last one (MeshLab writes per-face
  // lists the header does not declare), is read all the same.
  void skip(const PlyProperty& property, const std::string& element) {
    if (scanner_.at_line_end()) return;
    if (!property.is_list) {
      scanner_.read_double("property '" + property.name + "' of " + element);
      return;
    }
    const std::int64_t count =
        scanner_.read_integer("the length of list '" + property.name + "' of " + element);
    for (std::int64_t k = 0; k < count && !scanner_.at_line_end(); ++k) {
      scanner_.read_double("entry " + std::to_string(k) + " of list '" + property.name + "' of " +
                           element);
    }
  }
  void end(const std::string&) { scanner_.next_line(); }
  void mark() {}
  [[noreturn]] void fail(std::string_view problem) const { scanner_.fail(problem); }

 private:
  TextScanner& scanner_;
};

// Values of a binary PLY in either byte order. Errors name the offset of the value being read.
class BinaryValues {
 public:
  explicit BinaryValues(BinaryCursor cursor) : cursor_(cursor) {}
  void begin(const std::string&) {}
  double scalar(PlyType type, const std::string& what) {
    mark();
    switch (type) {
      case PlyType::float32: return cursor_.read<float>(what);
      case PlyType::float64: return cursor_.read<double>(what);
      default: return static_cast<double>(integer(type, what));
    }
  }
  std::int64_t integer(PlyType type, const std::string& what) {
    mark();
    switch (type) {
      case PlyType::int8: return cursor_.read<std::int8_t>(what);
      case PlyType::uint8: return cursor_.read<std::uint8_t>(what);
      case PlyType::int16: return cursor_.read<std::int16_t>(what);
      case PlyType::uint16: return cursor_.read<std::uint16_t>(what);
      case PlyType::int32: return cursor_.read<std::int32_t>(what);
      case PlyType::uint32: return cursor_.read<std::uint32_t>(what);
      case PlyType::float32:
      case PlyType::float64: break;
    }
    fail(what + " must have an integer type");
  }
  void skip(const PlyProperty& property, const std::string& element) {
    const std::string what = "property '" + property.name + "' of " + element;
    if (!property.is_list) {
      cursor_.skip(size_of(property.type), what);
      return;
    }
    const std::int64_t count = integer(property.count_type, "the length of list " + what);
    if (count < 0) fail("list " + what + " has a negative length");
    if (!detail::count_fits(count, size_of(property.type), cursor_.remaining())) {
      fail("list " + what + " claims " + std::to_string(count) +
           " entries, more than the rest of the file holds (truncated?)");
    }
    cursor_.skip(static_cast<std::uint64_t>(count) * size_of(property.type), what);
  }
  void end(const std::string&) {}
  void mark() { value_offset_ = cursor_.offset(); }
  [[noreturn]] void fail(std::string_view problem) const {
    cursor_.fail_at(value_offset_, problem);
  }

 private:
  BinaryCursor cursor_;
  std::size_t value_offset_ = 0;
};

template <typename Values>
void read_vertex(Values& values, const PlyElement& element, int vertex, detail::MeshBuilder& mesh) {
  const std::string label = "vertex " + std::to_string(vertex);
  double position[3] = {0.0, 0.0, 0.0};
  values.begin(label);
  for (const PlyProperty& property : element.properties) {
    const bool is_coordinate = !property.is_list && property.name.size() == 1 &&
                               property.name[0] >= 'x' && property.name[0] <= 'z';
    if (!is_coordinate) {
      values.skip(property, label);
      continue;
    }
    const std::string coordinate = property.name + " coordinate";
    const double value = values.scalar(property.type, "the " + coordinate + " of " + label);
    if (!std::isfinite(value)) values.fail(label + " has a non-finite " + coordinate);
    position[property.name[0] - 'x'] = value;
  }
  values.end(label);
  mesh.add_vertex(position[0], position[1], position[2]);
}

template <typename Values>
void read_face(Values& values, const PlyElement& element, int face, std::int64_t vertex_count,
               std::vector<int>& corners, detail::MeshBuilder& mesh) {
  const std::string label = "face " + std::to_string(face);
  values.begin(label);
  for (const PlyProperty& property : element.properties) {
    if (!is_index_list(property)) {
      values.skip(property, label);
      continue;
    }
    const std::int64_t count = values.integer(property.count_type, "the vertex count of " + label);
    if (count < 3) {
      values.fail(label + " has " + std::to_string(count) + " vertices; a face needs at least 3");
    }
    corners.clear();
    for (std::int64_t corner = 0; corner < count; ++corner) {
      const std::int64_t index =
          values.integer(property.type, "corner " + std::to_string(corner) + " of " + label);
      if (index < 0 || index >= vertex_count) {
        values.fail(label + ": vertex index " + std::to_string(index) + " (corner " +
                    std::to_string(corner) + ") is out of range: " + std::to_string(vertex_count) +
                    " vertices");
      }
      corners.push_back(static_cast<int>(index));
    }
  }
  values.end(label);
  mesh.add_polygon(corners);
}

template <typename Values>
Mesh read_elements(Values& values, const PlyHeader& header, std::int64_t vertex_count,
                   std::int64_t face_count) {
  detail::MeshBuilder mesh;
  // The counts were checked against the file size, so this reservation is bounded by it.
  mesh.reserve(static_cast<std::size_t>(vertex_count), static_cast<std::size_t>(face_count));
  std::vector<int> corners;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex") {
      for (std::int64_t v = 0; v < element.count; ++v) {
        read_vertex(values, element, static_cast<int>(v), mesh);
      }
    } else if (element.name == "face") {
      for (std::int64_t f = 0; f < element.count; ++f) {
        read_face(values, element, static_cast<int>(f), vertex_count, corners, mesh);
      }
    } else {
      for (std::int64_t k = 0; k < element.count; ++k) {
        const std::string label = element.name + " " + std::to_string(k);
        values.begin(label);
        for (const PlyProperty& property : element.properties) values.skip(property, label);
        values.end(label);
      }
    }
  }
  return mesh.build();
}

}  // namespace

namespace detail {

Mesh parse_ply(std::string_view bytes, std::string_view file_name) {
  const std::string name(file_name);
  TextScanner scanner(bytes, name);
  if (bytes.empty()) scanner.fail("the file is empty");
  const PlyHeader header = read_header(scanner);

  // Check the header's claims before reading (and allocating for) any element.
  const std::uint64_t data_bytes = bytes.size() - scanner.offset();
  const PlyElement* vertices = nullptr;
  const PlyElement* faces = nullptr;
  for (const PlyElement& element : header.elements) {
    auto fail = [&](const std::string& problem) {
      detail::throw_at_line(name, element.line, "element '" + element.name + "': " + problem);
    };
    if ((element.name == "vertex" && vertices) || (element.name == "face" && faces)) {
      fail("declared twice");
    }
    if (element.name == "vertex") vertices = &element;
    if (element.name == "face") faces = &element;
    const std::uint64_t bytes_each = min_element_bytes(element, header.format);
    if (!detail::count_fits(element.count, bytes_each, data_bytes) ||
        element.count > std::numeric_limits<int>::max()) {
      fail("the header claims " + std::to_string(element.count) +
           " elements, more than the remaining " + std::to_string(data_bytes) +
           " bytes of the file can hold");
    }
    if (&element == vertices) {
      for (const char axis : {'x', 'y', 'z'}) {
        bool found = false;
        for (const PlyProperty& property : element.properties) {
          found = found || (!property.is_list && property.name == std::string(1, axis));
        }
        if (!found) fail(std::string("no scalar property '") + axis + "'");
      }
    }
    if (&element == faces) {
      int lists = 0;
      for (const PlyProperty& property : element.properties) {
        if (!is_index_list(property)) continue;
        ++lists;
        if (!is_integer(property.type)) fail("'" + property.name + "' must have integer entries");
      }
      if (lists != 1) fail("expected one list property 'vertex_indices' (or 'vertex_index')");
    }
  }
  if (vertices == nullptr) scanner.fail("no 'vertex' element in the header");
  if (faces == nullptr || faces->count == 0) {
    detail::throw_at_line(name, faces ? faces->line : scanner.line() - 1,
                          "no faces: the header declares none");
  }

  if (header.format == PlyFormat::ascii) {
    AsciiValues values(scanner);
    return read_elements(values, header, vertices->count, faces->count);
  }
  const std::endian order =
      header.format == PlyFormat::binary_little_endian ? std::endian::little : std::endian::big;
  BinaryValues values(BinaryCursor(bytes, scanner.offset(), order, name));
  return read_elements(values, header, vertices->count, faces->count);
}

}  // namespace detail

Mesh read_ply(const std::filesystem::path& path) {
  return detail::parse_ply(detail::read_whole_file(path), path.string());
}

}  // namespace harmonia
