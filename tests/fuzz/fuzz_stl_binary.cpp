// Fuzz target: binary STL. The first byte chooses whether the triangle count at byte 80 is
// the one the body's size gives (then the body is read as triangles whatever its bytes: NaNs,
// repeated corners) or the next four bytes (a count that disagrees with the size: the file must
// be refused, or read as ASCII if it starts with "solid"), and whether the 80-byte header starts
// with "solid" as some binary exporters write it.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/fuzz_checks.h"
#include "fuzz/fuzz_targets.h"
#include "io/mesh_parsers.h"

namespace harmonia::fuzz {
namespace {

constexpr std::size_t header_bytes = 80;
constexpr std::size_t triangle_bytes = 50;

void append_little_endian_uint32(std::string& bytes, std::uint32_t value) {
  for (int k = 0; k < 4; ++k) bytes.push_back(static_cast<char>(value >> (8 * k) & 0xff));
}

}  // namespace

void fuzz_stl_binary(Bytes input) {
  const std::uint8_t* data = input.data();
  const std::size_t size = input.size();
  if (size < 1) return;
  const std::uint8_t choice = data[0];
  std::string_view rest(reinterpret_cast<const char*>(data + 1), size - 1);

  std::string contents(header_bytes, '\0');
  if (choice & 2) contents.replace(0, 6, "solid ");
  if (choice & 1) {
    rest = rest.substr(0, rest.size() / triangle_bytes * triangle_bytes);
    append_little_endian_uint32(contents, static_cast<std::uint32_t>(rest.size() / triangle_bytes));
  } else {
    if (rest.size() < 4) return;
    std::uint32_t declared = 0;
    for (int k = 3; k >= 0; --k) declared = declared << 8 | static_cast<std::uint8_t>(rest[k]);
    append_little_endian_uint32(contents, declared);
    rest.remove_prefix(4);
  }
  contents.append(rest);
  parse_and_check(contents, detail::parse_stl);
}

}  // namespace harmonia::fuzz
