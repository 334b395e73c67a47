#include "cli/atlas.h"

#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "cli/atlas_gltf.h"
#include "cli/atlas_report.h"
#include "cli/methods.h"
#include "cli/progress_line.h"
#include "cli/report_output.h"
#include "harmonia/atlas_io.h"
#include "harmonia/atlas_picture.h"
#include "harmonia/view_page.h"
#include "atlas/atlas_metrics.h"
#include "harmonia/cleanup.h"
#include "harmonia/gltf.h"

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

CLI::Validator atlas_resolution() {
  return CLI::Validator(
      [](std::string& text) {
        std::istringstream in(text);
        AtlasResolution resolution;
        in >> resolution;
        const auto in_range = [](int side) { return side >= kSmallestResolution && side <= kLargestResolution; };
        const bool whole = !in.fail() && (in.eof() || in.peek() == std::char_traits<char>::eof());
        if (!whole || !in_range(resolution.width) || !in_range(resolution.height)) {
          return "must be N (an N x N atlas) or WxH, each side in [" + std::to_string(kSmallestResolution) + ", " +
                 std::to_string(kLargestResolution) + "]";
        }
        return std::string();
      },
      "N|WxH");
}

}  // namespace atlas_limits

std::string AtlasResolution::text() const {
  return width == height ? std::to_string(width) : std::to_string(width) + "x" + std::to_string(height);
}

std::istream& operator>>(std::istream& in, AtlasResolution& resolution) {
  int width = 0;
  if (!(in >> width)) return in;
  int height = width;
  // (peek at the end of the stream would mark it failed)
  if (const int next = in.eof() ? std::char_traits<char>::eof() : in.peek(); next == 'x' || next == 'X' || next == '*') {
    in.get();
    if (!(in >> height)) return in;
  }
  resolution = AtlasResolution{width, height};
  return in;
}

namespace {

// The ranges of the other options TextureAtlasOptions documents (the command line refuses a
// value outside them as a usage error, before any work).
constexpr double kSmallestNormalDeviation = 1.0;
constexpr double kLargestNormalDeviation = 89.0;
constexpr int kMostThreads = 1024;

}  // namespace

CLI::App* add_atlas_command(CLI::App& app, AtlasOptions& options) {
  const TextureAtlasOptions defaults;
  options.resolution = AtlasResolution{defaults.resolution, defaults.resolution};
  options.padding = defaults.padding;
  options.max_distortion = defaults.max_distortion;
  options.max_normal_deviation_degrees = defaults.max_normal_deviation_degrees;
  options.threads = defaults.threads;
  CLI::App* command = app.add_subcommand(
      "atlas",
      "Texture atlas of any triangle mesh (closed or open, any genus, several parts): "
      "write an OBJ with per-corner vt in [0, 1]");
  command->add_option("IN", options.input, "Input mesh (.obj, .off, .ply, .stl, .gltf, .glb)")
      ->required();
  command
      ->add_option("OUT", options.output,
                   "Output OBJ: the input's vertices and faces in input order, per-corner vt, "
                   "a `g chart_N` line wherever the chart changes; or glTF (.glb, .gltf): the "
                   "input document with the atlas in a texture-coordinate set of each primitive, "
                   "vertices split along chart seams, everything else kept")
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
      ->add_option("--texels-per-unit", options.texels_per_unit,
                   "Pack at exactly this many texels per unit of the model's length (one density "
                   "for every mesh made at it, as lightmaps need) instead of the densest that fits; "
                   "charts that do not fit one square of the resolution at it go on further pages "
                   "(a chart larger than a page is split)")
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--max-pages", options.max_pages,
                   "With --texels-per-unit: the most pages the atlas may have (default 0: as many "
                   "as the charts need); more are refused")
      ->check(CLI::NonNegativeNumber);
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
  command->add_flag("--repack", options.repack,
                    "Keep the input's own UV charts (an OBJ with `vt` on every corner): lay each "
                    "out as it is at the atlas' one texel density, turned by quarter turns at "
                    "most, and only pack them");
  command->add_flag("--join-charts", options.join_charts,
                    "After flattening, join neighbouring charts whose union flattens within "
                    "--max-distortion: fewer charts and seams, for some coverage and time");
  command
      ->add_option("--group", options.group,
                   "glTF output: one atlas per mesh (default), per primitive, or one for the "
                   "whole scene at one texel density (each mesh once, in the world frame of its "
                   "first instance)")
      ->check(CLI::IsMember({"mesh", "primitive", "scene"}));
  command
      ->add_option("--texcoord", options.texcoord,
                   "glTF output: the TEXCOORD_n set the atlas goes to (default: the lowest set "
                   "each primitive lacks: TEXCOORD_0 on a bare mesh, TEXCOORD_1 on a textured one)")
      ->check(CLI::Range(0, 31));
  command->add_flag("--overwrite", options.overwrite,
                    "glTF output: allow --texcoord to name a set the primitive has (replaced)");
  command->add_option("--picture", options.picture,
                      "Also draw the atlas coloured by distortion beside the mesh wearing a "
                      "checker through it (.png)");
  command->add_option("--view", options.view,
                      "Also write a page to look at the atlas in a browser (.html; see `harmonia "
                      "view`); OBJ output only");
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
  Eigen::VectorXi original_face;     // Surface face -> input face (after a repair only).
};

