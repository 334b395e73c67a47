// The atlas command's report: the table, the JSON object and the defects that fail a run.

#include "cli/atlas_report.h"

#include "cli/report_output.h"

#include <iostream>
#include <cstdio>
#include <map>

namespace harmonia::cli {

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

namespace {

nlohmann::json chart_json(const AtlasChart& chart) {
  const Eigen::AlignedBox2d& box = chart.texel_box;
  return {
      {"faces", chart.faces.size()},
      {"method", std::string(to_string(chart.method))},
      {"piece_of_a_cut", chart.piece_of_a_cut},
      {"page", chart.page},
      {"l2_stretch", chart.l2_stretch},
      {"angle_distortion", chart.angle_distortion},
      {"area_distortion", chart.area_distortion},
      {"surface_area", chart.surface_area},
      {"texel_box",
       {{"min", {box.min().x(), box.min().y()}}, {"max", {box.max().x(), box.max().y()}}}},
  };
}

}  // namespace

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
      {"height", atlas_options.height > 0 ? atlas_options.height : atlas_options.resolution},
      {"padding", atlas_options.padding},
      {"max_distortion", atlas_options.max_distortion},
      {"max_normal_deviation", atlas_options.max_normal_deviation_degrees},
      {"keep_splits", atlas_options.keep_splits},
      {"join_charts", atlas_options.join_charts},
      {"repack", options.repack},
      {"welded_vertices", atlas.welded_vertices},
      {"backend", std::string(to_string(report.backend))},
      {"solver", report.solver},
      {"backend_notice", report.backend_notice},
      {"faces", metrics.faces},
      {"charts", metrics.charts},
      {"coverage", metrics.coverage},
      {"pages", atlas.pages},
      {"page_coverage", metrics.page_coverage},
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

namespace {

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

}  // namespace

void print_table(const AtlasOptions& options, const TextureAtlas& atlas,
                 const std::vector<PhaseTiming>& timings) {
  const AtlasMetrics& metrics = atlas.metrics;
  FieldTable table;
  table.add("output", options.output);
  if (!options.picture.empty()) table.add("picture", options.picture);
  table.add("resolution", std::to_string(atlas.resolution) + " x " + std::to_string(atlas.height_texels()) +
                              " texels" + (atlas.pages > 1 ? " a page" : ""));
  if (atlas.pages > 1) {
    std::string per_page;
    for (const double coverage : metrics.page_coverage) {
      char figure[16];
      std::snprintf(figure, sizeof figure, "%.3f", coverage);
      per_page += (per_page.empty() ? "" : " ") + std::string(figure);
    }
    table.add("pages", std::to_string(atlas.pages) + " (coverage " + per_page + ")");
  }
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

void refuse_picture_of_pages(const TextureAtlas& atlas) {
  if (atlas.pages <= 1) return;
  throw CliFailure(ExitCode::usage, "--picture draws one square of the atlas; this one has " +
                                        std::to_string(atlas.pages) +
                                        " pages (--max-pages 1, a larger --resolution or a smaller "
                                        "--texels-per-unit makes one); nothing was written");
}

// What makes a written atlas unusable as a texture layout, in words; empty when nothing does.
namespace {

// "3 flipped triangles, 1 mirrored charts" from the counts that are not 0.
std::string counted(const std::vector<std::pair<int, std::string>>& counts) {
  std::string words;
  for (const auto& [count, what] : counts)
    if (count > 0) words += (words.empty() ? "" : ", ") + std::to_string(count) + " " + what;
  return words;
}

}  // namespace

std::string atlas_defects(const AtlasMetrics& metrics, bool repack) {
  if (repack) return counted({{metrics.overlapping_texels, "overlapping texels"}, {metrics.dropped_faces, "dropped faces"}});
  return counted({{metrics.flipped_triangles, "flipped triangles"},
                  {metrics.mirrored_charts, "mirrored charts"},
                  {metrics.overlapping_texels, "overlapping texels"},
                  {metrics.boundary_crossings, "crossing chart boundaries"},
                  {metrics.dropped_faces, "dropped faces"}});
}

std::string kept_layout_faults(const AtlasMetrics& metrics) {
  return counted({{metrics.flipped_triangles, "flipped triangles"},
                  {metrics.mirrored_charts, "mirrored charts"},
                  {metrics.boundary_crossings, "crossing chart boundaries"}});
}


}  // namespace harmonia::cli
