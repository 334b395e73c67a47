#include "cli/info.h"

#include <iostream>

#include "cli/report_output.h"
#include "harmonia/topology.h"

namespace harmonia::cli {

CLI::App* add_info_command(CLI::App& app, InfoOptions& options) {
  CLI::App* command = app.add_subcommand(
      "info", "Print the topology of a mesh: counts, boundary loops, genus, manifoldness, defects");
  command->add_option("MESH", options.mesh, "Mesh file (.obj, .off, .ply, .stl)")->required();
  command->add_flag("--json", options.json, "Print every field as one JSON object");
  return command;
}

ExitCode run_info(const InfoOptions& options, const GlobalOptions& /*global*/) {
  const Mesh mesh = load_mesh(options.mesh);
  const TopologyReport report = analyze_topology(mesh);
  if (options.json) {
    nlohmann::json output = topology_json(report);
    output["file"] = options.mesh;
    std::cout << output.dump(2) << '\n';
    return ExitCode::ok;
  }
  // Index lists can be as long as the mesh; text mode shows the first few and the count.
  constexpr std::size_t list_limit = 20;
  FieldTable table;
  table.add("file", options.mesh);
  add_topology_rows(table, report, list_limit);
  table.print(std::cout);
  return ExitCode::ok;
}

}  // namespace harmonia::cli
