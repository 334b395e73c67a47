#pragma once
//! \file unwrap.h
//! \brief `harmonia unwrap IN OUT ...`: flatten a disk-shaped mesh and write it as a UV-mapped OBJ.

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/common.h"
#include "harmonia/gltf.h"

namespace harmonia::cli {

struct UnwrapOptions {
  std::string input;
  std::string output;
  bool in_place = false;  //!< OUT may be IN: the input is replaced by the result.
  GltfWriteOptions gltf;  //!< glTF output: --texcoord and --overwrite.
  std::string method = "conformal";
  std::optional<std::string> weights;   //!< conformal, qhm and free only (defaults in unwrap.cpp).
  std::optional<std::string> boundary;  //!< Default circle; conformal and qhm only.
  std::optional<int> rounds;            //!< qhm: most rounds (default 5); linabf: rounds.
  bool polish = false;                  //!< free only: add the fixed-boundary polish P3.
  std::optional<std::string> stop_after;  //!< free only: conformal (P1) or quasi-harmonic (P2).
  std::optional<double> boundary_t;     //!< abf only: boundary control t (default 2).
  std::optional<std::string> solver;    //!< abf only: Newton step solver (default auto).
  std::optional<std::string> reconstruction;  //!< abf and linabf: lsq (default) or greedy.
  bool underdetermined = false;         //!< abf only: feasible point nearest the start.
  std::string backend = "auto";
  std::string preconditioner = "multilevel";  //!< multilevel or jacobi (device solves).
  std::string normalize = "surface-area";
  std::string cleanup = "strict";
  std::string picture;
  std::string view;  //!< Also write a page to look at the layout in a browser (.html).
  bool cut = false;  //!< Cut a non-disk input into a disk first; UVs are then written per corner.
  bool json = false;
};

CLI::App* add_unwrap_command(CLI::App& app, UnwrapOptions& options);
//! ok; input (not a disk, unreadable, dirty in strict mode); invalid_result (flipped triangles, the
//! file is still written); numerical (solver failure); environment (cannot write, no device).
[[nodiscard]] ExitCode run_unwrap(const UnwrapOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
