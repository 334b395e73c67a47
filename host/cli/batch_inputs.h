#pragma once
//! \file batch_inputs.h
//! \brief Which files `harmonia batch` works on, and where each one's result goes.

#include <filesystem>
#include <string>
#include <vector>

namespace harmonia::cli {

//! One mesh file of a batch.
struct BatchInput {
  std::filesystem::path input;   //!< As given, or found below a given folder.
  std::filesystem::path output;  //!< OUT_DIR/<relative path>.obj.
  //! Empty, or why the input cannot be run (its output is another input's output too).
  std::string conflict;
};

//! The inputs of a batch, from the files and folders given, in a deterministic order: each given
//! path in turn; below a folder, the mesh files (the extensions the readers accept, any case) of
//! the whole tree sorted by path. A given file is taken whatever its extension (its child then
//! says what is wrong with it); a path that is not there too, so that its log line says so.
//!
//! Outputs: a given file goes to `out_dir`/<its name>.obj; a file found below a given folder to
//! `out_dir`/<its path relative to that folder>.obj, keeping the folder structure so that files
//! named alike in different subfolders do not collide. A file reached twice (given twice, or
//! given and found below a given folder) is taken once. Where two inputs would still write one
//! output (x.obj and x.ply side by side, or two given folders with the same relative paths), the
//! later one gets a `conflict` naming the earlier. `out_dir` itself is never searched (a folder
//! holding it would otherwise find the previous outputs as inputs). Throws CliFailure(usage) when
//! `out_dir` is one of the given folders: its outputs would replace its inputs.
[[nodiscard]] std::vector<BatchInput> find_batch_inputs(const std::vector<std::string>& paths,
                                                        const std::filesystem::path& out_dir);

}  // namespace harmonia::cli
