#pragma once
//! \file info.h
//! \brief `harmonia info MESH [--json]`: the topology report of a mesh.

#include <string>

#include <CLI/CLI.hpp>

#include "cli/common.h"

namespace harmonia::cli {

struct InfoOptions {
  std::string mesh;
  bool json = false;
};

//! Declares the subcommand and its options (filled in when the command line is parsed).
CLI::App* add_info_command(CLI::App& app, InfoOptions& options);
//! Prints the report; exit code ok (an unusable mesh is still described, not refused).
[[nodiscard]] ExitCode run_info(const InfoOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
