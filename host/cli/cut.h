#pragma once
//! \file cut.h
//! \brief `harmonia cut IN OUT [--from V --to W] [--json]`: cut a mesh open into a disk.

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/common.h"

namespace harmonia::cli {

struct CutCommandOptions {
  std::string input;
  std::string output;
  bool in_place = false;  //!< OUT may be IN: the input is replaced by the cut mesh.
  std::optional<int> from_vertex;
  std::optional<int> to_vertex;
  bool json = false;
};

CLI::App* add_cut_command(CLI::App& app, CutCommandOptions& options);
//! Writes the disk to OUT (OBJ, OFF or PLY by extension) and prints seam and vertex counts.
[[nodiscard]] ExitCode run_cut(const CutCommandOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
