#include "cli/eval.h"

#include <fstream>
#include <iostream>
#include <vector>

#include <nlohmann/json.hpp>

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

namespace {

// The layout to measure: per-corner indices into uv, one row per face of the 3D mesh.
struct Layout {
  Eigen::MatrixX2d uv;
  Eigen::MatrixX3i uv_faces;
};

bool extension_is_obj(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".obj";
}

// True if the OBJ has at least one `vt` line; then its texture indices define the layout.
bool obj_has_texture_coordinates(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::string line;
  while (std::getline(file, line)) {
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line.compare(start, 2, "vt") != 0) continue;
    if (start + 2 < line.size() && (line[start + 2] == ' ' || line[start + 2] == '\t')) return true;
  }
  return false;
}

Layout load_layout(const std::string& path) {
  if (extension_is_obj(path) && obj_has_texture_coordinates(path)) {
    try {
      TexturedMesh textured = read_textured_obj(path);
      return {std::move(textured.uv), std::move(textured.uv_faces)};
    } catch (const Error& failure) {
      const std::string message = failure.what();
      throw CliFailure(ExitCode::input,
                       message.find(path) == std::string::npos ? path + ": " + message : message);
    }
  }
  const Mesh flat = load_mesh(path);
  return {flat.vertices.leftCols<2>(), flat.faces};
}

// The layout must belong to the 3D mesh: one face per 3D face, in the same order, and no UV vertex
// standing for two different 3D vertices (a cut may split a 3D vertex into several UV vertices,
// never the reverse). This accepts the mesh's own faces and the faces of a cut of it.
void require_matching_faces(const Mesh& mesh3d, const Layout& layout, const EvalOptions& options) {
  if (layout.uv_faces.rows() != mesh3d.faces.rows()) {
    throw CliFailure(ExitCode::input,
                     options.parameterization + " has " + std::to_string(layout.uv_faces.rows()) +
                         " faces but " + options.mesh3d + " has " +
                         std::to_string(mesh3d.faces.rows()) + "; they are not the same mesh");
  }
  std::vector<int> vertex_of_uv(layout.uv.rows(), -1);
  std::vector<int> first_face_of_uv(layout.uv.rows(), -1);
  for (int face = 0; face < mesh3d.face_count(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int uv_index = layout.uv_faces(face, corner);
      const int vertex = mesh3d.faces(face, corner);
      if (uv_index < 0 || uv_index >= layout.uv.rows()) {
        throw CliFailure(ExitCode::input, options.parameterization + ": face " +
                                              std::to_string(face) + " uses UV " +
                                              std::to_string(uv_index) + ", which does not exist");
      }
      if (vertex_of_uv[uv_index] < 0) {
        vertex_of_uv[uv_index] = vertex;
        first_face_of_uv[uv_index] = face;
      } else if (vertex_of_uv[uv_index] != vertex) {
        throw CliFailure(ExitCode::input, "faces of " + options.parameterization +
                                              " do not match " + options.mesh3d + ": UV " +
                                              std::to_string(uv_index) + " is 3D vertex " +
                                              std::to_string(vertex_of_uv[uv_index]) + " in face " +
                                              std::to_string(first_face_of_uv[uv_index]) +
                                              " but vertex " + std::to_string(vertex) +
                                              " in face " + std::to_string(face));
      }
    }
  }
}

}  // namespace

ExitCode run_eval(const EvalOptions& options, const GlobalOptions& /*global*/) {
  const Mesh mesh3d = load_mesh(options.mesh3d);
  const Layout layout = load_layout(options.parameterization);
  require_matching_faces(mesh3d, layout, options);
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
