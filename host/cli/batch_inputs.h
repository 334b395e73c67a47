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
  std::filesystem::path output;  //!< Where its result goes; no other input of the batch's.
};

//! The inputs of a batch, from the files and folders given, in a deterministic order: each given
//! path in turn; below a folder, the mesh files (the extensions the readers accept, any case) of
//! the whole tree sorted by path. A given file is taken whatever its extension (its child then
//! says what is wrong with it); a path that is not there too, so that its log line says so.
//!
//! Outputs: a given file goes to `out_dir`/<its name>; a file found below a given folder to
//! `out_dir`/<its path relative to that folder>, keeping the folder structure; the extension
//! becomes .obj (models/car.ply -> OUT/car.obj). Inputs whose outputs would be one file (x.obj and
//! x.ply side by side, box.obj and box.STL) all keep their extension in front of the .obj instead
//! (OUT/x.obj.obj, OUT/x.ply.obj); inputs that then still share one (the same relative path below
//! two given folders, or files of one name given from two folders) are numbered in input order
//! (OUT/x.obj, OUT/x-2.obj). So every input has an output of its own, and the same inputs get the
//! same names in every run (--resume relies on it). A file reached twice (given twice, or given and
//! found below a given folder) is taken once. `out_dir` itself is never searched (a folder holding
//! it would otherwise find the previous outputs as inputs). Throws CliFailure(usage) when
//! `out_dir` is one of the given folders: its outputs would replace its inputs.
[[nodiscard]] std::vector<BatchInput> find_batch_inputs(const std::vector<std::string>& paths,
                                                        const std::filesystem::path& out_dir);

}  // namespace harmonia::cli
