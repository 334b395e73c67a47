#include "cli/sphere.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <utility>

#include <nlohmann/json.hpp>

#include "cli/gltf_output.h"
#include "cli/methods.h"
#include "cli/progress_line.h"
#include "cli/report_output.h"
#include "harmonia/gltf.h"
#include "harmonia/io.h"
#include "harmonia/sphere_picture.h"
#include "harmonia/spherical_map.h"
#include "harmonia/spherical_metrics.h"

namespace harmonia::cli {

CLI::App* add_sphere_command(CLI::App& app, SphereOptions& options) {
  CLI::App* command = app.add_subcommand(
      "sphere", "Map a closed genus-0 mesh onto the unit sphere (curvilinear coordinates)");
  command->add_option("IN", options.input, "Input mesh, closed and genus 0 (.obj, .off, .ply, .stl)")
      ->required();
  command->add_option("OUT", options.output,
                      "Output OBJ: the unit-sphere points as v lines, in the input's vertex order, "
                      "with the input's faces; or glTF (.glb, .gltf): the input document (or a new "
                      "one) with the map as a longitude/latitude texture-coordinate set of each "
                      "primitive (see --uv), or as positions with --positions")
      ->required();
  add_texcoord_options(*command, options.gltf);
  command->add_flag("--in-place", options.in_place,
                    "Allow OUT to be IN: the input file is replaced by the result");
  command->add_option("--poles", options.poles,
                      "North and south pole, two 0-based vertex indices at least 3 edges apart "
                      "(default: the ends of a geodesic diameter)")
      ->expected(2);
  command->add_option("--weights", options.weights,
                      "Laplacian of the maps in curvilinear coordinates: cotangent (default; "
                      "mean-value where the first map folds) or mean-value (positive, so the maps "
                      "cannot fold; slower)")
      ->check(CLI::IsMember({"mean-value", "cotangent"}));
  command->add_option("--rounds", options.rounds,
                      "Quasi-harmonic rounds that undo the first map's area distortion (default 3)")
      ->check(CLI::Range(0, 100));
  command->add_option("--relax-rings", options.relax_rings,
                      "Rings around the date line relaxed on the sphere at the end (default 5; 0: "
                      "none)")
      ->check(CLI::Range(0, 1000));
  command->add_option("--relax-steps", options.relax_steps,
                      "Relaxation steps (default 3; with --method relaxation: global steps, "
                      "default 100)")
      ->check(CLI::Range(0, 100000));
  command->add_option("--method", options.method,
                      "curvilinear (default, thesis chapter 7) or relaxation (the baseline of "
                      "figure 7.9: global tangential relaxation, which tends to collapse)")
      ->check(CLI::IsMember({"curvilinear", "relaxation"}));
  command
      ->add_option("--backend", options.backend,
                   "cpu, vulkan, or auto (default: Vulkan where a device exists, else cpu)")
      ->check(CLI::IsMember({"auto", "cpu", "vulkan"}));
  command->add_option("--preconditioner", options.preconditioner, preconditioner_help)
      ->check(CLI::IsMember({"multilevel", "jacobi"}));
  command->add_flag("--uv", options.uv,
                    "Also write longitude/latitude texture coordinates (vt per corner, u = "
                    "longitude / 2 pi, v = latitude / pi + 1/2), split along the date line");
  command->add_flag("--positions", options.positions,
                    "glTF output: write the sphere points as the primitives' positions instead of "
                    "a texture-coordinate set");
  command->add_option("--picture", options.picture,
                      "Also draw the sphere from two opposite sides (.png): triangles coloured by "
                      "area distortion, those turned over marked, the date line and poles drawn");
  command->add_flag("--json", options.json, "Print the report as one JSON object");
  return command;
}

namespace {

// Longitude/latitude texture coordinates per corner. A face whose corners straddle the date line
// (longitudes more than pi apart) takes the western ones past 2 pi, and a pole corner, whose
// longitude is undefined, takes the mean of the face's other two: the seam and the poles split.
TexturedMesh longitude_latitude_layout(const Mesh& mesh, const SphericalMapResult& map) {
  TexturedMesh textured;
  textured.mesh = mesh;
  textured.mesh.vertices = map.positions;
  textured.uv_faces.resize(mesh.faces.rows(), 3);
  std::map<std::pair<int, double>, int> corner_index;  // (vertex, u) -> vt row
  std::vector<Eigen::Vector2d> coordinates;
  const double pi = std::numbers::pi;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    double theta[3];
    bool pole[3];
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      theta[k] = map.angles(v, 0);
      pole[k] = v == map.north_pole || v == map.south_pole;
    }
    double low = 2.0 * pi, high = 0.0;
    for (int k = 0; k < 3; ++k)
      if (!pole[k]) {
        low = std::min(low, theta[k]);
        high = std::max(high, theta[k]);
      }
    if (high - low > pi)
      for (int k = 0; k < 3; ++k)
        if (!pole[k] && theta[k] < pi) theta[k] += 2.0 * pi;
    for (int k = 0; k < 3; ++k) {
      if (!pole[k]) continue;
      double sum = 0.0;
      int count = 0;
      for (int j = 0; j < 3; ++j)
        if (!pole[j]) {
          sum += theta[j];
          ++count;
        }
      theta[k] = count > 0 ? sum / count : 0.0;
    }
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      const double u = theta[k] / (2.0 * pi);
      const auto [slot, inserted] =
          corner_index.emplace(std::make_pair(v, u), static_cast<int>(coordinates.size()));
      if (inserted) coordinates.emplace_back(u, 1.0 - map.angles(v, 1) / pi);
      textured.uv_faces(f, k) = slot->second;
    }
  }
  textured.uv.resize(static_cast<Eigen::Index>(coordinates.size()), 2);
  for (std::size_t k = 0; k < coordinates.size(); ++k)
    textured.uv.row(static_cast<Eigen::Index>(k)) = coordinates[k].transpose();
  return textured;
}

}  // namespace

