#include "cli/eval.h"

#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/layout_file.h"
#include "cli/report_output.h"
#include "harmonia/io.h"
#include "harmonia/metrics.h"

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
  command->add_flag("--json", options.json, "Print the metrics as one JSON object");
  return command;
}

ExitCode run_eval(const EvalOptions& options, const GlobalOptions& /*global*/) {
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
