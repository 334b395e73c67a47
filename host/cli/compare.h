#pragma once
//! \file compare.h
//! \brief `harmonia compare MESH3D PARAM... [--labels A,B,...] [--picture FILE] [--json]`: several
//! layouts of one mesh side by side: validity, distortion figures, and per-triangle angle and area
//! distortion (as a table, and as the sorted curves of thesis figure 6.4 with --picture).

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cli/common.h"

namespace harmonia::cli {

struct CompareOptions {
  std::string mesh3d;
  std::vector<std::string> layouts;  //!< PARAM files, as `eval` reads them.
  std::vector<std::string> labels;   //!< One per layout; empty: the files' names.
  std::string picture;               //!< .svg or .png; empty: none.
  bool json = false;
};

CLI::App* add_compare_command(CLI::App& app, CompareOptions& options);
//! Prints the table (or JSON) and writes the picture, then: ok; invalid_result when a layout has
//! flipped triangles; usage for labels that do not match the layouts or a picture of more layouts
//! than it has colours; input when a file cannot be read or a layout does not belong to MESH3D;
//! environment when the picture cannot be written.
[[nodiscard]] ExitCode run_compare(const CompareOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