// --repack: the OBJ input's own UVs, per face corner, packed anew (repack_texture_atlas).
TextureAtlas repacked_atlas(const AtlasOptions& options, const Mesh& input, const TextureAtlasOptions& atlas_options) {
  const std::optional<ObjAsset> asset = kept_obj_asset(options.input);
  if (!asset || asset->texcoords.rows() == 0) {
    throw CliFailure(ExitCode::input, options.input + ": --repack keeps the input's texture coordinates, and it has "
                                                      "none (an OBJ with `vt` on every face corner is needed)");
  }
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv(input.faces.rows(), 6);
  for (Eigen::Index f = 0; f < input.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int row = asset->texcoord_faces(f, k);
      if (row < 0) {
        throw CliFailure(ExitCode::input, options.input + ": --repack keeps the input's texture coordinates, but " +
                                              "triangle " + std::to_string(f) + " (in file order, polygons fanned) " +
                                              "has a corner without one");
      }
      corner_uv(f, 2 * k) = asset->texcoords(row, 0);
      corner_uv(f, 2 * k + 1) = asset->texcoords(row, 1);
    }
  }
  try {
    return repack_texture_atlas(input, corner_uv, atlas_options);
  } catch (const Error& error) {
    TextureAtlas failed;
    failed.report.status = error.status();
    failed.report.message = error.what();
    return failed;
  }
}

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
  prepared.original_face = std::move(cleaned.original_face);
  prepared.surface = std::move(cleaned.mesh);
  prepared.written.vertices = input.vertices;
  prepared.written.faces = prepared.surface.faces;
  for (Eigen::Index face = 0; face < prepared.written.faces.rows(); ++face)
    for (int corner = 0; corner < 3; ++corner)
      prepared.written.faces(face, corner) =
          cleaned.original_vertex(prepared.surface.faces(face, corner));
  return prepared;
}

}  // namespace

TextureAtlasOptions library_options(const AtlasOptions& options, ProgressLine& progress) {
  TextureAtlasOptions atlas_options;
  atlas_options.resolution = options.resolution.width;
  atlas_options.height = options.resolution.height == options.resolution.width ? 0 : options.resolution.height;
  atlas_options.padding = options.padding;
  atlas_options.max_distortion = options.max_distortion;
  atlas_options.max_normal_deviation_degrees = options.max_normal_deviation_degrees;
  atlas_options.threads = options.threads;
  atlas_options.texels_per_unit = options.texels_per_unit;
  atlas_options.max_pages = options.max_pages;
  atlas_options.keep_splits = options.keep_splits;
  atlas_options.join_charts = options.join_charts;
  atlas_options.solver = program_solver_options(backend_choice(options.backend), progress.callback());
  return atlas_options;
}

