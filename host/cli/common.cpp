#include "cli/common.h"

#include <algorithm>
#include <cctype>
#include <iostream>
#include <system_error>

#include "harmonia/io.h"
#include "harmonia/topology.h"

namespace harmonia::cli {

ExitCode exit_code_for(Status status) {
  switch (status) {
    case Status::ok:
      return ExitCode::ok;
    case Status::invalid_input:
    case Status::parse_error:
    case Status::not_a_disk:
    case Status::not_a_sphere:
    case Status::non_manifold:
      return ExitCode::input;
    case Status::flipped_triangles:
      return ExitCode::invalid_result;
    case Status::not_converged:
    case Status::numerical_failure:
      return ExitCode::numerical;
    case Status::io_error:
    case Status::cancelled:
    case Status::unsupported:
    case Status::device_failure:
      return ExitCode::environment;
  }
  return ExitCode::numerical;  // Unreachable: -Werror=switch keeps the list above complete.
}

namespace {

// The readers name the file in their messages; add it where a message does not (e.g. a failure
// to open that only says why), so that every reason printed tells the user which file it is about.
std::string naming_the_file(const std::filesystem::path& path, const std::string& message) {
  if (message.find(path.string()) != std::string::npos) return message;
  return path.string() + ": " + message;
}

}  // namespace

namespace {

void require_input_file(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    throw CliFailure(ExitCode::input, path.string() + ": no such file");
  }
  if (std::filesystem::is_directory(path, error)) {
    throw CliFailure(ExitCode::input, path.string() + ": is a directory, not a mesh file");
  }
}

}  // namespace

namespace {

// The program's --mesh: the glTF mesh a command that takes one mesh reads ("" = the whole scene).
std::string chosen_gltf_mesh;

}  // namespace

void choose_gltf_mesh(const std::string& name_or_index) { chosen_gltf_mesh = name_or_index; }

const std::string& gltf_mesh_choice() { return chosen_gltf_mesh; }

GltfTriangles gltf_triangles_of(const GltfDocument& document) {
  if (chosen_gltf_mesh.empty()) return document.scene_triangles();
  return document.mesh_triangles(document.find_mesh(chosen_gltf_mesh));
}

std::optional<ObjAsset> kept_obj_asset(const std::filesystem::path& input) {
  std::string extension = input.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".obj") return std::nullopt;
  try {
    ObjAsset asset = read_obj_asset(input);
    if (!asset.carries_more_than_a_mesh()) return std::nullopt;
    return asset;
  } catch (const Error& failure) {
    throw CliFailure(ExitCode::input, naming_the_file(input, failure.what()));
  }
}

GltfDocument load_gltf(const std::filesystem::path& path) {
  require_input_file(path);
  try {
    return GltfDocument::read(path);
  } catch (const Error& failure) {
    throw CliFailure(ExitCode::input, naming_the_file(path, failure.what()));
  }
}

Mesh load_mesh(const std::filesystem::path& path) {
  require_input_file(path);
  Mesh mesh;
  try {
    mesh = is_gltf_path(path) ? gltf_triangles_of(GltfDocument::read(path)).mesh : read_mesh(path);
  } catch (const Error& failure) {
    throw CliFailure(ExitCode::input, naming_the_file(path, failure.what()));
  }
  std::string message;
  if (check_indices_and_coordinates(mesh, &message) != Status::ok) {
    throw CliFailure(ExitCode::input, naming_the_file(path, message));
  }
  return mesh;
}

void require_extension(const std::filesystem::path& path,
                       std::initializer_list<const char*> allowed, const std::string& what) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::string listed;
  for (const char* candidate : allowed) {
    if (extension == candidate) return;
    listed += listed.empty() ? "" : ", ";
    listed += candidate;
  }
  throw CliFailure(ExitCode::usage, what + " " + path.string() + " must end in " + listed);
}

void check_output(const std::filesystem::path& input, const std::filesystem::path& output,
                  bool in_place, const std::string& what) {
  std::error_code error;
  if (!in_place && std::filesystem::exists(output, error) &&
      std::filesystem::equivalent(input, output, error)) {
    throw CliFailure(ExitCode::usage, what + " " + output.string() + " is the input file " +
                                          input.string() +
                                          ": writing it would replace the input; choose another "
                                          "name, or pass --in-place to replace it on purpose");
  }
  try {
    check_writable(output);
  } catch (const Error& unwritable) {
    throw CliFailure(ExitCode::environment, unwritable.what());
  }
}

void note(const GlobalOptions& global, const std::string& message) {
  if (!global.quiet) std::cerr << "harmonia: " << message << '\n';
}

}  // namespace harmonia::cli
