#include "cli/transfer.h"

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/gltf_output.h"
#include "cli/methods.h"
#include "cli/progress_line.h"
#include "cli/report_output.h"
#include "harmonia/deformation_transfer.h"
#include "harmonia/gltf.h"
#include "harmonia/io.h"
#include "harmonia/marker_file.h"
#include "harmonia/transfer_picture.h"

namespace harmonia::cli {

CLI::App* add_transfer_command(CLI::App& app, TransferOptions& options) {
  CLI::App* command = app.add_subcommand(
      "transfer", "Make a target mesh perform a source mesh's poses (deformation transfer from "
                  "marker pairs)");
  command->add_option("--source-rest", options.source_rest, "The source in its rest pose")->required();
  command->add_option("--source-poses", options.source_poses,
                      "The source in each pose to transfer (the rest pose's connectivity)")
      ->required();
  command->add_option("--target", options.target, "The target in its rest pose")->required();
  command->add_option("--markers", options.markers,
                      "Marker pairs, one \"sourceVertex targetVertex\" per line (0-based; '#' "
                      "comments)")
      ->required();
  command->add_option("--out", options.out,
                      "Output folder: OUT/<pose name>.obj per pose (created if missing)")
      ->required();
  command->add_option("--method", options.method,
                      "correspondence (default: triangles matched by the marker fields, 8.4) or "
                      "quaternion (the markers' deformations interpolated harmonically, 8.5)")
      ->check(CLI::IsMember({"correspondence", "quaternion"}));
  command->add_option("--components", options.components,
                      "Largest marker-field components compared when matching triangles (default 8)")
      ->check(CLI::Range(3, 100000));
  command
      ->add_option("--backend", options.backend,
                   "cpu, vulkan, or auto (default: Vulkan where a device exists, else cpu)")
      ->check(CLI::IsMember({"auto", "cpu", "vulkan"}));
  command->add_flag("--picture", options.picture,
                    "Also draw OUT/correspondence.png (the markers' colours blended by their "
                    "fields on the source, carried to the target by the correspondence) and "
                    "OUT/<pose name>.png (each transferred pose beside its source pose)");
  command->add_flag("--json", options.json, "Print the report as one JSON object");
  return command;
}

namespace {

// The correspondence picture's name in OUT; a pose's picture is named after the pose.
constexpr const char* kCorrespondencePicture = "correspondence.png";

// OUT/<pose file name><extension>: where a pose's result goes.
std::filesystem::path pose_output(const TransferOptions& options, const std::string& pose,
                                  const std::string& extension) {
  return std::filesystem::path(options.out) /
         (std::filesystem::path(pose).stem().string() + extension);
}

}  // namespace

ExitCode run_transfer(const TransferOptions& options, const GlobalOptions& global) {
  ProgressLine progress(global, options.json);
  progress.show("reading " + options.source_rest);
  const Mesh source = load_mesh(options.source_rest);
  const Mesh target = load_mesh(options.target);
  std::vector<MarkerPair> markers;
  try {
    markers = read_marker_file(options.markers, source.vertex_count(), target.vertex_count());
  } catch (const Error& error) {
    throw CliFailure(exit_code_for(error.status()), error.what());
  }
  // Every pose is read and checked before any work, so that a bad one costs nothing.
  std::vector<Mesh> poses;
  for (const std::string& path : options.source_poses) {
    Mesh pose = load_mesh(path);
    if (pose.vertex_count() != source.vertex_count() || pose.faces != source.faces)
      throw CliFailure(ExitCode::input,
                       path + ": not the connectivity of " + options.source_rest + " (" +
                           std::to_string(pose.vertex_count()) + " vertices, " +
                           std::to_string(pose.face_count()) + " faces against " +
                           std::to_string(source.vertex_count()) + " and " +
                           std::to_string(source.face_count()) + ")");
    if (options.picture && pose_output(options, path, ".png").filename() == kCorrespondencePicture)
      throw CliFailure(ExitCode::input, path + ": its picture would replace " +
                                            kCorrespondencePicture + " (rename the pose)");
    poses.push_back(std::move(pose));
  }
  std::filesystem::create_directories(options.out);

  DeformationTransferOptions transfer_options;
  transfer_options.method = options.method == "quaternion" ? TransferMethod::quaternion
                                                            : TransferMethod::correspondence;
  transfer_options.components = options.components;
  const BackendChoice backend = backend_choice(options.backend);
  transfer_options.solver = program_solver_options(backend, progress.callback());
  progress.show("fields and correspondence");
  auto start = Clock::now();
  DeformationTransfer transfer(source, target, markers, transfer_options);
  const double setup_seconds = seconds_since(start);
  const SolveReport& setup = transfer.setup_report();
  nlohmann::json output = {
      {"status", std::string(to_string(setup.status))},
      {"message", setup.message},
      {"method", options.method},
      {"markers", markers.size()},
      {"components", options.components},
      {"backend", std::string(to_string(setup.backend))},
      {"solver", setup.solver},
      {"setup_seconds", setup_seconds},
      {"matched_triangles", transfer.matched_triangles()},
      {"unmatched_triangles", transfer.unmatched_triangles()},
  };
  if (!setup.ok()) {
    if (options.json) std::cout << output.dump(2) << '\n';
    throw CliFailure(exit_code_for(setup.status), setup.message);
  }
  // The pictures' titles name the meshes and the method; each view is fitted to its mesh.
  const std::string target_name = std::filesystem::path(options.target).filename().string();
  const auto picture_options = [&](const std::string& source_path) {
    TransferPictureOptions picture;
    picture.title = std::filesystem::path(source_path).filename().string() + " → " + target_name +
                    " - " + std::to_string(markers.size()) + " markers, " + options.method;
    return picture;
  };
  nlohmann::json pictures = nlohmann::json::array();
  if (options.picture) {
    const std::filesystem::path picture =
        std::filesystem::path(options.out) / kCorrespondencePicture;
    progress.show("drawing " + picture.string());
    write_output([&] {
      write_transfer_correspondence_picture(picture, source, target, transfer,
                                            picture_options(options.source_rest));
    });
    pictures.push_back(picture.string());
  }
  nlohmann::json pose_seconds = nlohmann::json::array();
  nlohmann::json pose_reports = nlohmann::json::array();
  std::vector<std::string> defective_poses;  // poses written with turned-over triangles
  for (std::size_t i = 0; i < poses.size(); ++i) {
    progress.show("pose " + std::to_string(i + 1) + "/" + std::to_string(poses.size()));
    start = Clock::now();
    const TransferResult result = transfer.transfer(poses[i].vertices);
    pose_seconds.push_back(seconds_since(start));
    if (!result.report.ok())
      throw CliFailure(exit_code_for(result.report.status),
                       options.source_poses[i] + ": " + result.report.message);
    // A glTF target gets its poses as glTF documents of its own format, the others as OBJ.
    const std::string extension = is_gltf_path(options.target)
                                      ? std::filesystem::path(options.target).extension().string()
                                      : std::string(".obj");
    const std::filesystem::path written = pose_output(options, options.source_poses[i], extension);
    if (is_gltf_path(written)) {
      write_positions_gltf(options.target, written.string(), result.positions);
    } else {
      write_output([&] { write_mesh(written, Mesh{result.positions, target.faces}); });
    }
    if (options.picture) {
      const std::filesystem::path picture = pose_output(options, options.source_poses[i], ".png");
      progress.show("drawing " + picture.string());
      write_output([&] {
        write_transfer_pose_picture(picture, source, poses[i].vertices, target, result.positions,
                                    transfer, picture_options(options.source_poses[i]));
      });
      pictures.push_back(picture.string());
    }
    pose_reports.push_back({{"pose", options.source_poses[i]},
                            {"output", written.string()},
                            {"turned_over_triangles", result.turned_over_triangles},
                            {"folded_triangles", result.folded_triangles},
                            {"source_folded_triangles", result.source_folded_triangles},
                            {"degenerate_triangles", result.report.degenerate_triangles}});
    if (result.turned_over_triangles > 0 || result.report.degenerate_triangles > 0)
      defective_poses.push_back(options.source_poses[i] + " (" +
                                std::to_string(result.turned_over_triangles) + " turned over, " +
                                std::to_string(result.report.degenerate_triangles) + " of zero area)");
  }
  progress.clear();
  if (options.json) {
    output["pose_seconds"] = pose_seconds;
    output["poses"] = pose_reports;
    if (options.picture) output["pictures"] = pictures;
    std::cout << output.dump(2) << '\n';
  } else {
    FieldTable table;
    table.add("method", options.method);
    table.add("markers", static_cast<long long>(markers.size()));
    table.add("matched triangles", transfer.matched_triangles());
    table.add("unmatched triangles", transfer.unmatched_triangles());
    table.add_number("setup seconds", setup_seconds);
    table.add("poses written", static_cast<long long>(poses.size()));
    table.add("output folder", options.out);
    if (options.picture) table.add("pictures", static_cast<long long>(pictures.size()));
    table.print(std::cout);
  }
  // As every command that writes a result with turned-over triangles (docs/cli.md, "Exit codes").
  if (!defective_poses.empty()) {
    std::string poses;
    for (const std::string& pose : defective_poses) poses += (poses.empty() ? "" : ", ") + pose;
    throw CliFailure(ExitCode::invalid_result, "triangles turned over against their transferred "
                                               "deformation in " + poses + "; every pose was written anyway");
  }
  return ExitCode::ok;
}

}  // namespace harmonia::cli
