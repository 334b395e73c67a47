#pragma once
// Writing a file so that it is either completely replaced or left untouched: the content goes to a
// temporary file in the same folder (so that the final rename stays on one file system, which makes
// it atomic on POSIX), and only a fully written and closed temporary file is renamed over the
// target.

#include <filesystem>
#include <string_view>

namespace harmonia::detail {

//! Writes `contents` to `path` atomically. Throws Error(io_error) naming the file on any failure,
//! after removing the temporary file; an existing `path` is then unchanged.
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace harmonia::detail
