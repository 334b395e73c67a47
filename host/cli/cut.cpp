#include "cli/cut.h"

#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/progress_line.h"
#include "cli/report_output.h"
#include "harmonia/cut.h"
#include "harmonia/io.h"

namespace harmonia::cli {

CLI::App* add_cut_command(CLI::App& app, CutCommandOptions& options) {
  CLI::App* command = app.add_subcommand(
      "cut", "Cut a mesh open along shortest edge paths so that it becomes a disk");
  command->add_option("IN", options.input, "Input mesh (.obj, .off, .ply, .stl)")->required();
  command->add_option("OUT", options.output, "Output mesh (.obj, .off or .ply)")->required();
  command->add_flag("--in-place", options.in_place,
                    "Allow OUT to be IN: the input file is replaced by the cut mesh");
  CLI::Option* from = command->add_option(
      "--from", options.from_vertex, "First end of the cut path, 0-based (closed genus-0 meshes)");
  CLI::Option* to = command->add_option(
      "--to", options.to_vertex, "Second end of the cut path, 0-based (closed genus-0 meshes)");
  from->needs(to);
  to->needs(from);
  command->add_flag("--json", options.json, "Print the counts as one JSON object");
  return command;
}

namespace {

void require_vertex_in_range(const char* flag, int vertex, const Mesh& mesh,
                             const std::string& file) {
  if (vertex < 0 || vertex >= mesh.vertex_count()) {
    throw CliFailure(ExitCode::input, std::string(flag) + " " + std::to_string(vertex) +
                                          " is not a vertex of " + file + " (it has " +
                                          std::to_string(mesh.vertex_count()) +
                                          ", numbered from 0)");
  }
}

}  // namespace

ExitCode run_cut(const CutCommandOptions& options, const GlobalOptions& global) {
  require_extension(options.output, {".obj", ".off", ".ply"}, "output");
  check_output(options.input, options.output, options.in_place, "OUT");
  ProgressLine progress(global, options.json);
  progress.show("reading " + options.input);
  const Mesh mesh = load_mesh(options.input);

  CutOptions cut_options;
  if (options.from_vertex) {
    require_vertex_in_range("--from", *options.from_vertex, mesh, options.input);
    require_vertex_in_range("--to", *options.to_vertex, mesh, options.input);
    cut_options.from_vertex = options.from_vertex;
    cut_options.to_vertex = options.to_vertex;
  }
  progress.show("cutting");
  const CutResult cut = cut_to_disk(mesh, cut_options);
  if (cut.status != Status::ok) {
    throw CliFailure(exit_code_for(cut.status),
                     options.input + ": cannot cut into a disk: " + cut.message);
  }
  progress.show("writing " + options.output);
  write_output([&] { write_mesh(options.output, cut.disk); });
  progress.clear();

  const int added_vertices = cut.disk.vertex_count() - mesh.vertex_count();
  if (options.json) {
    const nlohmann::json output = {
        {"status", "ok"},
        {"input", options.input},
        {"output", options.output},
        {"seam_edges", cut.seam_edges},
        {"input_vertices", mesh.vertex_count()},
        {"output_vertices", cut.disk.vertex_count()},
        {"duplicated_vertices", added_vertices},
        {"faces", cut.disk.face_count()},
    };
    std::cout << output.dump(2) << '\n';
  } else {
    FieldTable table;
    table.add("output", options.output);
    table.add("seam edges", cut.seam_edges);
    table.add("vertices", std::to_string(mesh.vertex_count()) + " -> " +
                              std::to_string(cut.disk.vertex_count()) + " (" +
                              std::to_string(added_vertices) + " duplicated along the seams)");
    table.add("faces", cut.disk.face_count());
    table.print(std::cout);
  }
  return ExitCode::ok;
}

}  // namespace harmonia::cli
