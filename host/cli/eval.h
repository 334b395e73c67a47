#pragma once
//! \file eval.h
//! \brief `harmonia eval MESH3D PARAM [--sphere] [--json]`: distortion and validity of a
//! parameterization, planar or (with --sphere) spherical.

#include <string>

#include <CLI/CLI.hpp>

#include "cli/common.h"

namespace harmonia::cli {

struct EvalOptions {
  std::string mesh3d;
  std::string parameterization;
  bool sphere = false;  //!< PARAM is a spherical map: a mesh with the same faces, v on the sphere.
  bool json = false;
};

CLI::App* add_eval_command(CLI::App& app, EvalOptions& options);
//! ok, or invalid_result when the layout has flipped triangles (the metrics are printed either
//! way); input when the files cannot be read or do not belong together.
[[nodiscard]] ExitCode run_eval(const EvalOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
