#include "cli/compare.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <vector>

#include "cli/layout_file.h"
#include "cli/report_output.h"
#include "harmonia/distortion_plot.h"
#include "harmonia/io.h"
#include "harmonia/metrics.h"

namespace harmonia::cli {

CLI::App* add_compare_command(CLI::App& app, CompareOptions& options) {
  CLI::App* command = app.add_subcommand(
      "compare",
      "Compare layouts of one mesh: flips, distortion, per-triangle angle and area "
      "distortion (table, JSON, sorted-curve picture)");
  command->add_option("MESH3D", options.mesh3d, "The 3D mesh")->required();
  command
      ->add_option("PARAM", options.layouts,
                   "Layouts of MESH3D, as `eval` reads them (an OBJ with vt, or a mesh with the "
                   "same faces whose x,y are the UVs)")
      ->required();
  command
      ->add_option("--labels", options.labels,
                   "Names of the layouts, comma-separated, one per PARAM (default: file names)")
      ->delimiter(',');
  command->add_option("--picture", options.picture,
                      "Also plot each layout's sorted per-triangle angle and area distortion "
                      "(.svg or .png)");
  command->add_flag("--json", options.json, "Print one JSON object");
  return command;
}

namespace {

// The figures of one layout.
struct LayoutFigures {
  std::string label;
  std::string path;
  long long uv_vertices = 0;
  DistortionMetrics metrics;
  Eigen::VectorXd angle_distortion;
  double angle_median = NAN;
  double angle_p90 = NAN;
  double angle_max = NAN;
};

// The value at fraction p of the sorted values, interpolated linearly between neighbours
// (position p (n - 1)); NaN when there are none.
double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return NAN;
  const double position = p * static_cast<double>(sorted.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double weight = position - static_cast<double>(below);
  return weight == 0.0 ? sorted[below] : sorted[below] + weight * (sorted[above] - sorted[below]);
}

// The labels: as given (one per layout, none empty), else the file names, else (when two file
// names coincide) the paths as given.
std::vector<std::string> layout_labels(const CompareOptions& options) {
  if (!options.labels.empty()) {
    if (options.labels.size() != options.layouts.size()) {
      throw CliFailure(ExitCode::usage,
                       "--labels names " + std::to_string(options.labels.size()) + " layouts but " +
                           std::to_string(options.layouts.size()) + " PARAM files are given");
    }
    for (std::size_t i = 0; i < options.labels.size(); ++i) {
      if (options.labels[i].empty())
        throw CliFailure(ExitCode::usage, "--labels: label " + std::to_string(i + 1) + " is empty");
    }
    return options.labels;
  }
  std::vector<std::string> names;
  for (const std::string& path : options.layouts)
    names.push_back(std::filesystem::path(path).filename().string());
  if (std::set<std::string>(names.begin(), names.end()).size() != names.size())
    return options.layouts;
  return names;
}

LayoutFigures measure(const Mesh& mesh3d, const CompareOptions& options, const std::string& path,
                      std::string label) {
  const Layout layout = load_layout(path);
  require_layout_of(mesh3d, options.mesh3d, layout, path);
  LayoutFigures figures;
  figures.label = std::move(label);
  figures.path = path;
  figures.uv_vertices = layout.uv.rows();
  figures.metrics = evaluate_map(mesh3d, layout.uv, layout.uv_faces);
  figures.angle_distortion = face_angle_distortion(mesh3d, layout.uv, layout.uv_faces);
  std::vector<double> sorted;
  for (const double value : figures.angle_distortion) {
    if (!std::isnan(value)) sorted.push_back(value);
  }
  std::sort(sorted.begin(), sorted.end());
  figures.angle_median = percentile(sorted, 0.5);
  figures.angle_p90 = percentile(sorted, 0.9);
  if (!sorted.empty()) figures.angle_max = sorted.back();
  return figures;
}

nlohmann::json comparison_json(const CompareOptions& options, const Mesh& mesh3d,
                               const std::vector<LayoutFigures>& all_figures) {
  nlohmann::json layouts = nlohmann::json::array();
  for (const LayoutFigures& figures : all_figures) {
    nlohmann::json layout = metrics_json(figures.metrics);
    layout["label"] = figures.label;
    layout["parameterization"] = figures.path;
    layout["uv_vertices"] = figures.uv_vertices;
    layout["angle_distortion_median"] = figures.angle_median;
    layout["angle_distortion_p90"] = figures.angle_p90;
    layout["angle_distortion_max"] = figures.angle_max;
    layouts.push_back(std::move(layout));
  }
  return {{"mesh", options.mesh3d},
          {"faces", mesh3d.face_count()},
          {"layouts", std::move(layouts)},
          {"picture",
           options.picture.empty() ? nlohmann::json(nullptr) : nlohmann::json(options.picture)}};
}

// One row per layout, the label left-aligned and the numbers right-aligned under their headers.
void print_table(const std::vector<LayoutFigures>& all_figures) {
  const std::vector<std::string> headers = {
      "layout",        "flips",     "zero-area", "crossings",    "abf energy", "conformal mean",
      "conformal max", "area mean", "area max",  "angle median", "angle p90",  "angle max"};
  std::vector<std::vector<std::string>> rows;
  for (const LayoutFigures& figures : all_figures) {
    const DistortionMetrics& metrics = figures.metrics;
    rows.push_back({figures.label, std::to_string(metrics.flipped_triangles),
                    std::to_string(metrics.zero_area_triangles),
                    std::to_string(metrics.boundary_self_intersections),
                    format_number(metrics.abf_energy),
                    format_number(metrics.conformal_distortion_mean),
                    format_number(metrics.conformal_distortion_max),
                    format_number(metrics.area_distortion_mean),
                    format_number(metrics.area_distortion_max), format_number(figures.angle_median),
                    format_number(figures.angle_p90), format_number(figures.angle_max)});
  }
  std::vector<std::size_t> widths;
  for (const std::string& header : headers) widths.push_back(header.size());
  for (const auto& row : rows) {
    for (std::size_t column = 0; column < row.size(); ++column)
      widths[column] = std::max(widths[column], row[column].size());
  }
  const auto print_row = [&](const std::vector<std::string>& cells) {
    std::string line;
    for (std::size_t column = 0; column < cells.size(); ++column) {
      const std::string padding(widths[column] - cells[column].size(), ' ');
      if (column == 0) {
        line += cells[column] + padding;
      } else {
        line += "  " + padding + cells[column];
      }
    }
    std::cout << line << '\n';
  };
  print_row(headers);
  for (const auto& row : rows) print_row(row);
}

}  // namespace

ExitCode run_compare(const CompareOptions& options, const GlobalOptions& /*global*/) {
  // Refuse a bad command line before any work.
  const std::vector<std::string> labels = layout_labels(options);
  if (!options.picture.empty()) {
    require_extension(options.picture, {".svg", ".png"}, "picture");
    if (static_cast<int>(options.layouts.size()) > kMostPlottedLayouts) {
      throw CliFailure(ExitCode::usage, "--picture tells at most " +
                                            std::to_string(kMostPlottedLayouts) +
                                            " layouts apart (one colour each), not " +
                                            std::to_string(options.layouts.size()));
    }
    check_output(options.mesh3d, options.picture, false, "--picture");
  }

  const Mesh mesh3d = load_mesh(options.mesh3d);
  std::vector<LayoutFigures> all_figures;
  for (std::size_t i = 0; i < options.layouts.size(); ++i)
    all_figures.push_back(measure(mesh3d, options, options.layouts[i], labels[i]));

  if (options.json) {
    std::cout << comparison_json(options, mesh3d, all_figures).dump(2) << '\n';
  } else {
    print_table(all_figures);
  }

  if (!options.picture.empty()) {
    std::vector<LayoutDistortion> curves;
    for (const LayoutFigures& figures : all_figures) {
      curves.push_back(
          {figures.label, figures.angle_distortion, figures.metrics.face_area_log_ratio});
    }
    DistortionPlotOptions plot;
    plot.title = std::filesystem::path(options.mesh3d).filename().string() +
                 " - sorted per-triangle distortion of " + std::to_string(curves.size()) +
                 (curves.size() == 1 ? " layout" : " layouts");
    write_output([&] { write_distortion_plot(options.picture, curves, plot); });
  }

  std::string flipped;
  for (const LayoutFigures& figures : all_figures) {
    if (figures.metrics.flipped_triangles == 0) continue;
    flipped += (flipped.empty() ? "" : ", ") + figures.path + " has " +
               std::to_string(figures.metrics.flipped_triangles) + " flipped triangles";
  }
  if (!flipped.empty()) throw CliFailure(ExitCode::invalid_result, flipped);
  return ExitCode::ok;
}

}  // namespace harmonia::cli
