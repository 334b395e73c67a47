#include "io/io_support.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <system_error>

#include "harmonia/types.h"

namespace harmonia::detail {

std::string read_whole_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw Error(Status::io_error, name + ": cannot read: it is a directory");
  }
  // A unique_ptr with fclose closes the file on every path out of this function.
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(name.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) throw Error(Status::io_error, name + ": cannot open: " + std::strerror(errno));

  std::string contents;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (!error) contents.reserve(static_cast<std::size_t>(size));
  // Read in blocks rather than trusting the size: the file may change or be a pipe.
  char block[1 << 16];
  for (;;) {
    const std::size_t got = std::fread(block, 1, sizeof block, file.get());
    contents.append(block, got);
    if (got < sizeof block) break;
  }
  if (std::ferror(file.get())) {
    throw Error(Status::io_error, name + ": cannot read: " + std::strerror(errno));
  }
  return contents;
}

std::string printable(std::string_view text, std::size_t limit) {
  std::string shown;
  const std::size_t count = text.size() < limit ? text.size() : limit;
  for (std::size_t i = 0; i < count; ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte >= 0x20 && byte < 0x7f) {
      shown += static_cast<char>(byte);
    } else {
      static constexpr char hex[] = "0123456789abcdef";
      shown += "\\x";
      shown += hex[byte >> 4];
      shown += hex[byte & 15];
    }
  }
  if (text.size() > limit) shown += "...";
  return shown;
}

void throw_at_line(std::string_view file, std::int64_t line, std::string_view problem) {
  std::string message(file);
  message += ':';
  message += std::to_string(line);
  message += ": ";
  message += problem;
  throw Error(Status::parse_error, message);
}

void throw_at_byte(std::string_view file, std::uint64_t offset, std::string_view problem) {
  std::string message(file);
  message += ": byte ";
  message += std::to_string(offset);
  message += ": ";
  message += problem;
  throw Error(Status::parse_error, message);
}

}  // namespace harmonia::detail
