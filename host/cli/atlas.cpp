#include "cli/atlas.h"

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "cli/methods.h"
#include "cli/progress_line.h"
#include "cli/report_output.h"
#include "harmonia/atlas_io.h"
#include "harmonia/atlas_picture.h"
#include "harmonia/cleanup.h"

namespace harmonia::cli {

namespace atlas_limits {

std::string with_default(const std::string& text, double value) {
  return text + " (default " + format_number(value) + ")";
}

CLI::Validator greater_than_one() {
  return CLI::Validator(
      [](std::string& text) {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        const bool parsed = end != text.c_str() && *end == '\0';
        return parsed && value > 1.0 ? std::string()
                                     : "must be a number greater than 1 (1 is an isometry)";
      },
      "NUMBER > 1");
}

}  // namespace atlas_limits

namespace {

// The ranges of the other options TextureAtlasOptions documents (the command line refuses a
// value outside them as a usage error, before any work).
constexpr double kSmallestNormalDeviation = 1.0;
constexpr double kLargestNormalDeviation = 89.0;
constexpr int kMostThreads = 1024;

}  // namespace

CLI::App* add_atlas_command(CLI::App& app, AtlasOptions& options) {
  const TextureAtlasOptions defaults;
  options.resolution = defaults.resolution;
  options.padding = defaults.padding;
  options.max_distortion = defaults.max_distortion;
  options.max_normal_deviation_degrees = defaults.max_normal_deviation_degrees;
  options.threads = defaults.threads;
  CLI::App* command = app.add_subcommand(
      "atlas",
      "Texture atlas of any triangle mesh (closed or open, any genus, several parts): "
      "write an OBJ with per-corner vt in [0, 1]");
  command->add_option("IN", options.input, "Input mesh (.obj, .off, .ply, .stl)")->required();
  command
      ->add_option("OUT", options.output,
                   "Output OBJ: the input's vertices and faces in input order, per-corner vt, "
                   "a `g chart_N` line wherever the chart changes")
      ->required();
  command->add_flag("--in-place", options.in_place,
                    "Allow OUT to be IN: the input file is replaced by the result");
  add_atlas_layout_options(*command, options.resolution, options.padding, options.max_distortion);
  command
      ->add_option("--max-normal-deviation", options.max_normal_deviation_degrees,
                   atlas_limits::with_default(
                       "Advanced: the most a face's normal may turn from its chart's mean normal, "
                       "in degrees (smaller: more, flatter charts)",
                       defaults.max_normal_deviation_degrees))
      ->check(CLI::Range(kSmallestNormalDeviation, kLargestNormalDeviation));
  command
      ->add_option("--threads", options.threads,
                   "Threads flattening the charts (default 0: one per core)")
      ->check(CLI::Range(0, kMostThreads));
  command
      ->add_option("--cleanup", options.cleanup,
                   "none (default: take the mesh as it is; degenerate faces and non-manifold "
                   "vertices are handled by the atlas), strict (refuse dirty input and say why) "
                   "or repair (merge duplicate vertices, drop degenerate and duplicate faces, fix "
                   "orientation; non-manifold edges and vertices are kept and cut)")
      ->check(CLI::IsMember({"none", "strict", "repair"}));
  command->add_flag("--keep-splits", options.keep_splits,
                    "Make every split of the file (vertices repeated at one point, as exporters "
                    "write seams and hard edges) a chart boundary; by default charts span them");
  command->add_option("--picture", options.picture,
                      "Also draw the atlas coloured by distortion beside the mesh wearing a "
                      "checker through it (.png)");
  command
      ->add_option("--backend", options.backend,
                   "cpu, vulkan, or auto (default: Vulkan where a hardware device exists and the mesh has "
                   "50,000 faces or more, else cpu); on a device the charts' linear ABF systems are "
                   "solved together")
      ->check(CLI::IsMember({"auto", "cpu", "vulkan"}));
  command->add_flag("--json", options.json, "Print the report as one JSON object");
  return command;
}

namespace {

// The mesh the atlas is made of, and the mesh OUT is written with.
struct PreparedSurface {
  Mesh surface;  // The input, or the input repaired.
  // The input's vertices in input order, with the surface's faces numbered as the input's
  // vertices: OUT keeps the input's numbering even after a repair (as `unwrap` does).
  Mesh written;
  std::vector<std::string> changes;  // One line per kind of repair.
};

PreparedSurface prepare_surface(const Mesh& input, const AtlasOptions& options) {
  PreparedSurface prepared;
  if (options.cleanup == "none") {
    prepared.surface = input;
    prepared.written = input;
    return prepared;
  }
  CleanupOptions cleanup_options;
  cleanup_options.mode = options.cleanup == "repair" ? CleanupMode::repair : CleanupMode::strict;
  // What welding makes non-manifold (a hard edge shared by several surfaces, touching parts) is a
  // chart boundary for the atlas, not a reason to refuse the asset.
  cleanup_options.keep_non_manifold = true;
  CleanupResult cleaned = cleanup(input, cleanup_options);
  if (cleaned.status != Status::ok) {
    std::string reason = options.input + ": " + cleaned.message;
    if (cleanup_options.mode == CleanupMode::strict) {
      reason +=
          " (`--cleanup repair` may fix it; `--cleanup none` lets the atlas take it as it is)";
    }
    throw CliFailure(ExitCode::input, reason);
  }
  prepared.changes = std::move(cleaned.changes);
  prepared.surface = std::move(cleaned.mesh);
  prepared.written.vertices = input.vertices;
  prepared.written.faces = prepared.surface.faces;
  for (Eigen::Index face = 0; face < prepared.written.faces.rows(); ++face)
    for (int corner = 0; corner < 3; ++corner)
      prepared.written.faces(face, corner) =
          cleaned.original_vertex(prepared.surface.faces(face, corner));
  return prepared;
}

// Runs the atlas; a failure the library throws (e.g. charts that cannot fit the resolution)
// becomes the report's status, so that it is reported like one the library returns.
TextureAtlas make_atlas(const Mesh& surface, const TextureAtlasOptions& options) {
  try {
    return texture_atlas(surface, options);
  } catch (const Error& error) {
    TextureAtlas failed;
    failed.report.status = error.status();
    failed.report.message = error.what();
    return failed;
  }
}

double total_seconds(const std::vector<PhaseTiming>& timings) {
  double total = 0.0;
  for (const PhaseTiming& timing : timings) total += timing.seconds;
  return total;
}

nlohmann::json chart_json(const AtlasChart& chart) {
  const Eigen::AlignedBox2d& box = chart.texel_box;
  return {
      {"faces", chart.faces.size()},
      {"method", std::string(to_string(chart.method))},
      {"piece_of_a_cut", chart.piece_of_a_cut},
      {"l2_stretch", chart.l2_stretch},
      {"angle_distortion", chart.angle_distortion},
      {"area_distortion", chart.area_distortion},
      {"surface_area", chart.surface_area},
      {"texel_box",
       {{"min", {box.min().x(), box.min().y()}}, {"max", {box.max().x(), box.max().y()}}}},
  };
}

nlohmann::json report_json(const AtlasOptions& options, const TextureAtlasOptions& atlas_options,
                           const TextureAtlas& atlas, const std::vector<PhaseTiming>& timings) {
  const SolveReport& report = atlas.report;
  const AtlasMetrics& metrics = atlas.metrics;
  nlohmann::json per_chart = nlohmann::json::array();
  for (const AtlasChart& chart : atlas.charts) per_chart.push_back(chart_json(chart));
  return {
      {"status", std::string(to_string(report.status))},
      {"message", report.message},
      {"input", options.input},
      {"output", options.output},
      {"cleanup", options.cleanup},
      {"resolution", atlas_options.resolution},
      {"padding", atlas_options.padding},
      {"max_distortion", atlas_options.max_distortion},
      {"max_normal_deviation", atlas_options.max_normal_deviation_degrees},
      {"keep_splits", atlas_options.keep_splits},
      {"welded_vertices", atlas.welded_vertices},
      {"backend", std::string(to_string(report.backend))},
      {"solver", report.solver},
      {"backend_notice", report.backend_notice},
      {"faces", metrics.faces},
      {"charts", metrics.charts},
      {"coverage", metrics.coverage},
      {"texels_per_unit", metrics.texels_per_unit},
      {"l2_stretch", metrics.l2_stretch},
      {"angle_distortion", metrics.angle_distortion},
      {"area_distortion", metrics.area_distortion},
      {"flipped_triangles", metrics.flipped_triangles},
      {"mirrored_charts", metrics.mirrored_charts},
      {"overlapping_texels", metrics.overlapping_texels},
      {"boundary_crossings", metrics.boundary_crossings},
      {"dropped_faces", metrics.dropped_faces},
      {"timings", timings_json(timings)},
      {"seconds", total_seconds(timings)},
      {"per_chart", per_chart},
  };
}

// "linear_abf 40, free_boundary 2, single_triangle 1": how many charts each method flattened.
std::string methods_summary(const TextureAtlas& atlas) {
  std::map<std::string, int> count_of_method;
  for (const AtlasChart& chart : atlas.charts)
    ++count_of_method[std::string(to_string(chart.method))];
  std::string text;
  for (const auto& [method, count] : count_of_method)
    text += (text.empty() ? "" : ", ") + method + " " + std::to_string(count);
  return text;
}

void print_table(const AtlasOptions& options, const TextureAtlas& atlas,
                 const std::vector<PhaseTiming>& timings) {
  const AtlasMetrics& metrics = atlas.metrics;
  FieldTable table;
  table.add("output", options.output);
  if (!options.picture.empty()) table.add("picture", options.picture);
  table.add("resolution", std::to_string(atlas.resolution) + " x " +
                              std::to_string(atlas.resolution) + " texels");
  table.add("faces", metrics.faces);
  table.add("charts", metrics.charts);
  table.add("chart methods", methods_summary(atlas));
  table.add("backend", std::string(to_string(atlas.report.backend)) +
                           (atlas.report.solver.empty() ? "" : " (" + atlas.report.solver + ")"));
  if (!atlas.report.backend_notice.empty()) table.add("backend notice", atlas.report.backend_notice);
  table.add_number("coverage", metrics.coverage);
  table.add_number("texels per unit", metrics.texels_per_unit);
  table.add_number("L2 stretch", metrics.l2_stretch);
  table.add_number("angle distortion", metrics.angle_distortion);
  table.add_number("area distortion", metrics.area_distortion);
  table.add("flipped triangles", metrics.flipped_triangles);
  table.add("mirrored charts", metrics.mirrored_charts);
  table.add("overlapping texels", metrics.overlapping_texels);
  table.add("boundary crossings", metrics.boundary_crossings);
  table.add("dropped faces", metrics.dropped_faces);
  table.add_number("seconds", total_seconds(timings));
  table.print(std::cout);
}

// What makes a written atlas unusable as a texture layout, in words; empty when nothing does.
std::string atlas_defects(const AtlasMetrics& metrics) {
  std::string defects;
  const auto add = [&defects](int count, const std::string& what) {
    if (count > 0) defects += (defects.empty() ? "" : ", ") + std::to_string(count) + " " + what;
  };
  add(metrics.flipped_triangles, "flipped triangles");
  add(metrics.mirrored_charts, "mirrored charts");
  add(metrics.overlapping_texels, "overlapping texels");
  add(metrics.boundary_crossings, "crossing chart boundaries");
  add(metrics.dropped_faces, "dropped faces");
  return defects;
}

}  // namespace

ExitCode run_atlas(const AtlasOptions& options, const GlobalOptions& global) {
  ProgressLine progress(global, options.json);
  std::vector<PhaseTiming> timings;
  const Mesh input = read_input_for_output(options.input, options.output, options.in_place,
                                           options.picture, progress, timings);
  auto start = Clock::now();
  const PreparedSurface prepared = prepare_surface(input, options);
  timings.push_back({"cleanup", seconds_since(start)});
  progress.clear();
  for (const std::string& change : prepared.changes) note(global, "cleanup: " + change);

  TextureAtlasOptions atlas_options;
  atlas_options.resolution = options.resolution;
  atlas_options.padding = options.padding;
  atlas_options.max_distortion = options.max_distortion;
  atlas_options.max_normal_deviation_degrees = options.max_normal_deviation_degrees;
  atlas_options.threads = options.threads;
  atlas_options.keep_splits = options.keep_splits;
  atlas_options.solver = program_solver_options(backend_choice(options.backend), progress.callback());
  const TextureAtlas atlas = make_atlas(prepared.surface, atlas_options);
  progress.clear();
  timings.insert(timings.end(), atlas.report.timings.begin(), atlas.report.timings.end());
  if (!atlas.report.ok()) {
    if (options.json)
      std::cout << report_json(options, atlas_options, atlas, timings).dump(2) << '\n';
    throw CliFailure(exit_code_for(atlas.report.status),
                     options.input + ": " + atlas.report.message);
  }

  start = Clock::now();
  progress.show("writing " + options.output);
  write_output([&] { write_atlas_obj(options.output, prepared.written, atlas); });
  timings.push_back({"write", seconds_since(start)});
  if (!options.picture.empty()) {
    start = Clock::now();
    progress.show("drawing " + options.picture);
    AtlasPictureOptions picture;
    picture.title = std::filesystem::path(options.input).filename().string() + " - " +
                    std::to_string(atlas.resolution) + " x " + std::to_string(atlas.resolution) +
                    " texels - " + std::to_string(atlas.metrics.charts) + " charts";
    write_output([&] { write_atlas_picture(options.picture, prepared.surface, atlas, picture); });
    timings.push_back({"picture", seconds_since(start)});
  }
  progress.clear();

  if (options.json) {
    nlohmann::json output = report_json(options, atlas_options, atlas, timings);
    output["vertices"] = input.vertex_count();
    output["cleanup_changes"] = prepared.changes;
    if (!options.picture.empty()) output["picture"] = options.picture;
    std::cout << output.dump(2) << '\n';
  } else {
    print_table(options, atlas, timings);
  }
  if (const std::string defects = atlas_defects(atlas.metrics); !defects.empty()) {
    throw CliFailure(ExitCode::invalid_result,
                     "the atlas has " + defects + "; " + options.output + " was written anyway");
  }
  return ExitCode::ok;
}

}  // namespace harmonia::cli
