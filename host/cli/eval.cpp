#include "cli/eval.h"

#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/layout_file.h"
#include "cli/report_output.h"
#include "harmonia/io.h"
#include "harmonia/metrics.h"
#include "cli/sphere.h"

namespace harmonia::cli {

CLI::App* add_eval_command(CLI::App& app, EvalOptions& options) {
  CLI::App* command = app.add_subcommand(
      "eval", "Measure a parameterization: flips, boundary crossings, angle/area distortion");
  command->add_option("MESH3D", options.mesh3d, "The 3D mesh")->required();
  command
      ->add_option("PARAM", options.parameterization,
                   "The layout: an OBJ with vt and texture indices, or a mesh with the same "
                   "faces whose x,y are the UVs")
      ->required();
  command->add_flag("--sphere", options.sphere,
                    "PARAM is a spherical map (a mesh with the same faces whose vertices lie on "
                    "the unit sphere, as `harmonia sphere` writes): triangles turned over against "
                    "the outward normal, degree, angle/conformal/area distortion");
  command->add_flag("--json", options.json, "Print the metrics as one JSON object");
  return command;
}

namespace {

ExitCode run_sphere_eval(const EvalOptions& options) {
  const Mesh mesh3d = load_mesh(options.mesh3d);
  const Mesh sphere = load_mesh(options.parameterization);
  if (sphere.vertex_count() != mesh3d.vertex_count() || sphere.faces != mesh3d.faces) {
    throw CliFailure(ExitCode::input,
                     options.parameterization + " does not belong to " + options.mesh3d + ": " +
                         std::to_string(sphere.vertex_count()) + " vertices and " +
                         std::to_string(sphere.face_count()) + " faces against " +
                         std::to_string(mesh3d.vertex_count()) + " and " +
                         std::to_string(mesh3d.face_count()) +
                         (sphere.face_count() == mesh3d.face_count() ? ", or other faces" : ""));
  }
  const SphericalMetrics metrics = spherical_metrics(mesh3d, sphere.vertices);
  if (options.json) {
    nlohmann::json output = spherical_metrics_json(metrics);
    output["mesh"] = options.mesh3d;
    output["sphere"] = options.parameterization;
    std::cout << output.dump(2) << '\n';
  } else {
    FieldTable table;
    table.add("mesh", options.mesh3d);
    table.add("sphere", options.parameterization);
    add_spherical_metrics_rows(table, metrics);
    table.add_number("radius deviation", metrics.max_radius_deviation);
    table.print(std::cout);
  }
  const int bad = metrics.flipped_triangles + metrics.degenerate_triangles;
  if (bad > 0) {
    throw CliFailure(ExitCode::invalid_result,
                     options.parameterization + " has " + std::to_string(metrics.flipped_triangles) +
                         " triangles turned over and " +
                         std::to_string(metrics.degenerate_triangles) +
                         " degenerate triangles on the sphere");
  }
  return ExitCode::ok;
}

}  // namespace

ExitCode run_eval(const EvalOptions& options, const GlobalOptions& /*global*/) {
  if (options.sphere) return run_sphere_eval(options);
  const Mesh mesh3d = load_mesh(options.mesh3d);
  const Layout layout = load_layout(options.parameterization);
  require_layout_of(mesh3d, options.mesh3d, layout, options.parameterization);
  const DistortionMetrics metrics = evaluate_map(mesh3d, layout.uv, layout.uv_faces);
  if (options.json) {
    nlohmann::json output = metrics_json(metrics);
    output["mesh"] = options.mesh3d;
    output["parameterization"] = options.parameterization;
    output["uv_vertices"] = layout.uv.rows();
    std::cout << output.dump(2) << '\n';
  } else {
    FieldTable table;
    table.add("mesh", options.mesh3d);
    table.add("parameterization", options.parameterization);
    table.add("uv vertices", static_cast<long long>(layout.uv.rows()));
    add_metrics_rows(table, metrics);
    table.print(std::cout);
  }
  if (metrics.flipped_triangles > 0) {
    throw CliFailure(ExitCode::invalid_result, options.parameterization + " has " +
                                                   std::to_string(metrics.flipped_triangles) +
                                                   " flipped triangles");
  }
  return ExitCode::ok;
}

}  // namespace harmonia::cli
