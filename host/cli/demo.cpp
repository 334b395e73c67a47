#include "cli/demo.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <system_error>
#include <vector>

#include "cli/methods.h"
#include "cli/progress_line.h"
#include "cli/report_output.h"
#include "harmonia/io.h"
#include "harmonia/metrics.h"
#include "harmonia/picture.h"
#include "harmonia/procedural.h"

namespace harmonia::cli {

CLI::App* add_demo_command(CLI::App& app, DemoOptions& options) {
  CLI::App* command = app.add_subcommand(
      "demo", "Flatten a built-in wavy surface with four methods; write OBJ, SVG and PNG files");
  command->add_option("OUTDIR", options.output_directory,
                      "Folder for the results (created if missing; default ./harmonia-demo)");
  return command;
}

namespace {

struct DemoMethod {
  std::string name;   // Used in the file names and the table.
  std::string title;  // How the pictures' titles name it.
  MethodChoice choice;
};

std::vector<DemoMethod> demo_methods() {
  MethodChoice conformal;  // Cotangent weights, circle boundary: the discrete conformal map.
  MethodChoice mean_value;
  mean_value.weights = WeightScheme::mean_value;
  MethodChoice lscm;
  lscm.method = MethodKind::lscm;
  MethodChoice qhm;
  qhm.method = MethodKind::qhm;
  MethodChoice free;
  free.method = MethodKind::free;
  return {{"conformal", "conformal (cotangent)", conformal},
          {"mean-value", "conformal (mean-value)", mean_value},
          {"lscm", "lscm", lscm},
          {"qhm", "qhm (cotangent)", qhm},
          {"free", "free (cotangent)", free}};
}

struct DemoRow {
  std::string method;
  std::string status;
  int flips = 0;
  double conformal_mean = 0.0;
  double area_distortion = 0.0;
  double seconds = 0.0;
};

void print_table(const std::vector<DemoRow>& rows) {
  std::printf("%-12s %-18s %6s %15s %16s %9s\n", "method", "status", "flips", "conformal mean",
              "area distortion", "seconds");
  for (const DemoRow& row : rows) {
    std::printf("%-12s %-18s %6d %15s %16s %9.3f\n", row.method.c_str(), row.status.c_str(),
                row.flips, format_number(row.conformal_mean).c_str(),
                format_number(row.area_distortion).c_str(), row.seconds);
  }
  std::fflush(stdout);
}

}  // namespace

ExitCode run_demo(const DemoOptions& options, const GlobalOptions& global) {
  const std::filesystem::path folder = options.output_directory;
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error || !std::filesystem::is_directory(folder)) {
    throw CliFailure(ExitCode::environment,
                     "cannot create the folder " + folder.string() + ": " + error.message());
  }

  const Mesh surface = demo_surface();
  write_output([&] { write_mesh(folder / "demo-surface.obj", surface); });
  note(global, "demo surface: " + std::to_string(surface.vertex_count()) + " vertices, " +
                   std::to_string(surface.face_count()) + " faces -> " +
                   (folder / "demo-surface.obj").string());

  ProgressLine progress(global, false);
  std::vector<DemoRow> rows;
  ExitCode worst = ExitCode::ok;
  for (const DemoMethod& method : demo_methods()) {
    progress.show(method.name);
    const auto start = std::chrono::steady_clock::now();
    const MapResult result = run_method(surface, method.choice, progress.callback());
    DemoRow row;
    row.method = method.name;
    row.status = std::string(to_string(result.report.status));
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const bool have_map =
        result.report.status == Status::ok || result.report.status == Status::flipped_triangles;
    if (have_map) {
      const DistortionMetrics metrics = evaluate_map(surface, result.uv, surface.faces);
      row.flips = metrics.flipped_triangles;
      row.conformal_mean = metrics.conformal_distortion_mean;
      row.area_distortion = metrics.area_distortion_mean;
      const std::string stem = (folder / ("demo-" + method.name)).string();
      progress.show("writing " + stem + ".obj/.svg/.png");
      PictureOptions picture;
      picture.title = "demo-surface.obj - " + method.title + " - " + picture_headline(metrics);
      write_output([&] {
        write_obj(stem + ".obj", surface, result.uv);
        write_picture(stem + ".svg", surface, result.uv, surface.faces, picture);
        write_picture(stem + ".png", surface, result.uv, surface.faces, picture);
      });
      if (metrics.flipped_triangles > 0 && worst == ExitCode::ok) worst = ExitCode::invalid_result;
    } else {
      progress.clear();
      note(global, method.name + " failed: " + result.report.message);
      const ExitCode code = exit_code_for(result.report.status);
      if (static_cast<int>(code) > static_cast<int>(worst)) worst = code;
    }
    rows.push_back(row);
  }
  progress.clear();
  print_table(rows);
  if (worst != ExitCode::ok) {
    throw CliFailure(worst, "not every method produced a valid map; see the table above");
  }
  return ExitCode::ok;
}

}  // namespace harmonia::cli
