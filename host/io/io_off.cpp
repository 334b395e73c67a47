// Object File Format (OFF) reader. The header keyword may carry the prefixes of Geomview's variants
// (ST, C, N: texture coordinates, colours and normals after each vertex's position, all ignored)
// and may be left out; the counts `V F E` may follow it on the same line (even glued to it,
// "OFF8 6 12", as some writers do) or on a line of their own.
// Faces are `n i0 ... in-1` with 0-based indices, optionally followed by a colour (ignored).

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "harmonia/io.h"
#include "harmonia/types.h"
#include "io/io_support.h"
#include "io/mesh_parsers.h"
#include "io/text_scanner.h"
#include "mesh/mesh_builder.h"

namespace harmonia {
namespace {

using detail::TextScanner;

// The smallest a vertex line ("0 0 0\n") and a face line ("3 0 1 2\n") can be. Header counts whose
// lines could not fit in the file are rejected before any memory is reserved for them.
constexpr std::uint64_t min_vertex_bytes = 6;
constexpr std::uint64_t min_face_bytes = 8;

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Accepts "OFF" with any of the prefixes ST, C, N (in that order); 4OFF and nOFF are not 3D meshes.
bool is_off_keyword(std::string_view word) {
  if (word.size() < 3 || word.substr(word.size() - 3) != "OFF") return false;
  std::string_view prefix = word.substr(0, word.size() - 3);
  if (prefix.starts_with("ST")) prefix.remove_prefix(2);
  if (prefix.starts_with("C")) prefix.remove_prefix(1);
  if (prefix.starts_with("N")) prefix.remove_prefix(1);
  return prefix.empty();
}

std::int64_t read_count(TextScanner& scanner, std::string_view what) {
  const std::int64_t count = scanner.read_integer(what);
  if (count < 0) scanner.fail(std::string(what) + " is negative (" + std::to_string(count) + ")");
  return count;
}

}  // namespace

namespace detail {

Mesh parse_off(std::string_view text, std::string_view file_name) {
  const std::string name(file_name);
  TextScanner scanner(text, name);
  if (text.empty()) scanner.fail("the file is empty");
  if (!scanner.skip_empty_lines()) scanner.fail_at_end("no OFF header (only comments)");

  const std::string first = scanner.token_here();
  const bool has_keyword = !std::all_of(first.begin(), first.end(), is_digit);
  // The vertex count when a writer glued it to the keyword ("OFF8 6 12"), as trimesh reads it.
  std::optional<std::int64_t> glued_vertex_count;
  if (has_keyword) {
    std::string_view keyword = scanner.read_word();
    if (keyword.ends_with("4OFF") || keyword.ends_with("nOFF")) {
      scanner.fail("'" + first + "' files (4D or n-dimensional) are not supported");
    }
    if (const std::size_t off = keyword.find("OFF"); off != std::string_view::npos &&
                                                      off + 3 < keyword.size()) {
      const std::string_view digits = keyword.substr(off + 3);
      std::int64_t count = 0;
      const auto [stop, error] = std::from_chars(digits.data(), digits.data() + digits.size(), count);
      if (error == std::errc() && stop == digits.data() + digits.size()) {
        glued_vertex_count = count;
        keyword = keyword.substr(0, off + 3);
      }
    }
    if (!is_off_keyword(keyword)) {
      scanner.fail("expected the OFF header ('OFF', 'COFF', 'NOFF', ...), found '" + first + "'");
    }
    if (!glued_vertex_count && scanner.at_line_end() && !scanner.skip_empty_lines()) {
      scanner.fail_at_end("the file ends after the OFF header (truncated)");
    }
  }
  const std::int64_t vertex_count =
      glued_vertex_count ? *glued_vertex_count : read_count(scanner, "the vertex count");
  if (vertex_count < 0) scanner.fail("the vertex count is negative");
  const std::int64_t face_count = read_count(scanner, "the face count");
  if (!scanner.at_line_end()) read_count(scanner, "the edge count");  // Unused, but must be valid.
  scanner.expect_line_end("the counts 'vertices faces edges'");

  const std::uint64_t size = text.size();
  if (!detail::count_fits(vertex_count, min_vertex_bytes, size) ||
      !detail::count_fits(face_count, min_face_bytes, size) ||
      vertex_count > std::numeric_limits<int>::max()) {
    scanner.fail("the header claims " + std::to_string(vertex_count) + " vertices and " +
                 std::to_string(face_count) + " faces, more than a file of " +
                 std::to_string(size) + " bytes can hold");
  }
  if (face_count == 0) scanner.fail("no faces: the header declares 0 faces");
  scanner.next_line();

  detail::MeshBuilder builder;
  builder.reserve(static_cast<std::size_t>(vertex_count), static_cast<std::size_t>(face_count));
  for (std::int64_t vertex = 0; vertex < vertex_count; ++vertex) {
    if (!scanner.skip_empty_lines()) {
      scanner.fail_at_end("the file ends after " + std::to_string(vertex) + " of " +
                          std::to_string(vertex_count) + " vertices (truncated)");
    }
    const std::string label = "vertex " + std::to_string(vertex);
    double position[3];
    for (int axis = 0; axis < 3; ++axis) {
      const std::string coordinate = std::string(1, "xyz"[axis]) + " coordinate";
      position[axis] = scanner.read_double("the " + coordinate + " of " + label);
      if (!std::isfinite(position[axis])) scanner.fail(label + " has a non-finite " + coordinate);
    }
    scanner.skip_numbers("a normal, colour or texture value of " + label);
    builder.add_vertex(position[0], position[1], position[2]);
    scanner.next_line();
  }

  std::vector<int> corners;
  for (std::int64_t face = 0; face < face_count; ++face) {
    if (!scanner.skip_empty_lines()) {
      scanner.fail_at_end("the file ends after " + std::to_string(face) + " of " +
                          std::to_string(face_count) + " faces (truncated)");
    }
    const std::string label = "face " + std::to_string(face);
    const std::int64_t size_of_face = scanner.read_integer("the vertex count of " + label);
    if (size_of_face < 3) {
      scanner.fail(label + " has " + std::to_string(size_of_face) +
                   " vertices; a face needs at least 3");
    }
    corners.clear();
    for (std::int64_t corner = 0; corner < size_of_face; ++corner) {
      const std::int64_t index =
          scanner.read_integer("corner " + std::to_string(corner) + " of " + label);
      if (index < 0 || index >= vertex_count) {
        scanner.fail(label + ": vertex index " + std::to_string(index) + " (corner " +
                     std::to_string(corner) + ") is out of range: " + std::to_string(vertex_count) +
                     " vertices");
      }
      corners.push_back(static_cast<int>(index));
    }
    scanner.skip_numbers("a colour value of " + label);
    builder.add_polygon(corners);
    scanner.next_line();
  }
  return builder.build();
}

}  // namespace detail

Mesh read_off(const std::filesystem::path& path) {
  return detail::parse_off(detail::read_whole_file(path), path.string());
}

}  // namespace harmonia
