#include "cli/batch_inputs.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <set>
#include <system_error>

#include "cli/common.h"
#include "harmonia/gltf.h"
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

// The outputs, one per input and never one for two (see find_batch_inputs): first the relative
// path with .obj for its extension (a glTF input keeps its .gltf or .glb); the inputs that would share one keep their extension in
// front of the .obj; inputs that still share one (the same relative path below two given folders)
// are numbered in input order, "-2", "-3", past any name already taken. (Inputs that share their
// whole relative path go straight to the numbers: their extensions would not tell them apart.)
void name_outputs(std::vector<BatchInput>& inputs, const std::vector<fs::path>& relative_names,
                  const fs::path& out_dir) {
  const auto owners_of = [&](const auto& name_of) {
    std::map<fs::path, std::vector<std::size_t>> owners;
    for (std::size_t i = 0; i < inputs.size(); ++i) owners[resolved(out_dir / name_of(i))].push_back(i);
    return owners;
  };
  // glTF comes out as glTF (its document kept whole), everything else as OBJ.
  std::vector<std::string> extensions(inputs.size(), ".obj");
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (is_gltf_path(relative_names[i])) {
      extensions[i] = relative_names[i].extension().string();
      std::transform(extensions[i].begin(), extensions[i].end(), extensions[i].begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    }
  }
  std::vector<fs::path> names(inputs.size());
  for (std::size_t i = 0; i < inputs.size(); ++i)
    names[i] = fs::path(relative_names[i]).replace_extension(extensions[i]);
  for (const auto& [output, owners] : owners_of([&](std::size_t i) { return names[i]; }))
    if (owners.size() > 1 && std::any_of(owners.begin(), owners.end(), [&](std::size_t i) {
          return relative_names[i] != relative_names[owners.front()];
        }))
      for (const std::size_t i : owners) names[i] = fs::path(relative_names[i]) += extensions[i];
  std::set<fs::path> taken;
  for (std::size_t i = 0; i < inputs.size(); ++i) taken.insert(resolved(out_dir / names[i]));
  for (const auto& [output, owners] : owners_of([&](std::size_t i) { return names[i]; }))
    for (std::size_t k = 1; k < owners.size(); ++k) {
      fs::path& name = names[owners[k]];
      const fs::path stem = fs::path(name).replace_extension();
      for (int number = 2;; ++number) {
        fs::path numbered = stem;
        numbered += "-" + std::to_string(number) + extensions[owners[k]];
        if (taken.insert(resolved(out_dir / numbered)).second) {
          name = numbered;
          break;
        }
      }
    }
  for (std::size_t i = 0; i < inputs.size(); ++i) inputs[i].output = out_dir / names[i];
}

}  // namespace

std::vector<BatchInput> find_batch_inputs(const std::vector<std::string>& paths,
                                          const fs::path& out_dir) {
  const fs::path resolved_out = resolved(out_dir);
  std::vector<BatchInput> inputs;
  std::vector<fs::path> relative_names;       // Each input's path below OUT, before naming.
  std::set<fs::path> taken_inputs;            // Resolved input paths already in the list.
  const auto add = [&](const fs::path& input, const fs::path& relative) {
    if (!taken_inputs.insert(resolved(input)).second) return;
    inputs.push_back(BatchInput{input, {}});
    relative_names.push_back(relative);
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
  name_outputs(inputs, relative_names, out_dir);
  return inputs;
}

}  // namespace harmonia::cli
