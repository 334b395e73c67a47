#pragma once
// Internal: the file format of a picture or plot, from its extension, checked before any work so
// that a typo fails fast.

#include <filesystem>
#include <string>

namespace harmonia::detail {

enum class PictureFormat { svg, png };

// .svg or .png in any case; otherwise throws Error(io_error) naming `caller`, the extension and
// the path.
[[nodiscard]] PictureFormat picture_format(const std::filesystem::path& path,
                                           const std::string& caller);

}  // namespace harmonia::detail
