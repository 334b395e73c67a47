#pragma once
//! \file view.h
//! \brief `harmonia view RESULT... [--mesh MESH3D] --out PAGE.html`: one self-contained HTML page
//! (harmonia/view_page.h) showing each layout on its 3D model and in its UV square, several side
//! by side on one camera.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/common.h"

namespace harmonia::cli {

struct ViewOptions {
  std::vector<std::string> results;  //!< Layouts: OBJ files with vt and texture indices.
  std::string mesh3d;                //!< The 3D mesh; empty: each result's own vertices.
  std::string out;
  std::string title;
};

CLI::App* add_view_command(CLI::App& app, ViewOptions& options);
//! ok; input when a file cannot be read or a layout does not belong to its mesh; environment when
//! the page cannot be written.
[[nodiscard]] ExitCode run_view(const ViewOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
