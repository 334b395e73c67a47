#pragma once
//! \file batch.h
//! \brief `harmonia batch INPUTS... --out DIR [-j N] [--atlas | --method M] [--resume] [--json]`:
//! the texture atlas (or a planar map of `unwrap`) of many meshes, each in a child process of its
//! own, N at a time.

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli/atlas.h"
#include "cli/common.h"

namespace harmonia::cli {

struct BatchOptions {
  std::vector<std::string> inputs;    //!< Mesh files and folders (searched recursively).
  std::string out;                    //!< The output folder (created if missing).
  int jobs = 0;                       //!< Children at a time; 0: one per core.
  bool atlas = false;                 //!< `harmonia atlas` on each input (also the default).
  std::optional<std::string> method;  //!< `harmonia unwrap --method M` on each input instead.
  // Passed on to `harmonia atlas` when given (its defaults otherwise).
  std::optional<AtlasResolution> resolution;
  std::optional<int> padding;
  std::optional<double> max_distortion;
  std::optional<double> texels_per_unit;
  std::optional<int> max_pages;
  std::optional<std::string> cleanup;  //!< Passed on to either command.
  bool keep_splits = false;            //!< Passed on to `atlas`.
  bool join_charts = false;            //!< Passed on to `atlas`.
  bool repack = false;                 //!< Passed on to `atlas`.
  bool cut = false;                    //!< --method only: `unwrap --cut` (non-disk inputs).
  //! Skip the inputs whose output exists, unless the log says that output was written with
  //! defects (exit code 3): those run again; append to the log.
  bool resume = false;
  bool resume_keep_defective = false;  //!< With resume: skip outputs written with defects too.
  bool json = false;
  std::optional<std::string> backend;  //!< Passed on to either command (`--backend`).
  // The pieces of a batch that another scheduler runs (python -m harmonia.distributed): each
  // says what this program would do, so that the batch is written once.
  //! Print the plan, one JSON line per input in the order the batch would start them: {"input",
  //! "output", "run": true}, or for an input --resume skips {"run": false, "record": its log
  //! line}; run nothing, write no log.
  bool plan = false;
  //! Run one input (its output named by the plan) as the batch runs it, in a child process of its
  //! own, and print its log line; write no log.
  std::vector<std::string> task;
  //! Print the summary of the log lines in this file (a run's records), as the batch does at its
  //! end, with `elapsed` seconds for its wall-clock time; the exit code the batch would have had.
  std::optional<std::string> summary_of;
  double elapsed = 0.0;
};

CLI::App* add_batch_command(CLI::App& app, BatchOptions& options);

//! Runs every input (after all of them: ok when none failed, else input), writes
//! OUT/batch-log.jsonl and prints the summary. usage for a bad command line; input when no mesh
//! file is found; environment when OUT or its log cannot be written (before any work).
[[nodiscard]] ExitCode run_batch(const BatchOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
