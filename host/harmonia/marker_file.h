#pragma once
//! \file marker_file.h
//! \brief Marker files of deformation transfer (the format of
//! ../shared/data/deform/markers-lion-cat.txt): one pair "sourceVertex targetVertex" per data line,
//! 0-based vertex indices; '#' starts a comment; blank lines are ignored.

#include <filesystem>
#include <string>
#include <vector>

#include "harmonia/deformation_transfer.h"

namespace harmonia {

//! Parses marker text for meshes of the given vertex counts. Throws harmonia::Error: parse_error
//! naming `source` and the line for a line that is not two integers; invalid_input naming the line
//! for an index outside its mesh or a vertex already used by an earlier pair, and for fewer than 3
//! pairs.
[[nodiscard]] std::vector<MarkerPair> parse_markers(const std::string& text, int source_vertices,
                                                    int target_vertices,
                                                    const std::string& source = "markers");

//! Reads and parses a marker file; io_error if it cannot be read.
[[nodiscard]] std::vector<MarkerPair> read_marker_file(const std::filesystem::path& path,
                                                       int source_vertices, int target_vertices);

}  // namespace harmonia
