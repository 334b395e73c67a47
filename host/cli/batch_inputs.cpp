#include "cli/batch_inputs.h"

#include <algorithm>
#include <map>
#include <set>
#include <system_error>

#include "cli/common.h"
#include "harmonia/io.h"

namespace harmonia::cli {

namespace fs = std::filesystem;

namespace {

// Whether the readers take this file, by its extension: asked of the readers themselves, so that
// the batch follows them when a format is added.
bool is_mesh_file(const fs::path& path) {
  try {
    (void)format_from_extension(path);
    return true;
  } catch (const Error&) {
    return false;
  }
}

// The path with symbolic links and "." / ".." resolved, for telling whether two paths name the
// same place (also for paths that do not exist yet, such as a new output folder).
fs::path resolved(const fs::path& path) {
  std::error_code error;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(path), error);
  return error ? fs::absolute(path).lexically_normal() : canonical;
}

fs::path with_obj_extension(fs::path relative) { return relative.replace_extension(".obj"); }

// The mesh files below `folder`, sorted, as paths relative to it; `skipped_folder` (the output
// folder) is not entered.
std::vector<fs::path> mesh_files_below(const fs::path& folder, const fs::path& skipped_folder) {
  std::vector<fs::path> found;
  std::error_code error;
  fs::recursive_directory_iterator walk(folder, fs::directory_options::skip_permission_denied,
                                        error);
  for (const fs::recursive_directory_iterator end; !error && walk != end; walk.increment(error)) {
    const fs::directory_entry& entry = *walk;
    std::error_code kind_error;
    if (entry.is_directory(kind_error)) {
      if (resolved(entry.path()) == skipped_folder) walk.disable_recursion_pending();
      continue;
    }
    if (entry.is_regular_file(kind_error) && is_mesh_file(entry.path()))
      found.push_back(entry.path().lexically_relative(folder));
  }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace

std::vector<BatchInput> find_batch_inputs(const std::vector<std::string>& paths,
                                          const fs::path& out_dir) {
  const fs::path resolved_out = resolved(out_dir);
  std::vector<BatchInput> inputs;
  std::set<fs::path> taken_inputs;               // Resolved input paths already in the list.
  std::map<fs::path, fs::path> input_of_output;  // Resolved output -> the input writing it.
  const auto add = [&](const fs::path& input, const fs::path& relative_output) {
    if (!taken_inputs.insert(resolved(input)).second) return;
    BatchInput batch_input{input, out_dir / with_obj_extension(relative_output), {}};
    const auto [owner, added] = input_of_output.emplace(resolved(batch_input.output), input);
    if (!added) {
      batch_input.conflict = "its output " + batch_input.output.string() +
                             " is also the output of " + owner->second.string() +
                             "; rename one of them or run them into different --out folders";
    }
    inputs.push_back(std::move(batch_input));
  };
  for (const std::string& given : paths) {
    const fs::path path(given);
    std::error_code error;
    if (!fs::is_directory(path, error)) {
      add(path, path.filename());
      continue;
    }
    if (resolved(path) == resolved_out) {
      throw CliFailure(ExitCode::usage, "--out " + out_dir.string() + " is the input folder " +
                                            given + ": its outputs would replace its inputs");
    }
    for (const fs::path& relative : mesh_files_below(path, resolved_out))
      add(path / relative, relative);
  }
  return inputs;
}

}  // namespace harmonia::cli
