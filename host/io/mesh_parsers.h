#pragma once
// The readers' parsers, on a file's contents already in memory. `name` is the file name their
// error messages use ("NAME:LINE: problem"); read_obj(path) is parse_obj(contents of path, path),
// and likewise for the other formats. The fuzz harnesses (tests/fuzz) call them directly, so that
// every input they make reaches the parser without a trip through the file system.

#include <string_view>

#include "harmonia/mesh.h"
#include "harmonia/obj_asset.h"

namespace harmonia::detail {

[[nodiscard]] Mesh parse_obj(std::string_view contents, std::string_view name);
[[nodiscard]] TexturedMesh parse_textured_obj(std::string_view contents, std::string_view name);
[[nodiscard]] ObjAsset parse_obj_asset(std::string_view contents, std::string_view name);
[[nodiscard]] Mesh parse_off(std::string_view contents, std::string_view name);
//! ASCII or binary (little- or big-endian), as the header says.
[[nodiscard]] Mesh parse_ply(std::string_view contents, std::string_view name);
//! ASCII or binary, told apart as io_stl.cpp explains.
[[nodiscard]] Mesh parse_stl(std::string_view contents, std::string_view name);

}  // namespace harmonia::detail