nlohmann::json spherical_metrics_json(const SphericalMetrics& metrics) {
  return {
      {"faces", metrics.faces},
      {"flipped_triangles", metrics.flipped_triangles},
      {"degenerate_triangles", metrics.degenerate_triangles},
      {"degree", metrics.degree},
      {"angle_error_mean_squared", metrics.angle_error_mean_squared},
      {"conformal_distortion_mean", metrics.conformal_distortion_mean},
      {"conformal_distortion_max", metrics.conformal_distortion_max},
      {"area_distortion_mean", metrics.area_distortion_mean},
      {"area_distortion_max", metrics.area_distortion_max},
      {"max_radius_deviation", metrics.max_radius_deviation},
  };
}

void add_spherical_metrics_rows(FieldTable& table, const SphericalMetrics& metrics) {
  table.add("faces", metrics.faces);
  table.add("flipped triangles", metrics.flipped_triangles);
  table.add("degenerate triangles", metrics.degenerate_triangles);
  table.add_number("degree", metrics.degree);
  table.add_number("angle error (mean sq.)", metrics.angle_error_mean_squared);
  table.add("conformal distortion", format_number(metrics.conformal_distortion_mean) +
                                        " mean, " + format_number(metrics.conformal_distortion_max) +
                                        " max");
  table.add("area distortion", format_number(metrics.area_distortion_mean) + " mean, " +
                                   format_number(metrics.area_distortion_max) + " max");
}

