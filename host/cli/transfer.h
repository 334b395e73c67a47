#pragma once
//! \file transfer.h
//! \brief `harmonia transfer --source-rest S.obj --source-poses P.obj... --target T.obj
//! --markers M.txt --out DIR [--method correspondence|quaternion] [--components N]
//! [--backend B] [--picture] [--json]`: deformation transfer from marker pairs (thesis 8.4, 8.5).

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
  //! Also draw the correspondence and every pose beside its source (harmonia/transfer_picture.h).
  bool picture = false;
  bool json = false;
};

CLI::App* add_transfer_command(CLI::App& app, TransferOptions& options);

//! Writes OUT/<pose file name>.obj for every pose (the target's connectivity and vertex order),
//! with --picture also OUT/correspondence.png and OUT/<pose file name>.png, and prints the report
//! (with --json: setup_seconds, pose_seconds, matched and unmatched triangles, the pictures).
//! ok; input for a bad mesh, marker file (naming file and line), a pose of another connectivity,
//! or with --picture a pose named like the correspondence picture.
[[nodiscard]] ExitCode run_transfer(const TransferOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
