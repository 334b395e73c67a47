#pragma once
//! \file progress_line.h
//! \brief A single updating line on stderr that shows what a long command is doing.

#include <chrono>
#include <cstddef>
#include <set>
#include <string>
#include <vector>

#include "cli/common.h"
#include "harmonia/mesh.h"
#include "harmonia/types.h"

namespace harmonia::cli {

//! Shows "harmonia: <stage> <step>/<total>" on one line of stderr, rewritten in place ('\r'), at
//! most ten times a second. Enabled when stderr is a terminal or --progress is given; silent with
//! --quiet or when the command prints JSON (machine output must stay clean). Erased on destruction.
//! With --verbose (and without --quiet) it becomes a log instead: every stage not shown before
//! gets its own line "harmonia: <stage>" (so one line per ABF Newton step, whose stage text names
//! the step), and the repeated reports of an inner iterative solver are not listed.
class ProgressLine {
 public:
  ProgressLine(const GlobalOptions& global, bool json_output);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  //! A callback for SolverOptions::progress that updates this line (it never cancels).
  [[nodiscard]] ProgressCallback callback();
  //! Shows `text` now (e.g. "reading input.obj").
  void show(const std::string& text);
  //! Erases the line so that other output starts on a clean line.
  void clear();

 private:
  void draw(const std::string& text, bool force);
  void log(const std::string& text);

  bool enabled_ = false;
  bool verbose_ = false;
  std::set<std::string> logged_;  // Stages already given a line in verbose mode.
  std::size_t shown_length_ = 0;
  std::chrono::steady_clock::time_point last_draw_{};
};

//! The start of a command that reads the mesh IN and writes the mesh OUT (OBJ) and maybe a PNG
//! picture: refuses a bad command line before any work (extensions; OUT or the picture being IN
//! without in_place), then reads IN with the progress line, its time appended to `timings` as
//! "read".
[[nodiscard]] Mesh read_input_for_output(const std::string& input, const std::string& output,
                                         bool in_place, const std::string& picture,
                                         ProgressLine& progress, std::vector<PhaseTiming>& timings);

}  // namespace harmonia::cli
