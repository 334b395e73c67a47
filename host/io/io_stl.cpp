// STereoLithography (STL) reader, ASCII and binary. STL stores every triangle with its own three
// corner positions; corners at exactly the same position are merged into one vertex so that the
// result is an indexed mesh. Vertices are numbered in the order of their first appearance.
//
// A file is binary when its size is exactly 84 + 50 * (the triangle count at byte 80), whatever its
// first bytes say (some binary exporters start the header with "solid"); otherwise a file starting
// with "solid" is ASCII, and anything else is treated as binary and must pass the size check.

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <limits>
#include <numeric>
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

constexpr std::uint64_t binary_header_bytes = 84;    // 80 free bytes + uint32 triangle count.
constexpr std::uint64_t binary_triangle_bytes = 50;  // normal, 3 corners (12 float32), uint16.

using Position = std::array<double, 3>;

// Merges corners with identical positions. `corners` holds 3 positions per triangle. Sorting the
// corner numbers by position (ties by corner number) groups equal positions deterministically.
Mesh merge_corners(const std::vector<Position>& corners) {
  std::vector<int> order(corners.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return corners[a] != corners[b] ? corners[a] < corners[b] : a < b;
  });
  // first_corner[c]: the earliest corner at the same position as corner c.
  std::vector<int> first_corner(corners.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const bool starts_group = k == 0 || corners[order[k]] != corners[order[k - 1]];
    first_corner[order[k]] = starts_group ? order[k] : first_corner[order[k - 1]];
  }
  // Walking the corners in file order numbers the vertices by first appearance.
  std::vector<int> vertex_of_corner(corners.size(), -1);
  detail::MeshBuilder mesh;
  mesh.reserve(corners.size() / 2, corners.size() / 3);  // Closed meshes have about F/2 vertices.
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const int first = first_corner[c];
    if (first == static_cast<int>(c)) {
      vertex_of_corner[c] = mesh.vertex_count();
      mesh.add_vertex(corners[c][0], corners[c][1], corners[c][2]);
    } else {
      vertex_of_corner[c] = vertex_of_corner[first];
    }
  }
  for (std::size_t c = 0; c + 2 < corners.size(); c += 3) {
    mesh.add_triangle(vertex_of_corner[c], vertex_of_corner[c + 1], vertex_of_corner[c + 2]);
  }
  return mesh.build();
}

std::vector<Position> read_binary_corners(std::string_view bytes, const std::string& name) {
  BinaryCursor cursor(bytes, 80, std::endian::little, name);
  const std::uint64_t count = cursor.read<std::uint32_t>("the triangle count");
  const std::uint64_t needed = binary_header_bytes + count * binary_triangle_bytes;
  if (needed != bytes.size()) {
    cursor.fail_at(80, "the header claims " + std::to_string(count) + " triangles, which take " +
                           std::to_string(needed) + " bytes, but the file has " +
                           std::to_string(bytes.size()) + " (truncated, or not an STL file)");
  }
  if (count == 0) cursor.fail_at(80, "no faces: the header declares 0 triangles");
  if (3 * count > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) {
    cursor.fail_at(80, "too many triangles (" + std::to_string(count) + ")");
  }
  std::vector<Position> corners;
  corners.reserve(3 * count);  // Bounded by the file size, checked above.
  for (std::uint64_t triangle = 0; triangle < count; ++triangle) {
    const std::string label = "triangle " + std::to_string(triangle);
    cursor.skip(12, "the normal of " + label);
    for (int corner = 0; corner < 3; ++corner) {
      const std::size_t start = cursor.offset();
      Position position;
      for (double& coordinate : position) coordinate = cursor.read<float>(label);
      if (!std::isfinite(position[0]) || !std::isfinite(position[1]) ||
          !std::isfinite(position[2])) {
        cursor.fail_at(
            start, label + ": corner " + std::to_string(corner) + " has a non-finite coordinate");
      }
      corners.push_back(position);
    }
    cursor.skip(2, "the attribute of " + label);
  }
  return corners;
}

// Keywords in any case: some CAD exporters write them in capitals (SOLID, FACET NORMAL).
bool is_keyword(std::string_view word, std::string_view keyword) {
  return word.size() == keyword.size() &&
         std::equal(word.begin(), word.end(), keyword.begin(), [](char a, char b) {
           return std::tolower(static_cast<unsigned char>(a)) == b;
         });
}

void expect_keyword(TextScanner& scanner, std::string_view keyword, std::string_view context) {
  if (!scanner.skip_empty_lines()) {
    scanner.fail_at_end("the file ends " + std::string(context) + " (truncated)");
  }
  const std::string found = scanner.token_here();
  if (!is_keyword(scanner.read_word(), keyword)) {
    scanner.fail("expected '" + std::string(keyword) + "' " + std::string(context) + ", found '" +
                 found + "'");
  }
}

