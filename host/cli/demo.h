#pragma once
//! \file demo.h
//! \brief `harmonia demo [OUTDIR]`: flatten the built-in demo surface with four methods and
//! compare.

#include <string>

#include <CLI/CLI.hpp>

#include "cli/common.h"

namespace harmonia::cli {

struct DemoOptions {
  std::string output_directory = "harmonia-demo";
};

CLI::App* add_demo_command(CLI::App& app, DemoOptions& options);
//! Writes OUTDIR/demo-surface.obj and, per method, demo-<method>.obj/.svg/.png; prints a table.
//! ok; invalid_result if a method produced flipped triangles; the worst code of a failed method.
[[nodiscard]] ExitCode run_demo(const DemoOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
