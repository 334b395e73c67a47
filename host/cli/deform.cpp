#include "cli/deform.h"

#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/gltf_output.h"
#include "cli/methods.h"
#include "cli/progress_line.h"
#include "cli/report_output.h"
#include "harmonia/deform_picture.h"
#include "harmonia/deformation_metrics.h"
#include "harmonia/edit_file.h"
#include "harmonia/gltf.h"
#include "harmonia/io.h"
#include "harmonia/surface_editor.h"

namespace harmonia::cli {

CLI::App* add_deform_command(CLI::App& app, DeformOptions& options) {
  CLI::App* command = app.add_subcommand(
      "deform", "Apply a surface edit (handles moved, the rest following along harmonic fields)");
  command->add_option("IN", options.input, "Rest mesh (.obj, .off, .ply, .stl)")->required();
  command->add_option("EDIT", options.edit,
                      "Edit file (JSON: fixed vertices, handles with translate / rotate / scale; "
                      "docs/cli.md, \"deform\")")
      ->required();
  command->add_option("OUT", options.output,
                      "Output OBJ: the deformed positions (the last frame) with the input's faces; or glTF (.glb, .gltf): the input document (or a new one) with the deformed positions")
      ->required();
  command->add_flag("--in-place", options.in_place,
                    "Allow OUT to be IN: the input file is replaced by the result");
  command->add_option("--frames", options.frames,
                      "Play the edit as N frames on one editor (transformations interpolated from "
                      "the identity, t = k/N); the report gives every frame's time (default 1)")
      ->check(CLI::Range(1, 100000));
  command->add_option("--refine", options.refinement_steps,
                      "As-rigid-as-possible refinement steps per frame on the same factorization "
                      "(0: the harmonic-field method alone)")
      ->check(CLI::Range(0, 10000));
  command->add_option("--rotation-clusters", options.rotation_clusters,
                      "Where the handles' rotations act: this many vertex clusters, each turned as "
                      "rigidly as possible (default 8 per handle and 8 more: 16 for one handle, 24 for "
                      "two; 0: the thesis' blend along the harmonic fields alone)")
      ->check(CLI::Range(0, 1000000));
  command->add_option("--frame-budget", options.frame_budget_ms,
                      "A time budget per frame in milliseconds: as many refinement steps as fit "
                      "after the frame itself (--refine then caps them); the report gives each "
                      "frame's count")
      ->check(CLI::Range(0.0, 3.6e6));
  command
      ->add_option("--backend", options.backend,
                   "cpu, vulkan, or auto (default: Vulkan where a device exists, else cpu)")
      ->check(CLI::IsMember({"auto", "cpu", "vulkan"}));
  command->add_option("--picture", options.picture,
                      "Also draw the mesh before and after, side by side from the same camera, "
                      "handles and fixed vertices coloured (.png)");
  command->add_flag("--json", options.json, "Print the report as one JSON object");
  return command;
}

namespace {

// The role of every vertex for the picture (harmonia/deform_picture.h): free, fixed, or handle i.
std::vector<int> vertex_roles(const Mesh& mesh, const EditRegions& regions) {
  std::vector<int> roles(static_cast<std::size_t>(mesh.vertex_count()), kDeformRoleFree);
  for (const int v : regions.fixed) roles[static_cast<std::size_t>(v)] = kDeformRoleFixed;
  for (std::size_t i = 0; i < regions.handles.size(); ++i)
    for (const int v : regions.handles[i]) roles[static_cast<std::size_t>(v)] = static_cast<int>(i);
  return roles;
}

}  // namespace

ExitCode run_deform(const DeformOptions& options, const GlobalOptions& global) {
  ProgressLine progress(global, options.json);
  std::vector<PhaseTiming> timings;
  const Mesh mesh = read_input_for_output(options.input, options.output, options.in_place,
                                          options.picture, progress, timings);
  auto start = Clock::now();
  EditDescription edit;
  try {
    edit = read_edit_file(options.edit, mesh);
  } catch (const Error& error) {
    throw CliFailure(exit_code_for(error.status()), error.what());
  }
  timings.push_back({"read edit", seconds_since(start)});

  SurfaceEditOptions edit_options;
  if (options.refinement_steps) edit_options.refinement_steps = *options.refinement_steps;
  if (options.frame_budget_ms) edit_options.frame_budget = *options.frame_budget_ms / 1000.0;
  if (options.rotation_clusters) edit_options.rotation_clusters = *options.rotation_clusters;
  const BackendChoice backend = backend_choice(options.backend);
  edit_options.solver = program_solver_options(backend, progress.callback());
  progress.show("setting up the editor");
  start = Clock::now();
  SurfaceEditor editor(mesh, edit.regions, edit_options);
  const double setup_seconds = seconds_since(start);
  SurfaceEditResult frame;
  frame.report = editor.setup_report();
  nlohmann::json frame_seconds = nlohmann::json::array();
  nlohmann::json frame_refinement_steps = nlohmann::json::array();
  for (int k = 1; k <= options.frames && editor.setup_report().ok(); ++k) {
    progress.show("frame " + std::to_string(k) + "/" + std::to_string(options.frames));
    const double t = static_cast<double>(k) / options.frames;
    std::vector<SimilarityTransform> transforms;
    for (const SimilarityTransform& transform : edit.transforms)
      transforms.push_back(k == options.frames ? transform : transform.partial(t));
    start = Clock::now();
    frame = editor.deform(transforms);
    frame_seconds.push_back(seconds_since(start));
    frame_refinement_steps.push_back(frame.refinement_steps);
    if (!frame.report.ok()) break;
  }
  progress.clear();
  const SolveReport& report = frame.report;
  nlohmann::json output = {
      {"status", std::string(to_string(report.status))},
      {"message", report.message},
      {"input", options.input},
      {"edit", options.edit},
      {"output", options.output},
      {"handles", edit.regions.handles.size()},
      {"fixed_vertices", edit.regions.fixed.size()},
      {"refinement_steps", edit_options.refinement_steps},
      {"rotation_clusters", edit_options.rotation_clusters.value_or(automatic_rotation_clusters(
                                static_cast<int>(edit.regions.handles.size())))},
      {"frame_budget_ms",
       options.frame_budget_ms ? nlohmann::json(*options.frame_budget_ms) : nlohmann::json()},
      {"frame_refinement_steps", frame_refinement_steps},
      {"backend", std::string(to_string(report.backend))},
      {"solver", report.solver},
      {"device", report.device},
      {"backend_notice", report.backend_notice},
      {"setup_seconds", setup_seconds},
      {"frame_seconds", frame_seconds},
      {"factorizations", editor.factorization_count()},
  };
  if (!report.ok()) {
    output["timings"] = timings_json(timings);
    if (options.json) std::cout << output.dump(2) << '\n';
    throw CliFailure(exit_code_for(report.status), options.input + ": " + report.message + " (" +
                                                       std::string(to_string(report.status)) + ")");
  }
  start = Clock::now();
  const DeformationMetrics metrics = deformation_metrics(mesh, frame.positions);
  timings.push_back({"evaluation", seconds_since(start)});
  start = Clock::now();
  progress.show("writing " + options.output);
  if (is_gltf_path(options.output)) {
    write_positions_gltf(options.input, options.output, frame.positions);
  } else {
    write_output([&] { write_mesh(options.output, Mesh{frame.positions, mesh.faces}); });
  }
  timings.push_back({"write", seconds_since(start)});
  if (!options.picture.empty()) {
    start = Clock::now();
    progress.show("drawing " + options.picture);
    DeformPictureOptions picture;
    picture.title = std::filesystem::path(options.input).filename().string() + " - " +
                    std::filesystem::path(options.edit).filename().string();
    write_output([&] {
      write_deform_picture(options.picture, mesh, frame.positions, vertex_roles(mesh, edit.regions),
                           picture);
    });
    timings.push_back({"picture", seconds_since(start)});
  }
  progress.clear();
  const EditFrameTiming& split = frame.timing;
  if (options.json) {
    output["timings"] = timings_json(timings);
    output["frame_split"] = {{"blending", split.blending},   {"assembly", split.assembly},
                             {"solve", split.solve},         {"refinement", split.refinement},
                             {"check", split.check}};
    output["vertices"] = mesh.vertex_count();
    output["faces"] = mesh.face_count();
    output["iterations"] = report.iterations;
    output["residual"] = report.residual;  // the set-up's field solves, with the frames' factor
    // Two counts of turned-over triangles, under distinct names (docs/cli.md, "deform"): against
    // the orientation the edit gives each triangle (the exit code's), and folded onto neighbours.
    output["turned_over_triangles"] = report.flipped_triangles;
    output["folded_triangles"] = metrics.folded_faces;
    output["degenerate_triangles"] = report.degenerate_triangles;
    output["turned_faces"] = metrics.turned_faces;
    output["similarity_deviation_mean"] = metrics.similarity_deviation_mean;
    output["similarity_deviation_max"] = metrics.similarity_deviation_max;
    if (!options.picture.empty()) output["picture"] = options.picture;
    std::cout << output.dump(2) << '\n';
  } else {
    FieldTable table;
    table.add("output", options.output);
    if (!options.picture.empty()) table.add("picture", options.picture);
    table.add("handles", static_cast<long long>(edit.regions.handles.size()));
    table.add("backend", std::string(to_string(report.backend)) + " (" + report.solver + ")");
    if (!report.backend_notice.empty()) table.add("backend notice", report.backend_notice);
    table.add("vertices", mesh.vertex_count());
    table.add_number("setup seconds", setup_seconds);
    table.add_number("last frame seconds", frame_seconds.back().get<double>());
    table.add("frames", options.frames);
    table.add("turned over triangles", report.flipped_triangles);
    table.add("folded triangles", metrics.folded_faces);
    table.add("similarity deviation", format_number(metrics.similarity_deviation_mean) + " mean, " +
                                          format_number(metrics.similarity_deviation_max) + " max");
    table.print(std::cout);
  }
  // As every command that writes a result with turned-over triangles (docs/cli.md, "Exit codes").
  if (report.flipped_triangles > 0 || report.degenerate_triangles > 0) {
    throw CliFailure(ExitCode::invalid_result,
                     std::to_string(report.flipped_triangles) +
                         " triangles turned over against their target orientation and " +
                         std::to_string(report.degenerate_triangles) + " of zero area; " +
                         options.output + " was written anyway");
  }
  return ExitCode::ok;
}

}  // namespace harmonia::cli