ExitCode run_atlas(const AtlasOptions& options, const GlobalOptions& global) {
  if (options.repack) {
    // A repack keeps the input's faces, charts and layouts: nothing to clean, weld or join.
    if (is_gltf_path(options.input) != is_gltf_path(options.output))
      throw CliFailure(ExitCode::usage, "--repack writes the format it reads: an OBJ into an OBJ, a glTF document "
                                        "(its TEXCOORD_0) into a glTF document");
    if (options.cleanup != "none" || options.keep_splits || options.join_charts)
      throw CliFailure(ExitCode::usage, "--repack keeps the input's charts as they are: --cleanup, --keep-splits "
                                        "and --join-charts do not apply");
  }
  if (!options.view.empty()) {
    if (is_gltf_path(options.output))
      throw CliFailure(ExitCode::usage, "--view writes a page of an OBJ output; for " + options.output +
                                            ", run `harmonia view` on an OBJ atlas");
    require_extension(options.view, {".html"}, "view");
    check_output(options.input, options.view, false, "--view");
  }
  if (is_gltf_path(options.output)) return run_gltf_atlas(options, global);
  if (options.group != "mesh" || options.texcoord >= 0 || options.overwrite) {
    throw CliFailure(ExitCode::usage, "--group, --texcoord and --overwrite choose what a glTF "
                                      "output (.glb, .gltf) gets; " + options.output + " is an OBJ");
  }
  ProgressLine progress(global, options.json);
  std::vector<PhaseTiming> timings;
  const Mesh input = read_input_for_output(options.input, options.output, options.in_place,
                                           options.picture, progress, timings);
  auto start = Clock::now();
  const PreparedSurface prepared = prepare_surface(input, options);
  timings.push_back({"cleanup", seconds_since(start)});
  progress.clear();
  for (const std::string& change : prepared.changes) note(global, "cleanup: " + change);

  const TextureAtlasOptions atlas_options = library_options(options, progress);
  const TextureAtlas atlas = options.repack ? repacked_atlas(options, input, atlas_options)
                                            : make_atlas(prepared.surface, atlas_options);
  progress.clear();
  timings.insert(timings.end(), atlas.report.timings.begin(), atlas.report.timings.end());
  if (!atlas.report.ok()) {
    if (options.json)
      std::cout << report_json(options, atlas_options, atlas, timings).dump(2) << '\n';
    throw CliFailure(exit_code_for(atlas.report.status),
                     options.input + ": " + atlas.report.message);
  }
  if (!options.picture.empty()) refuse_picture_of_pages(atlas);

  start = Clock::now();
  progress.show("writing " + options.output);
  if (const std::optional<ObjAsset> asset = kept_obj_asset(options.input); asset) {
    if (asset->texcoord_faces.size() > 0 && asset->texcoord_faces.maxCoeff() >= 0) {
      note(global, options.output + ": the atlas replaces " + options.input +
                       "'s own texture coordinates (an OBJ holds one set; a glTF output keeps both)");
    }
    write_output([&] {
      write_atlas_obj(options.output, prepared.written, atlas, *asset, prepared.original_face);
    });
  } else {
    write_output([&] { write_atlas_obj(options.output, prepared.written, atlas); });
  }
  timings.push_back({"write", seconds_since(start)});
  if (!options.picture.empty()) {
    start = Clock::now();
    progress.show("drawing " + options.picture);
    AtlasPictureOptions picture;
    picture.title = std::filesystem::path(options.input).filename().string() + " - " +
                    std::to_string(atlas.resolution) + " x " + std::to_string(atlas.height_texels()) +
                    " texels - " + std::to_string(atlas.metrics.charts) + " charts";
    write_output([&] { write_atlas_picture(options.picture, prepared.surface, atlas, picture); });
    timings.push_back({"picture", seconds_since(start)});
  }
  if (!options.view.empty()) {
    start = Clock::now();
    progress.show("writing " + options.view);
    const detail::AtlasUvLayout layout = detail::atlas_uv_layout(prepared.written, atlas);
    const auto fixed_text = [](double value, int digits) {
      char text[32];
      std::snprintf(text, sizeof text, "%.*f", digits, value);
      return std::string(text);
    };
    ViewPageOptions page;
    page.title = std::filesystem::path(options.input).filename().string();
    page.headline = {{"charts", std::to_string(atlas.metrics.charts)},
                     {"coverage", fixed_text(atlas.metrics.coverage, 3)},
                     {"L2 stretch", fixed_text(atlas.metrics.l2_stretch, 4)},
                     {"texels", std::to_string(atlas.resolution) + " x " + std::to_string(atlas.height_texels())}};
    write_output([&] {
      ViewLayout shown{std::filesystem::path(options.output).filename().string(), "texture atlas",
                       prepared.written, layout.uv, layout.uv_faces, atlas.chart_of_face};
      // A face outside every chart (none in a valid atlas) leaves the page to find the charts.
      if (std::any_of(shown.chart_of_face.begin(), shown.chart_of_face.end(), [](int c) { return c < 0; }))
        shown.chart_of_face.clear();
      write_view_page(options.view, {shown}, page);
    });
    timings.push_back({"view", seconds_since(start)});
  }
  progress.clear();

  if (options.json) {
    nlohmann::json output = report_json(options, atlas_options, atlas, timings);
    output["vertices"] = input.vertex_count();
    output["cleanup_changes"] = prepared.changes;
    if (!options.picture.empty()) output["picture"] = options.picture;
    if (!options.view.empty()) output["view"] = options.view;
    std::cout << output.dump(2) << '\n';
  } else {
    print_table(options, atlas, timings);
  }
  if (const std::string kept = kept_layout_faults(atlas.metrics); options.repack && !kept.empty())
    note(global, options.output + ": kept as " + options.input + "'s layout has them: " + kept);
  if (const std::string defects = atlas_defects(atlas.metrics, options.repack); !defects.empty()) {
    throw CliFailure(ExitCode::invalid_result,
                     "the atlas has " + defects + "; " + options.output + " was written anyway");
  }
  return ExitCode::ok;
}

}  // namespace harmonia::cli
