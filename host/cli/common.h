#pragma once
//! \file common.h
//! \brief What every `harmonia` command shares: exit codes, the failure type that carries one, the
//! global flags, and loading a mesh with a message that names the file.

#include <chrono>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>

#include "harmonia/gltf.h"
#include "harmonia/mesh.h"
#include "harmonia/obj_asset.h"
#include "harmonia/types.h"

namespace harmonia::cli {

//! The program's exit codes (docs/cli.md, "Exit codes"). Stable: scripts depend on them.
enum class ExitCode : int {
  ok = 0,              //!< Success.
  usage = 1,           //!< Bad command line (unknown option, bad value, wrong file extension).
  input = 2,           //!< The input cannot be read or used (parse error, not a disk, ...).
  invalid_result = 3,  //!< A result was computed and written but is invalid (flipped triangles).
  numerical = 4,       //!< A solver failed (no convergence, factorization failure, non-finite).
  environment = 5,     //!< The environment failed (an output cannot be written, no device).
};

//! Thrown by a command to stop with `code` and the one-line `reason` (printed as "harmonia:
//! reason").
class CliFailure : public std::runtime_error {
 public:
  CliFailure(ExitCode code, const std::string& reason) : std::runtime_error(reason), code_(code) {}
  [[nodiscard]] ExitCode code() const noexcept { return code_; }

 private:
  ExitCode code_;
};

//! The exit code a library Status stands for.
[[nodiscard]] ExitCode exit_code_for(Status status);

//! Flags that apply to every command.
struct GlobalOptions {
  bool quiet = false;     //!< No progress line and no informational text on stderr.
  bool progress = false;  //!< Show the progress line even when stderr is not a terminal.
  //! One line on stderr per solver stage (e.g. per ABF Newton step), never rewritten; unlike the
  //! progress line it is kept with --json (stdout stays clean) but not with --quiet.
  bool verbose = false;
};

//! Reads a mesh (format from the extension; of a glTF file the triangles gltf_triangles_of gives)
//! and checks its indices and coordinates. Every problem
//! becomes a CliFailure(input) whose reason names the file (and line, from the readers).
[[nodiscard]] Mesh load_mesh(const std::filesystem::path& path);
//! The program's --mesh option: which mesh of a glTF file the commands read (its name or index;
//! empty, the default: the triangles of the whole default scene in world coordinates). Set once by
//! main() after parsing the command line.
void choose_gltf_mesh(const std::string& name_or_index);
[[nodiscard]] const std::string& gltf_mesh_choice();
//! The triangles a command reads from `document` under that choice.
[[nodiscard]] GltfTriangles gltf_triangles_of(const GltfDocument& document);
//! What an OBJ input carries besides its mesh (harmonia/obj_asset.h), for a writer to keep; none
//! for other formats and for an OBJ of positions and faces alone.
[[nodiscard]] std::optional<ObjAsset> kept_obj_asset(const std::filesystem::path& input);
//! Reads a glTF document (harmonia/gltf.h) with load_mesh's checks and messages.
[[nodiscard]] GltfDocument load_gltf(const std::filesystem::path& path);

//! Throws CliFailure(usage) unless `path` ends in one of the given extensions (lowercase, with
//! dot).
void require_extension(const std::filesystem::path& path,
                       std::initializer_list<const char*> allowed, const std::string& what);

//! Checks an output path before any work is done: CliFailure(usage) when it is the input file
//! itself (the same file, also through a link or a second name) and `in_place` was not given, and
//! CliFailure(environment) naming it when it cannot be written (no such folder, a folder without
//! permission, a directory at the path). `what` names the output in the messages ("OUT",
//! "--picture").
void check_output(const std::filesystem::path& input, const std::filesystem::path& output,
                  bool in_place, const std::string& what);

//! Prints "harmonia: message" on stderr unless quiet (for notes that are not failures).
void note(const GlobalOptions& global, const std::string& message);

//! Runs `write` and turns a harmonia::Error (file cannot be written) into CliFailure(environment).
template <typename Write>
void write_output(Write&& write) {
  try {
    write();
  } catch (const Error& error) {
    throw CliFailure(ExitCode::environment, error.what());
  }
}

//! Wall-clock seconds since `start`, for the phases a command times itself (read, write, ...).
using Clock = std::chrono::steady_clock;
[[nodiscard]] inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace harmonia::cli
