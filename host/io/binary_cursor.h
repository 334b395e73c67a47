#pragma once
// A bounds-checked reader of little- or big-endian numbers from the bytes of a binary file (binary
// PLY, binary STL). Every read checks that the bytes exist, so a truncated file is an error naming
// the byte offset, never a read past the end.

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "io/io_support.h"

namespace harmonia::detail {

class BinaryCursor {
 public:
  BinaryCursor(std::string_view bytes, std::size_t offset, std::endian order,
               std::string_view file_name)
      : bytes_(bytes), offset_(offset), order_(order), file_name_(file_name) {}

  [[nodiscard]] std::size_t offset() const { return offset_; }
  [[nodiscard]] std::size_t remaining() const { return bytes_.size() - offset_; }

  //! Reads one value of arithmetic type T; `context` says what was being read if the file ends.
  template <typename T>
  T read(std::string_view context) {
    if (remaining() < sizeof(T)) {
      fail("the file ends inside " + std::string(context) + " (truncated)");
    }
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, bytes_.data() + offset_, sizeof(T));
    if (order_ != std::endian::native) {
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    }
    T value;
    std::memcpy(&value, raw, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }

  //! Moves past `count` bytes; fails like read() if the file is shorter.
  void skip(std::uint64_t count, std::string_view context) {
    if (remaining() < count) fail("the file ends inside " + std::string(context) + " (truncated)");
    offset_ += static_cast<std::size_t>(count);
  }

  //! Throws Error(parse_error, "FILE: byte OFFSET: problem") at the current offset.
  [[noreturn]] void fail(std::string_view problem) const { fail_at(offset_, problem); }
  [[noreturn]] void fail_at(std::size_t offset, std::string_view problem) const {
    throw_at_byte(file_name_, offset, problem);
  }

 private:
  std::string_view bytes_;
  std::size_t offset_;
  std::endian order_;
  std::string_view file_name_;
};

}  // namespace harmonia::detail
