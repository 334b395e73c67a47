#include "cli/info.h"

#include <iostream>
#include <optional>

#include "cli/report_output.h"
#include "harmonia/gltf.h"
#include "harmonia/topology.h"

namespace harmonia::cli {

CLI::App* add_info_command(CLI::App& app, InfoOptions& options) {
  CLI::App* command = app.add_subcommand(
      "info", "Print the topology of a mesh: counts, boundary loops, genus, manifoldness, defects");
  command->add_option("MESH", options.mesh, "Mesh file (.obj, .off, .ply, .stl, .gltf, .glb; glTF: also its meshes, primitives, attributes, extensions and instances)")->required();
  command->add_flag("--json", options.json, "Print every field as one JSON object");
  return command;
}

namespace {

nlohmann::json gltf_json(const GltfSummary& summary, const GltfTriangles& triangles) {
  nlohmann::json meshes = nlohmann::json::array();
  for (const GltfMeshSummary& mesh : summary.meshes) {
    nlohmann::json primitives = nlohmann::json::array();
    for (const GltfPrimitiveSummary& primitive : mesh.primitives) {
      primitives.push_back({{"mode", primitive.mode},
                            {"vertices", primitive.vertices},
                            {"triangles", primitive.triangles},
                            {"attributes", primitive.attributes},
                            {"morph_targets", primitive.morph_targets},
                            {"draco", primitive.draco}});
    }
    meshes.push_back({{"name", mesh.name}, {"instances", mesh.instances}, {"primitives", primitives}});
  }
  return {{"meshes", meshes},
          {"scenes", summary.scenes},
          {"default_scene", summary.default_scene},
          {"nodes", summary.nodes},
          {"materials", summary.materials},
          {"textures", summary.textures},
          {"images", summary.images},
          {"skins", summary.skins},
          {"animations", summary.animations},
          {"extensions_used", summary.extensions_used},
          {"extensions_required", summary.extensions_required},
          {"skipped_point_primitives", triangles.skipped_point_primitives},
          {"skipped_line_primitives", triangles.skipped_line_primitives}};
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text.empty() ? "none" : text;
}

// The document's rows: what it holds, then a row per mesh and per primitive.
void add_gltf_rows(FieldTable& table, const GltfSummary& summary, const GltfTriangles& triangles) {
  table.add("glTF meshes", static_cast<long long>(summary.meshes.size()));
  table.add("glTF scenes", std::to_string(summary.scenes) +
                               (summary.default_scene >= 0
                                    ? " (default " + std::to_string(summary.default_scene) + ")"
                                    : " (none: every mesh once, in its own coordinates)"));
  table.add("glTF contents", std::to_string(summary.nodes) + " nodes, " +
                                 std::to_string(summary.materials) + " materials, " +
                                 std::to_string(summary.textures) + " textures, " +
                                 std::to_string(summary.images) + " images, " +
                                 std::to_string(summary.skins) + " skins, " +
                                 std::to_string(summary.animations) + " animations");
  table.add("extensions used", joined(summary.extensions_used));
  table.add("extensions required", joined(summary.extensions_required));
  if (triangles.skipped_point_primitives + triangles.skipped_line_primitives > 0) {
    table.add("skipped primitives", std::to_string(triangles.skipped_point_primitives) + " of points, " +
                                        std::to_string(triangles.skipped_line_primitives) + " of lines");
  }
  constexpr std::size_t kMeshRows = 40;
  for (std::size_t m = 0; m < summary.meshes.size() && m < kMeshRows; ++m) {
    const GltfMeshSummary& mesh = summary.meshes[m];
    table.add("mesh " + std::to_string(m), (mesh.name.empty() ? std::string("(no name)") : "'" + mesh.name + "'") +
                                               ", " + std::to_string(mesh.instances) + " instances in the scene");
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const GltfPrimitiveSummary& primitive = mesh.primitives[p];
      table.add("  primitive " + std::to_string(p),
                "mode " + std::to_string(primitive.mode) + ", " + std::to_string(primitive.vertices) +
                    " vertices, " + std::to_string(primitive.triangles) + " triangles; " +
                    joined(primitive.attributes) +
                    (primitive.morph_targets > 0 ? "; " + std::to_string(primitive.morph_targets) + " morph targets" : "") +
                    (primitive.draco ? "; Draco" : ""));
    }
  }
  if (summary.meshes.size() > kMeshRows) {
    table.add("meshes not listed", static_cast<long long>(summary.meshes.size() - kMeshRows));
  }
}

}  // namespace

ExitCode run_info(const InfoOptions& options, const GlobalOptions& /*global*/) {
  const Mesh mesh = load_mesh(options.mesh);
  const TopologyReport report = analyze_topology(mesh);
  std::optional<GltfSummary> gltf;
  GltfTriangles gltf_triangles;
  if (is_gltf_path(options.mesh)) {
    const GltfDocument document = load_gltf(options.mesh);
    gltf = document.summary();
    gltf_triangles = document.scene_triangles();
  }
  if (options.json) {
    nlohmann::json output = topology_json(report);
    output["file"] = options.mesh;
    if (gltf) output["gltf"] = gltf_json(*gltf, gltf_triangles);
    std::cout << output.dump(2) << '\n';
    return ExitCode::ok;
  }
  // Index lists can be as long as the mesh; text mode shows the first few and the count.
  constexpr std::size_t list_limit = 20;
  FieldTable table;
  table.add("file", options.mesh);
  add_topology_rows(table, report, list_limit);
  if (gltf) add_gltf_rows(table, *gltf, gltf_triangles);
  table.print(std::cout);
  return ExitCode::ok;
}

}  // namespace harmonia::cli
