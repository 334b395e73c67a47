// The picture formats, told apart by extension.
#include "picture/picture_format.h"

#include <cctype>

#include "harmonia/types.h"

namespace harmonia::detail {

PictureFormat picture_format(const std::filesystem::path& path, const std::string& caller) {
  std::string extension = path.extension().string();
  for (char& letter : extension)
    letter = static_cast<char>(std::tolower(static_cast<unsigned char>(letter)));
  if (extension == ".svg") return PictureFormat::svg;
  if (extension == ".png") return PictureFormat::png;
  throw Error(Status::io_error, caller + ": unknown picture format '" + extension + "' of '" +
                                    path.string() + "' (use .svg or .png)");
}

}  // namespace harmonia::detail
