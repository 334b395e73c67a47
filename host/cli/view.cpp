#include "cli/view.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string_view>
#include <system_error>

#include "cli/layout_file.h"
#include "harmonia/obj_asset.h"
#include "harmonia/view_page.h"

namespace harmonia::cli {

namespace {

// The chart of each face from an OBJ's `g chart_N` (or `chart_N_aP`) groups, as `harmonia atlas`
// and xatlas write them and atlaseval.py reads them; empty unless every face has one.
std::vector<int> charts_from_groups(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  if (extension != ".obj") return {};
  const ObjAsset asset = read_obj_asset(path);
  std::vector<int> chart_of_label(asset.labels.size(), -1);
  for (std::size_t k = 0; k < asset.labels.size(); ++k) {
    const std::string& label = asset.labels[k];
    if (!label.starts_with("chart_")) continue;
    int id = -1;
    const char* first = label.data() + 6;
    const char* last = label.data() + label.size();
    const auto [end, error] = std::from_chars(first, last, id);
    if (error == std::errc() && end != first && (end == last || std::string_view(end, last).starts_with("_a")) && id >= 0)
      chart_of_label[k] = id;
  }
  std::vector<int> chart(asset.groups_of_face.size(), -1);
  for (std::size_t f = 0; f < chart.size(); ++f) {
    const int group = asset.groups_of_face[f];
    if (group < 0 || chart_of_label[static_cast<std::size_t>(group)] < 0) return {};
    chart[f] = chart_of_label[static_cast<std::size_t>(group)];
  }
  return chart;
}

}  // namespace

CLI::App* add_view_command(CLI::App& app, ViewOptions& options) {
  CLI::App* command = app.add_subcommand(
      "view", "Write a page to look at layouts in a browser: the 3D model wearing a checker or "
              "coloured by distortion, linked to its UV square (one HTML file, no network)");
  command
      ->add_option("RESULT", options.results,
                   "Layouts: OBJ files with vt and texture indices (as `harmonia unwrap` and "
                   "`harmonia atlas` write; the charts are the file's `g chart_N` groups where "
                   "every face has one, else the faces connected through shared UVs); several are "
                   "shown side by side on one camera")
      ->required();
  command->add_option("--mesh", options.mesh3d,
                      "The 3D mesh of every RESULT (default: each RESULT's own vertices)");
  command->add_option("-o,--out", options.out, "The page to write (.html)")->required();
  command->add_option("--title", options.title, "The page's headline (default: the first RESULT's name)");
  return command;
}

ExitCode run_view(const ViewOptions& options, const GlobalOptions& /*global*/) {
  std::vector<ViewLayout> layouts;
  std::optional<Mesh> shared_mesh;
  if (!options.mesh3d.empty()) shared_mesh = load_mesh(options.mesh3d);
  for (const std::string& result : options.results) {
    ViewLayout layout;
    layout.name = std::filesystem::path(result).filename().string();
    layout.method = "layout of " + layout.name;
    layout.mesh3d = shared_mesh ? *shared_mesh : load_mesh(result);
    const Layout uv = load_layout(result);
    require_layout_of(layout.mesh3d, shared_mesh ? options.mesh3d : result, uv, result);
    layout.uv = uv.uv;
    layout.uv_faces = uv.uv_faces;
    layout.chart_of_face = charts_from_groups(result);
    if (layout.chart_of_face.size() != static_cast<std::size_t>(layout.uv_faces.rows())) layout.chart_of_face.clear();
    layouts.push_back(std::move(layout));
  }
  ViewPageOptions page;
  page.title = options.title.empty() ? layouts.front().name : options.title;
  write_view_page(options.out, layouts, page);
  std::cout << "wrote " << options.out << '\n';
  return ExitCode::ok;
}

}  // namespace harmonia::cli
