#pragma once
//! \file deform.h
//! \brief `harmonia deform IN EDIT.json OUT [--frames N] [--refine K] [--backend B]
//! [--picture FILE.png] [--json]`: apply a surface edit (harmonic-field guided, thesis 8.3 and
//! 8.5) described by an edit file (harmonia/edit_file.h).

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/common.h"

namespace harmonia::cli {

struct DeformOptions {
  std::string input;
  std::string edit;
  std::string output;
  bool in_place = false;
  int frames = 1;                        //!< Frames played (transformations at t = k / frames).
  std::optional<int> refinement_steps;   //!< SurfaceEditOptions::refinement_steps.
  std::optional<double> frame_budget_ms;  //!< SurfaceEditOptions::frame_budget, in milliseconds.
  std::optional<int> rotation_clusters;  //!< SurfaceEditOptions::rotation_clusters.
  std::string backend = "auto";
  std::string picture;  //!< Also draw before and after (PNG); empty: no picture.
  bool json = false;
};

CLI::App* add_deform_command(CLI::App& app, DeformOptions& options);

//! Writes OUT (OBJ: the last frame's positions, the input's faces), the picture if asked, and prints
//! the report (with --json: setup_seconds, frame_seconds, the last frame's split and quality).
//! ok; input for a bad mesh or edit file (naming the field); numerical on a failed solve.
[[nodiscard]] ExitCode run_deform(const DeformOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
