#pragma once
// Shared pieces of the mesh readers: loading a whole file, and building the error messages that
// name the file and the line (text formats) or the byte offset (binary formats).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace harmonia::detail {

//! The complete contents of a file. Throws Error(io_error) if it cannot be opened or read.
[[nodiscard]] std::string read_whole_file(const std::filesystem::path& path);

//! A short printable rendering of untrusted text for an error message: at most `limit` characters,
//! control and non-ASCII bytes written as \xNN, so binary garbage never garbles a terminal.
[[nodiscard]] std::string printable(std::string_view text, std::size_t limit = 24);

//! Throws Error(parse_error, "FILE:LINE: problem").
[[noreturn]] void throw_at_line(std::string_view file, std::int64_t line, std::string_view problem);

//! Throws Error(parse_error, "FILE: byte OFFSET: problem").
[[noreturn]] void throw_at_byte(std::string_view file, std::uint64_t offset,
                                std::string_view problem);

//! True when `count` elements of at least `bytes_each` bytes can fit into `available` bytes. Used
//! to reject absurd element counts from a file header before anything is allocated from them.
[[nodiscard]] constexpr bool count_fits(std::uint64_t count, std::uint64_t bytes_each,
                                        std::uint64_t available) {
  return bytes_each == 0 ? count <= available : count <= available / bytes_each;
}

}  // namespace harmonia::detail