// facet normal nx ny nz / outer loop / vertex x y z (3 or more) / endloop / endfacet, repeated,
// inside "solid NAME" ... "endsolid NAME" (several solids may follow each other).
std::vector<Position> read_ascii_corners(std::string_view text, const std::string& name) {
  TextScanner scanner(text, name);
  std::vector<Position> corners;
  std::vector<Position> polygon;
  expect_keyword(scanner, "solid", "at the start");
  scanner.next_line();
  int facet = 0;
  for (;;) {
    // A file that ends after a whole facet without its 'endsolid' line holds every facet it
    // declares (trimesh and Assimp read it); one that ends inside a facet is cut short (below).
    if (!scanner.skip_empty_lines()) {
      if (facet > 0) break;
      scanner.fail_at_end("the file ends without 'endsolid' (truncated)");
    }
    const std::string found = scanner.token_here();
    const std::string_view keyword = scanner.read_word();
    if (is_keyword(keyword, "endsolid")) {
      scanner.next_line();
      if (!scanner.skip_empty_lines()) break;
      expect_keyword(scanner, "solid", "after 'endsolid'");
      scanner.next_line();
      continue;
    }
    if (!is_keyword(keyword, "facet")) scanner.fail("expected 'facet' or 'endsolid', found '" + found + "'");
    const std::string label = "facet " + std::to_string(facet);
    scanner.next_line();  // The normal is recomputed by whoever needs it.
    expect_keyword(scanner, "outer", "inside " + label);
    scanner.next_line();
    polygon.clear();
    for (;;) {
      if (!scanner.skip_empty_lines()) {
        scanner.fail_at_end("the file ends inside " + label + " (truncated)");
      }
      const std::string word_found = scanner.token_here();
      const std::string_view word = scanner.read_word();
      if (is_keyword(word, "endloop")) break;
      if (!is_keyword(word, "vertex")) {
        scanner.fail("expected 'vertex' or 'endloop' in " + label + ", found '" + word_found + "'");
      }
      Position position;
      const std::string corner = "corner " + std::to_string(polygon.size()) + " of " + label;
      position[0] = scanner.read_double("the x coordinate of " + corner);
      position[1] = scanner.read_double("the y coordinate of " + corner);
      position[2] = scanner.read_double("the z coordinate of " + corner);
      scanner.expect_line_end("the coordinates of " + corner);
      if (!std::isfinite(position[0]) || !std::isfinite(position[1]) ||
          !std::isfinite(position[2])) {
        scanner.fail(corner + " has a non-finite coordinate");
      }
      polygon.push_back(position);
      scanner.next_line();
    }
    if (polygon.size() < 3) {
      scanner.fail(label + " has " + std::to_string(polygon.size()) +
                   " vertices; a face needs at least 3");
    }
    scanner.next_line();
    expect_keyword(scanner, "endfacet", "after the loop of " + label);
    scanner.next_line();
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      corners.insert(corners.end(), {polygon[0], polygon[k], polygon[k + 1]});
    }
    ++facet;
  }
  if (corners.empty()) scanner.fail_at_end("no faces in the file");
  return corners;
}

bool starts_with_solid(std::string_view bytes) {
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  return first != std::string_view::npos && bytes.size() - first >= 5 &&
         is_keyword(bytes.substr(first, 5), "solid");
}

bool is_binary_by_size(std::string_view bytes) {
  if (bytes.size() < binary_header_bytes) return false;
  std::uint64_t count = 0;  // Little-endian uint32 at byte 80.
  for (int k = 3; k >= 0; --k) count = count << 8 | static_cast<unsigned char>(bytes[80 + k]);
  return binary_header_bytes + count * binary_triangle_bytes == bytes.size();
}

}  // namespace

namespace detail {

Mesh parse_stl(std::string_view bytes, std::string_view file_name) {
  const std::string name(file_name);
  if (bytes.empty()) detail::throw_at_byte(name, 0, "the file is empty");
  if (!is_binary_by_size(bytes) && starts_with_solid(bytes)) {
    return merge_corners(read_ascii_corners(bytes, name));
  }
  if (bytes.size() < binary_header_bytes) {
    detail::throw_at_byte(name, bytes.size(),
                          "the file ends inside the 84-byte header of a binary STL (it has " +
                              std::to_string(bytes.size()) + " bytes)");
  }
  return merge_corners(read_binary_corners(bytes, name));
}

}  // namespace detail

Mesh read_stl(const std::filesystem::path& path) {
  return detail::parse_stl(detail::read_whole_file(path), path.string());
}

}  // namespace harmonia
