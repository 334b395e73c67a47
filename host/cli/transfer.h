#pragma once
//! \file transfer.h
//! \brief `harmonia transfer --source-rest S.obj --source-poses P.obj... --target T.obj
//! --markers M.txt --out DIR [--method correspondence|quaternion] [--components N]
//! [--backend B] [--json]`: deformation transfer from marker pairs (thesis 8.4, 8.5).

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/common.h"

namespace harmonia::cli {

struct TransferOptions {
  std::string source_rest;
  std::vector<std::string> source_poses;
  std::string target;
  std::string markers;
  std::string out;
  std::string method = "correspondence";
  int components = 8;
  std::string backend = "auto";
  bool json = false;
};

CLI::App* add_transfer_command(CLI::App& app, TransferOptions& options);

//! Writes OUT/<pose file name>.obj for every pose (the target's connectivity and vertex order) and
//! prints the report (with --json: setup_seconds, pose_seconds, matched and unmatched triangles).
//! ok; input for a bad mesh, marker file (naming file and line) or a pose of another connectivity.
[[nodiscard]] ExitCode run_transfer(const TransferOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
