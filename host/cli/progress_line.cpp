#include "cli/progress_line.h"

#include <cstdio>
#include <iostream>

#include <unistd.h>

namespace harmonia::cli {

ProgressLine::ProgressLine(const GlobalOptions& global, bool json_output) {
  const bool terminal = isatty(fileno(stderr)) != 0;
  verbose_ = global.verbose && !global.quiet;
  // The log replaces the rewritten line: the two would garble each other.
  enabled_ = !verbose_ && !global.quiet && !json_output && (terminal || global.progress);
}

ProgressLine::~ProgressLine() { clear(); }

ProgressCallback ProgressLine::callback() {
  if (verbose_) {
    return [this](const Progress& progress) {
      log(std::string(progress.stage));
      return true;
    };
  }
  if (!enabled_) return {};
  return [this](const Progress& progress) {
    std::string text(progress.stage);
    // Some stages already carry their count ("round 2/5"); do not repeat it.
    if (progress.total > 0 && text.find('/') == std::string::npos) {
      // Appended piece by piece: `" " + std::to_string(...)` trips a GCC 12 -Wrestrict false alarm.
      text += ' ';
      text += std::to_string(progress.step + 1);
      text += '/';
      text += std::to_string(progress.total);
    }
    draw(text, false);
    return true;
  };
}

void ProgressLine::show(const std::string& text) {
  if (verbose_)
    log(text);
  else
    draw(text, true);
}

void ProgressLine::log(const std::string& text) {
  // Krylov solvers report every few iterations under one stage name; one line says it ran.
  if (!logged_.insert(text).second) return;
  std::cerr << "harmonia: " << text << '\n' << std::flush;
}

void ProgressLine::draw(const std::string& text, bool force) {
  if (!enabled_) return;
  // Solvers may report every iteration; redrawing more often than this only costs time.
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const std::string line = "harmonia: " + text;
  // Pad with spaces so that a shorter line fully covers the previous one.
  const std::size_t padding = shown_length_ > line.size() ? shown_length_ - line.size() : 0;
  std::cerr << '\r' << line << std::string(padding, ' ') << std::flush;
  shown_length_ = line.size();
}

void ProgressLine::clear() {
  if (!enabled_ || shown_length_ == 0) return;
  std::cerr << '\r' << std::string(shown_length_, ' ') << '\r' << std::flush;
  shown_length_ = 0;
}

Mesh read_input_for_output(const std::string& input, const std::string& output, bool in_place,
                           const std::string& picture, ProgressLine& progress,
                           std::vector<PhaseTiming>& timings) {
  require_extension(output, {".obj", ".gltf", ".glb"}, "output");
  if (!picture.empty()) require_extension(picture, {".png"}, "picture");
  check_output(input, output, in_place, "OUT");
  if (!picture.empty()) check_output(input, picture, false, "--picture");
  const auto start = Clock::now();
  progress.show("reading " + input);
  Mesh mesh = load_mesh(input);
  timings.push_back({"read", seconds_since(start)});
  return mesh;
}

}  // namespace harmonia::cli
