// Fuzz target: binary PLY bodies behind a well-formed header that the first six bytes choose
// (byte order, the coordinates' type, the face list's count and index types, an extra property on
// each element, and the two element counts), so that mutations reach the binary reader itself.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/fuzz_checks.h"
#include "fuzz/fuzz_targets.h"
#include "io/mesh_parsers.h"

namespace harmonia::fuzz {
namespace {

constexpr std::array<const char*, 8> scalar_types = {"char", "uchar", "short", "ushort",
                                                    "int",  "uint",  "float", "double"};
constexpr std::array<const char*, 8> integer_types = {"uchar", "ushort", "uint", "char",
                                                     "short", "int",    "int8", "uint32"};
constexpr std::size_t choice_bytes = 6;

}  // namespace

void fuzz_ply_binary(Bytes input) {
  const std::uint8_t* data = input.data();
  const std::size_t size = input.size();
  if (size < choice_bytes) return;
  const std::uint8_t layout = data[0];
  const std::uint8_t lists = data[1];
  const unsigned vertex_count = data[2] | data[3] << 8;
  const unsigned face_count = data[4] | data[5] << 8;

  const std::string coordinate = scalar_types[(layout >> 1) & 7];
  std::string header = "ply\nformat ";
  header += (layout & 1) ? "binary_big_endian" : "binary_little_endian";
  header += " 1.0\nelement vertex " + std::to_string(vertex_count) + "\n";
  for (const char* axis : {"x", "y", "z"}) header += "property " + coordinate + " " + axis + "\n";
  if (layout & 0x10) header += "property uchar red\n";
  header += "element face " + std::to_string(face_count) + "\n";
  header += std::string("property list ") + integer_types[lists & 7] + " " +
            integer_types[(lists >> 3) & 7] + " vertex_indices\n";
  if (lists & 0x40) header += "property float quality\n";
  header += "end_header\n";

  const std::string contents =
      header + std::string(reinterpret_cast<const char*>(data + choice_bytes), size - choice_bytes);
  parse_and_check(contents, detail::parse_ply);
}

}  // namespace harmonia::fuzz