ExitCode run_sphere(const SphereOptions& options, const GlobalOptions& global) {
  ProgressLine progress(global, options.json);
  std::vector<PhaseTiming> timings;
  const Mesh mesh = read_input_for_output(options.input, options.output, options.in_place,
                                          options.picture, progress, timings);

  SphericalMapOptions map_options;
  map_options.method = options.method == "relaxation" ? SphericalMethod::relaxation
                                                      : SphericalMethod::curvilinear;
  if (options.poles.size() == 2) {
    for (const int pole : options.poles)
      if (pole < 0 || pole >= mesh.vertex_count())
        throw CliFailure(ExitCode::input, "--poles: " + std::to_string(pole) +
                                              " is not a vertex of " + options.input + " (it has " +
                                              std::to_string(mesh.vertex_count()) +
                                              ", numbered from 0)");
    map_options.poles = std::array<int, 2>{options.poles[0], options.poles[1]};
  }
  map_options.weights =
      options.weights == "cotangent" ? WeightScheme::cotangent : WeightScheme::mean_value;
  if (options.rounds) map_options.rounds = *options.rounds;
  if (options.relax_rings) map_options.relax_rings = *options.relax_rings;
  if (options.relax_steps) {
    if (map_options.method == SphericalMethod::relaxation)
      map_options.global_relaxation_steps = *options.relax_steps;
    else
      map_options.relax_steps = *options.relax_steps;
  }
  const BackendChoice backend = backend_choice(options.backend);
  progress.show("spherical map");
  map_options.solver = program_solver_options(backend, progress.callback());
  map_options.solver.preconditioner = preconditioner_choice(options.preconditioner);
  const SphericalMapResult result = spherical_map(mesh, map_options);
  progress.clear();
  const SolveReport& report = result.report;
  const bool have_map = report.ok() || report.status == Status::flipped_triangles;

  nlohmann::json output = {
      {"status", std::string(to_string(report.status))},
      {"message", report.message},
      {"input", options.input},
      {"output", options.output},
      {"method", options.method},
      {"weights", options.weights},
      {"north_pole", result.north_pole},
      {"south_pole", result.south_pole},
      {"date_line_vertices", result.date_line.size()},
      {"rounds", report.rounds},
      {"relaxed_vertices", result.relaxed_vertices},
      {"backend", std::string(to_string(report.backend))},
      {"solver", report.solver},
      {"device", report.device},
      {"backend_notice", report.backend_notice},
      {"flipped_triangles", report.flipped_triangles},
      {"degenerate_triangles", report.degenerate_triangles},
      {"fallbacks", report.fallbacks},
  };
  nlohmann::json rounds = nlohmann::json::array();
  for (const SphericalRound& round : result.rounds)
    rounds.push_back({{"area_distortion", round.area_distortion}, {"seconds", round.seconds}});
  output["round_area_distortion"] = rounds;
  if (!have_map) {
    std::vector<PhaseTiming> all = report.timings;
    all.insert(all.end(), timings.begin(), timings.end());
    output["timings"] = timings_json(all);
    if (options.json) std::cout << output.dump(2) << '\n';
    throw CliFailure(exit_code_for(report.status), options.input + ": " + report.message + " (" +
                                                       std::string(to_string(report.status)) + ")");
  }

  auto start = Clock::now();
  const SphericalMetrics metrics = spherical_metrics(mesh, result.positions);
  timings.push_back({"evaluation", seconds_since(start)});
  start = Clock::now();
  progress.show("writing " + options.output);
  if (is_gltf_path(options.output) && !options.positions) {
    write_layout_gltf(options.input, options.output, longitude_latitude_layout(mesh, result),
                      options.gltf);
  } else if (is_gltf_path(options.output)) {
    write_positions_gltf(options.input, options.output, result.positions);
  } else if (options.uv) {
    const TexturedMesh layout = longitude_latitude_layout(mesh, result);
    write_output([&] { write_obj(options.output, layout); });
  } else {
    write_output([&] { write_mesh(options.output, Mesh{result.positions, mesh.faces}); });
  }
  timings.push_back({"write", seconds_since(start)});
  if (!options.picture.empty()) {
    start = Clock::now();
    progress.show("drawing " + options.picture);
    SpherePictureOptions picture;
    const std::string method =
        map_options.method == SphericalMethod::relaxation ? "relaxation" : options.weights;
    picture.title = std::filesystem::path(options.input).filename().string() + " - sphere (" +
                    method + ") - " + sphere_picture_headline(metrics);
    picture.north_pole = result.north_pole;
    picture.south_pole = result.south_pole;
    picture.date_line = result.date_line;
    write_output(
        [&] { write_sphere_picture(options.picture, mesh, result.positions, picture); });
    timings.push_back({"picture", seconds_since(start)});
  }
  progress.clear();

  std::vector<PhaseTiming> all = report.timings;
  all.insert(all.end(), timings.begin(), timings.end());
  if (options.json) {
    output["timings"] = timings_json(all);
    output["metrics"] = spherical_metrics_json(metrics);
    output["vertices"] = mesh.vertex_count();
    if (!options.picture.empty()) output["picture"] = options.picture;
    std::cout << output.dump(2) << '\n';
  } else {
    double total = 0.0;
    for (const PhaseTiming& timing : all) total += timing.seconds;
    FieldTable table;
    table.add("output", options.output);
    if (!options.picture.empty()) table.add("picture", options.picture);
    table.add("method", options.method + " (" + options.weights + " weights, " +
                            std::to_string(report.rounds) + " quasi-harmonic rounds)");
    table.add("poles", std::to_string(result.north_pole) + " (north), " +
                           std::to_string(result.south_pole) + " (south)");
    if (!result.date_line.empty())
      table.add("date line", static_cast<long long>(result.date_line.size()));
    table.add("backend", std::string(to_string(report.backend)) + " (" + report.solver + ")");
    if (!report.backend_notice.empty()) table.add("backend notice", report.backend_notice);
    for (const std::string& fallback : report.fallbacks) table.add("fallback", fallback);
    table.add("vertices", mesh.vertex_count());
    add_spherical_metrics_rows(table, metrics);
    table.add_number("seconds", total);
    table.print(std::cout);
  }
  if (report.status == Status::flipped_triangles)
    throw CliFailure(ExitCode::invalid_result,
                     options.input + ": " + report.message + "; " + options.output +
                         " was written all the same");
  return ExitCode::ok;
}

}  // namespace harmonia::cli
