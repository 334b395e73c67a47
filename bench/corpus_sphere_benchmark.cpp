// corpus_sphere_benchmark: the spherical map (harmonia::spherical_map, thesis chapter 7) on every
// closed mesh of the corpus (plus homer and cow at 4x and 16x their size), with default options
// (cotangent weights) and with mean-value weights, next to the floor of the same mesh cut open
// (harmonia::cut_to_disk, automatic ends, as `harmonia cut` does), measured in the same run.
//
// Per mesh: the floor row (the CHOLMOD floor of the cut-open disk, bench/bench_support.h), then
// the `sphere` and `sphere-mean-value` rows: the library's time (the sum of report.timings) and its
// split into phase groups, x_floor, peak resident size, and the quality of the map on the sphere
// (harmonia::spherical_metrics: flips, degenerate triangles, degree, angle / conformal / area
// distortion) with the area distortion of the first map and of the final one (result.rounds).
// The markdown ends with how the time splits, how it grows with size, the fall-backs taken and the
// issue's targets (valid everywhere, <= 4x the floor at 100K-200K faces, <= 1 GB at ~200K faces).
//
// Every measurement (the cut, the floor, each map) runs in its own forked process
// (corpus_child.h), so its peak resident size (VmHWM) is its own and a crash ends only that row.
// Output: a markdown report (stdout and --out-md) and a JSON file (--out-json).

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_support.h"
#include "bench/corpus_child.h"
#include "bench/corpus_methods.h"
#include "bench/corpus_report.h"
#include "harmonia/blas_threads.h"
#include "harmonia/cut.h"
#include "harmonia/io.h"
#include "harmonia/spherical_map.h"
#include "harmonia/spherical_metrics.h"

namespace {

namespace fs = std::filesystem;
namespace bench = harmonia::bench;
using bench::Json;

// ---------------------------------------------------------------------------------------------
// Options and the meshes to run

struct Options {
  std::vector<int> sizes{1, 4, 16};                     // Size factors of the scaling meshes.
  std::vector<std::string> meshes;                      // Corpus names to run (empty: all).
  std::vector<std::string> scaling_meshes{"homer", "cow"};
  bool scale_all = false;     // Every closed mesh at every size, not only the scaling meshes.
  int repeat = 1;             // Timed repetitions per map; the fastest counts.
  int timeout_seconds = 900;  // Per child process.
  harmonia::BlasThreadPolicy blas_threads =
      harmonia::BlasThreadPolicy::hold_during_split_factorizations;
  fs::path out_md = "sphere-bench-results.md";
  fs::path out_json = "sphere-bench-results.json";
};

struct MeshCase {
  std::string name;  // e.g. "homer-x16".
  std::string base;  // The corpus mesh it was made from, e.g. "homer".
  fs::path path;
  int factor = 1;
};

//! One spherical-map row kind: the weights of steps 2 and 3 (everything else default).
struct SphereVariant {
  std::string key;  // Column "row": "sphere" (default options) or "sphere-mean-value".
  harmonia::WeightScheme weights;
};

const std::vector<SphereVariant>& sphere_variants() {
  static const std::vector<SphereVariant> variants{
      {"sphere", harmonia::SphericalMapOptions{}.weights},
      {"sphere-mean-value", harmonia::WeightScheme::mean_value},
  };
  return variants;
}

// The targets.
constexpr int kFloorTargetMinFaces = 100000;  // x_floor <= 4 on meshes of 100K-200K faces.
constexpr int kFloorTargetMaxFaces = 200000;
constexpr double kFloorTargetMultiple = 4.0;
constexpr int kMemoryTargetMinFaces = 150000;  // "~200K faces": within 25 % of 200K.
constexpr int kMemoryTargetMaxFaces = 250000;
constexpr double kMemoryTargetMegabytes = 1024.0;
//! |degree - 1| above this is not a bijection (the degree is a sum of signed areas over 4 pi, so
//! a bijective map gives 1 up to rounding, a fold at least one triangle's share away from it).
constexpr double kDegreeTolerance = 1e-6;

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

bool contains(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

bool wanted(const std::vector<std::string>& filter, const std::string& name) {
  return filter.empty() || contains(filter, name);
}

//! Appends `item` to the list `text`, after `separator` unless it is the first.
void append_item(std::string& text, const std::string& item, const char* separator = ", ") {
  if (!text.empty()) text += separator;
  text += item;
}

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      return line.substr(line.find(':') + 2);
    }
  }
  return "unknown CPU";
}

std::string load_average() {
  std::ifstream loadavg("/proc/loadavg");
  std::string one, five, fifteen;
  loadavg >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}

void print_usage() {
  std::cout
      << "usage: corpus_sphere_benchmark [--sizes 1,4,16] [--meshes a,b] [--scaling-meshes a,b]\n"
         "                               [--scale-all] [--repeat N] [--timeout S]\n"
         "                               [--out-md FILE] [--out-json FILE]\n"
         "                               [--blas-threads hold|leave]\n"
         "Every closed corpus mesh (../shared/data/closed) once; the scaling meshes (default\n"
         "homer,cow) at every size of --sizes (powers of 4, midpoint subdivision), or every mesh\n"
         "with --scale-all. Rows per mesh: floor (CHOLMOD floor of the mesh cut open), sphere\n"
         "(spherical_map, default options, CPU) and sphere-mean-value (mean-value weights).\n";
}

bool parse_options(int argc, char** argv, Options* options) {
  for (int index = 1; index < argc; ++index) {
    const std::string flag = argv[index];
    if (flag == "--help" || flag == "-h") {
      print_usage();
      std::exit(0);
    } else if (flag == "--scale-all") {
      options->scale_all = true;
    } else if (index + 1 >= argc) {
      std::cerr << "corpus_sphere_benchmark: " << flag << " needs a value (or is unknown)\n";
      return false;
    } else {
      const std::string value = argv[++index];
      if (flag == "--sizes") {
        options->sizes.clear();
        for (const std::string& size : split_list(value)) options->sizes.push_back(std::stoi(size));
      } else if (flag == "--meshes") {
        options->meshes = split_list(value);
      } else if (flag == "--scaling-meshes") {
        options->scaling_meshes = split_list(value);
      } else if (flag == "--repeat") {
        options->repeat = std::max(1, std::stoi(value));
      } else if (flag == "--timeout") {
        options->timeout_seconds = std::max(1, std::stoi(value));
      } else if (flag == "--out-md") {
        options->out_md = value;
      } else if (flag == "--out-json") {
        options->out_json = value;
      } else if (flag == "--blas-threads" && (value == "hold" || value == "leave")) {
        options->blas_threads = value == "hold"
                                    ? harmonia::BlasThreadPolicy::hold_during_split_factorizations
                                    : harmonia::BlasThreadPolicy::leave_alone;
      } else {
        std::cerr << "corpus_sphere_benchmark: unknown option " << flag << "\n";
        return false;
      }
    }
  }
  for (const int size : options->sizes) {
    if (bench::subdivision_steps(size) < 0) {
      std::cerr << "corpus_sphere_benchmark: size " << size << " is not a power of 4\n";
      return false;
    }
  }
  return true;
}

std::vector<MeshCase> mesh_cases(const std::vector<fs::path>& corpus, const Options& options) {
  std::vector<MeshCase> cases;
  for (const fs::path& path : corpus) {
    const std::string name = path.stem().string();
    if (!wanted(options.meshes, name)) continue;
    if (!contains(options.scaling_meshes, name) && !options.scale_all) {
      cases.push_back({name, name, path, 1});
      continue;
    }
    for (const int factor : options.sizes) {
      std::string message;
      const auto scaled = bench::scaled_mesh(path, factor, &message);
      if (!scaled) {
        std::cerr << "corpus_sphere_benchmark: " << message << "\n";
        continue;
      }
      cases.push_back(
          {factor == 1 ? name : name + "-x" + std::to_string(factor), name, *scaled, factor});
    }
  }
  return cases;
}

// ---------------------------------------------------------------------------------------------
// Child bodies

//! Child body: cuts the closed mesh open (cut_to_disk, automatic ends: the double-sweep diameter)
//! and writes the disk to `disk_path` for the floor.
Json write_cut_disk_child(const fs::path& closed_path, const fs::path& disk_path) {
  const harmonia::Mesh mesh = harmonia::read_mesh(closed_path);
  bench::Stopwatch cutting;
  const harmonia::CutResult cut = harmonia::cut_to_disk(mesh);
  const double cut_seconds = cutting.seconds();
  if (cut.status != harmonia::Status::ok) {
    return Json{{"status", std::string(harmonia::to_string(cut.status))},
                {"message", "cut_to_disk: " + cut.message}};
  }
  harmonia::write_mesh(disk_path, cut.disk);
  return Json{{"status", "ok"},
              {"cut_seconds", cut_seconds},
              {"seam_edges", cut.seam_edges},
              {"disk_vertices", cut.disk.vertex_count()}};
}

//! The phase groups of a spherical map's report.timings, in the order of the pipeline.
const std::vector<std::string>& phase_groups() {
  static const std::vector<std::string> groups{"paths",      "harmonic_map", "quasi_harmonic",
                                               "relaxation", "metrics",      "other"};
  return groups;
}

//! Group of one phase name (spherical_map.cpp's PhaseClock names):
//!   paths          = validation (check_sphere), poles (geodesic diameter) and analysis (the
//!                    date line, the curvilinear domain cut along it, the system's pattern);
//!   harmonic_map   = the first map (7.1): factorization, solve, lift and untangling;
//!   quasi_harmonic = every quasi-harmonic round (7.2), shortened attempts included;
//!   relaxation     = the band relaxation around the date line (7.3);
//!   metrics        = the validity check on the sphere (spherical_metrics);
//!   other          = any phase this program does not know (so none is lost).
std::string phase_group(const std::string& phase) {
  if (phase == "validation" || phase == "poles" || phase == "analysis") return "paths";
  if (phase == "harmonic map") return "harmonic_map";
  if (phase == "quasi-harmonic round") return "quasi_harmonic";
  if (phase == "relaxation") return "relaxation";
  if (phase == "metrics") return "metrics";
  return "other";
}

double library_seconds(const harmonia::SolveReport& report) {
  double total = 0.0;
  for (const harmonia::PhaseTiming& timing : report.timings) total += timing.seconds;
  return total;
}

//! Child body for one spherical map: read the mesh, time `repeat` calls of spherical_map on the
//! CPU backend (the fastest by the library's own time counts), read the peak resident size of the
//! calls, then measure the fastest call's map with spherical_metrics (outside the peak).
Json measure_sphere_child(const fs::path& mesh_path, const SphereVariant& variant, int repeat) {
  bench::Stopwatch reading;
  const harmonia::Mesh mesh = harmonia::read_mesh(mesh_path);
  const double read_seconds = reading.seconds();
  harmonia::SphericalMapOptions options;
  options.weights = variant.weights;
  options.solver.backend = harmonia::BackendChoice::cpu;

  const double resident_before = bench::process_status_megabytes("VmRSS");
  const bool peak_reset = bench::reset_peak_resident_size();
  harmonia::SphericalMapResult best;
  double best_seconds = std::numeric_limits<double>::infinity();
  double best_wall_seconds = 0.0;
  for (int run = 0; run < repeat; ++run) {
    bench::Stopwatch stopwatch;
    harmonia::SphericalMapResult result = harmonia::spherical_map(mesh, options);
    const double wall_seconds = stopwatch.seconds();
    const double seconds = library_seconds(result.report);
    if (seconds < best_seconds) {
      best_seconds = seconds;
      best_wall_seconds = wall_seconds;
      best = std::move(result);
    }
  }
  const double peak = bench::process_status_megabytes("VmHWM");

  const harmonia::SolveReport& report = best.report;
  Json phase_seconds = Json::object();
  for (const std::string& group : phase_groups()) phase_seconds[group] = 0.0;
  int quasi_harmonic_phases = 0;  // Rounds started (one phase each, its refused attempts inside).
  for (const harmonia::PhaseTiming& timing : report.timings) {
    const std::string group = phase_group(timing.phase);
    phase_seconds[group] = phase_seconds[group].get<double>() + timing.seconds;
    if (group == "quasi_harmonic") ++quasi_harmonic_phases;
  }
  Json rounds = Json::array();
  for (const harmonia::SphericalRound& round : best.rounds) {
    rounds.push_back(Json{{"area_distortion", round.area_distortion}, {"seconds", round.seconds}});
  }
  Json row{{"status", std::string(harmonia::to_string(report.status))},
           {"message", report.message},
           {"faces", mesh.face_count()},
           {"vertices", mesh.vertex_count()},
           {"backend", std::string(harmonia::to_string(report.backend))},
           {"solver", report.solver},
           {"weights", std::string(harmonia::to_string(variant.weights))},
           {"seconds", best_seconds},
           {"wall_seconds", best_wall_seconds},
           {"read_seconds", read_seconds},
           {"peak_MB", peak},
           {"rss_before_MB", resident_before},
           {"peak_is_per_method", peak_reset},
           {"phase_groups", phase_seconds},
           {"phases", bench::phases_json(report)},
           {"quasi_harmonic_rounds", report.rounds},
           {"quasi_harmonic_phases", quasi_harmonic_phases},
           {"rounds", rounds},
           {"north_pole", best.north_pole},
           {"south_pole", best.south_pole},
           {"date_line_vertices", static_cast<int>(best.date_line.size())},
           {"relaxed_vertices", best.relaxed_vertices},
           {"fallbacks", report.fallbacks}};
  if (!best.rounds.empty()) {
    row["area_first"] = best.rounds.front().area_distortion;
    row["area_final"] = best.rounds.back().area_distortion;
  }
  if (best.positions.rows() == mesh.vertex_count() && best.positions.allFinite()) {
    const harmonia::SphericalMetrics metrics = harmonia::spherical_metrics(mesh, best.positions);
    row["flips"] = metrics.flipped_triangles;
    row["degenerate"] = metrics.degenerate_triangles;
    row["degree"] = metrics.degree;
    row["angle_error_mean_squared"] = metrics.angle_error_mean_squared;
    row["conformal_mean"] = metrics.conformal_distortion_mean;
    row["conformal_max"] = metrics.conformal_distortion_max;
    row["area_distortion_mean"] = metrics.area_distortion_mean;
    row["area_distortion_max"] = metrics.area_distortion_max;
    row["max_radius_deviation"] = metrics.max_radius_deviation;
  }
  return row;
}

// ---------------------------------------------------------------------------------------------
// Rows

//! The floor row of one mesh: cut open and written to `scratch` in one child, floor measured on
//! the written disk in another (so neither's memory is in the other's peak).
Json floor_row(const MeshCase& mesh_case, const fs::path& scratch, const Options& options) {
  Json row{{"mesh", mesh_case.name}, {"base", mesh_case.base}, {"factor", mesh_case.factor},
           {"key", "floor"},         {"weights", "cotangent"}};
  const fs::path disk_path = scratch / (mesh_case.name + "-cut.obj");
  const Json cut = bench::run_in_child(
      [&] { return write_cut_disk_child(mesh_case.path, disk_path); }, options.timeout_seconds);
  if (cut.value("status", std::string()) != "ok") {
    row.update(cut);
    return row;
  }
  row["cut_seconds"] = cut["cut_seconds"];
  row["seam_edges"] = cut["seam_edges"];
  row["disk_vertices"] = cut["disk_vertices"];
  row.update(bench::run_in_child(
      [&] { return bench::measure_floor_child(disk_path, options.repeat); },
      options.timeout_seconds));
  std::error_code error;
  fs::remove(disk_path, error);
  if (row.value("status", std::string()) == "ok") row["x_floor"] = 1.0;
  return row;
}

Json sphere_row(const MeshCase& mesh_case, const SphereVariant& variant, double floor_seconds,
                const Options& options) {
  Json row{{"mesh", mesh_case.name},
           {"base", mesh_case.base},
           {"factor", mesh_case.factor},
           {"key", variant.key}};
  row.update(bench::run_in_child(
      [&] { return measure_sphere_child(mesh_case.path, variant, options.repeat); },
      options.timeout_seconds));
  // Only rows that computed a map get a multiple of the floor.
  if (floor_seconds > 0.0 && row.contains("seconds") && row.contains("flips")) {
    row["x_floor"] = row["seconds"].get<double>() / floor_seconds;
  }
  return row;
}

// ---------------------------------------------------------------------------------------------
// Validity, growth and targets

//! A map row that is a bijection onto the sphere: status ok, no flipped or degenerate triangle,
//! degree 1.
bool valid_map(const Json& row) {
  return row.value("status", std::string()) == "ok" && row.value("flips", -1) == 0 &&
         row.value("degenerate", -1) == 0 && row.contains("degree") &&
         std::abs(row["degree"].get<double>() - 1.0) <= kDegreeTolerance;
}

//! How the time of each scaling mesh grows: per (base mesh, row kind, part) the figure at each
//! size and the growth exponent between consecutive sizes, log(t2 / t1) / log(faces2 / faces1)
//! (1 = linear in the face count).
Json growth(const Json& runs) {
  // (base, key) -> the rows of that kind in size order (the run order).
  std::map<std::pair<std::string, std::string>, std::vector<const Json*>> families;
  std::vector<std::pair<std::string, std::string>> order;
  for (const Json& row : runs) {
    if (!row.contains("seconds")) continue;
    const auto family =
        std::make_pair(row["base"].get<std::string>(), row["key"].get<std::string>());
    if (families.find(family) == families.end()) order.push_back(family);
    families[family].push_back(&row);
  }
  Json list = Json::array();
  for (const auto& family : order) {
    const std::vector<const Json*>& rows = families[family];
    if (rows.size() < 2) continue;
    std::vector<std::string> parts{"seconds", "peak_MB"};
    if (family.second != "floor") {
      for (const std::string& group : phase_groups()) parts.push_back(group);
    }
    for (const std::string& part : parts) {
      Json entry{{"base", family.first},
                 {"key", family.second},
                 {"part", part},
                 {"faces", Json::array()},
                 {"values", Json::array()},
                 {"exponents", Json::array()}};
      bool any = false;
      for (std::size_t k = 0; k < rows.size(); ++k) {
        const Json& row = *rows[k];
        const Json value = part == "seconds" || part == "peak_MB"
                               ? row.value(part, Json())
                               : row["phase_groups"].value(part, Json());
        any = any || (value.is_number() && value.get<double>() > 0.0);
        entry["faces"].push_back(row["faces"]);
        entry["values"].push_back(value);
        if (k == 0) continue;
        const Json& previous = entry["values"][k - 1];
        const double faces_ratio =
            row["faces"].get<double>() / (*rows[k - 1])["faces"].get<double>();
        if (value.is_number() && previous.is_number() && previous.get<double>() > 0.0 &&
            value.get<double>() > 0.0 && faces_ratio > 1.0) {
          entry["exponents"].push_back(std::log(value.get<double>() / previous.get<double>()) /
                                       std::log(faces_ratio));
        } else {
          entry["exponents"].push_back(Json());
        }
      }
      if (any) list.push_back(entry);
    }
  }
  return list;
}

//! `met` is null when the run has no row the target is about (e.g. no mesh of that size).
void add_target(Json& list, const std::string& name, const std::string& measured,
                const std::string& limit, const Json& met, const std::string& note = {}) {
  list.push_back(Json{
      {"target", name}, {"measured", measured}, {"limit", limit}, {"met", met}, {"note", note}});
}

//! The targets: the default spherical map valid on every mesh of the run (the mean-value
//! variant too, for comparison); <= 4x the floor on the meshes of 100K-200K faces; peak memory
//! <= 1 GB on the meshes of about 200K faces.
Json targets(const Json& runs) {
  Json list = Json::array();
  for (const SphereVariant& variant : sphere_variants()) {
    int maps = 0;
    std::string failing;
    for (const Json& row : runs) {
      if (row["key"] != variant.key) continue;
      ++maps;
      if (valid_map(row)) continue;
      append_item(failing, row["mesh"].get<std::string>() + " (" + bench::status_text(row) +
                               ", flips " + bench::integer(row, "flips") + ", degenerate " +
                               bench::integer(row, "degenerate") + ", degree " +
                               bench::scientific(row.value("degree", Json())) + ")");
    }
    if (maps == 0) continue;
    add_target(list, variant.key + " valid on every mesh",
               failing.empty() ? "all " + std::to_string(maps) : "invalid: " + failing,
               "status ok, 0 flips, 0 degenerate, degree 1", failing.empty(),
               variant.key == "sphere" ? "" : "comparison (not the default options)");
  }
  for (const SphereVariant& variant : sphere_variants()) {
    std::string figures;
    bool met = true;
    bool any = false;
    for (const Json& row : runs) {
      const int faces = row.value("faces", 0);
      if (row["key"] != variant.key || faces < kFloorTargetMinFaces ||
          faces > kFloorTargetMaxFaces) {
        continue;
      }
      any = true;
      const Json x_floor = row.value("x_floor", Json());
      met = met && x_floor.is_number() && x_floor.get<double>() <= kFloorTargetMultiple;
      append_item(figures, row["mesh"].get<std::string>() + " " + bench::fixed(x_floor, 2));
    }
    add_target(list, variant.key + " x_floor at 100K-200K faces",
               any ? figures : "no mesh of 100K-200K faces in this run",
               "<= " + bench::fixed(Json(kFloorTargetMultiple), 0), any ? Json(met) : Json(),
               variant.key == "sphere" ? "" : "comparison (not the default options)");
  }
  for (const SphereVariant& variant : sphere_variants()) {
    std::string figures;
    bool met = true;
    bool any = false;
    for (const Json& row : runs) {
      const int faces = row.value("faces", 0);
      if (row["key"] != variant.key || faces < kMemoryTargetMinFaces ||
          faces > kMemoryTargetMaxFaces) {
        continue;
      }
      any = true;
      const Json peak = row.value("peak_MB", Json());
      met = met && peak.is_number() && peak.get<double>() <= kMemoryTargetMegabytes;
      append_item(figures, row["mesh"].get<std::string>() + " (" + std::to_string(faces) +
                               " faces) " + bench::fixed(peak, 0) + " MB");
    }
    add_target(list, variant.key + " peak memory at ~200K faces (150K-250K)",
               any ? figures : "no mesh of 150K-250K faces in this run",
               "<= " + bench::fixed(Json(kMemoryTargetMegabytes), 0) + " MB",
               any ? Json(met) : Json(),
               variant.key == "sphere" ? "" : "comparison (not the default options)");
  }
  return list;
}

// ---------------------------------------------------------------------------------------------
// Markdown

//! "seconds (percent of the row's total)".
std::string share_text(const Json& row, const std::string& group) {
  const Json value = row["phase_groups"].value(group, Json());
  if (!value.is_number()) return "-";
  const double total = row["seconds"].get<double>();
  const long percent = total > 0.0 ? std::lround(100.0 * value.get<double>() / total) : 0;
  return bench::fixed(value, 3) + " (" + std::to_string(percent) + "%)";
}

std::string markdown(const Json& results) {
  std::ostringstream md;
  md << "# harmonia spherical map benchmark\n\n"
     << "Host: " << results["cpu"].get<std::string>() << ", " << results["cores"]
     << " cores; load average " << results["load_start"].get<std::string>() << " at start, "
     << results["load_end"].get<std::string>()
     << " at end. CPU backend. Seconds: the library's own time (sum of report.timings), fastest "
     << "of " << results["repeat"] << " run(s); each (mesh, row) in its own process, capped at "
     << results["timeout"] << " s. floor: CHOLMOD supernodal analyze + factorize + solve of the "
     << "cotangent Dirichlet system of the same mesh cut open (cut_to_disk, automatic ends), "
     << "assembly excluded; x_floor = seconds / floor. sphere: spherical_map with default options "
     << "(cotangent weights); sphere-mean-value: options.weights = mean_value. solver: "
     << "report.solver (the rectangle's factorization). peak_MB: peak "
     << "resident size of the map's process (mesh included). flips / degen: triangles turned over "
     << "/ degenerate on the sphere (exact orientation); degree: signed area / 4 pi (1 = "
     << "bijective); angle_ms: mean squared corner angle error (rad^2); conformal / area: "
     << "spherical_metrics' area-weighted means (chord triangles); area_first / area_final: the "
     << "library's area distortion (spherical areas) of the first map and of the final round; "
     << "qh: quasi-harmonic rounds taken; fb: fall-backs (listed below).\n\n";
  md << "| mesh | faces | row | solver | seconds | x_floor | peak_MB | flips | degen | degree | "
        "angle_ms | conformal | area | area_first | area_final | qh | fb | status |\n"
     << "|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const Json& row : results["runs"]) {
    const bool map = row["key"] != "floor";
    md << "| " << row["mesh"].get<std::string>() << " | " << row.value("faces", 0) << " | "
       << row["key"].get<std::string>() << " | " << bench::solver_text(row) << " | "
       << bench::fixed(row.value("seconds", Json()), 3) << " | "
       << bench::fixed(row.value("x_floor", Json()), 2) << " | "
       << bench::fixed(row.value("peak_MB", Json()), 0) << " | " << bench::integer(row, "flips")
       << " | " << bench::integer(row, "degenerate") << " | "
       << bench::fixed(row.value("degree", Json()), 6) << " | "
       << bench::fixed(row.value("angle_error_mean_squared", Json()), 4) << " | "
       << bench::fixed(row.value("conformal_mean", Json()), 4) << " | "
       << bench::fixed(row.value("area_distortion_mean", Json()), 4) << " | "
       << bench::fixed(row.value("area_first", Json()), 4) << " | "
       << bench::fixed(row.value("area_final", Json()), 4) << " | "
       << (map ? bench::integer(row, "quasi_harmonic_rounds") : std::string("-")) << " | "
       << (map && row.contains("fallbacks") ? std::to_string(row["fallbacks"].size())
                                            : std::string("-"))
       << " | " << bench::status_text(row) << " |\n";
  }

  md << "\n## How the time splits (seconds, share of the row's total)\n\n"
     << "paths: validation, poles and analysis (the date line, the domain cut along it, the "
     << "system's pattern); harmonic map: the first map (factorization, solve, lift, untangling); "
     << "quasi-harmonic (rounds started): every round (7.2), a shortened round's refused "
     << "attempts included (they are in the fall-backs); relaxation: the band around the date line "
     << "(7.3); metrics: the validity check. "
     << "untimed: wall clock of the call minus the phases. floor: analyze / factorize / solve.\n\n"
     << "| mesh | faces | row | seconds | paths | harmonic map | quasi-harmonic (rounds) | "
        "relaxation | metrics | other | untimed |\n"
     << "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Json& row : results["runs"]) {
    if (!row.contains("seconds")) continue;
    md << "| " << row["mesh"].get<std::string>() << " | " << row.value("faces", 0) << " | "
       << row["key"].get<std::string>() << " | " << bench::fixed(row["seconds"], 3) << " | ";
    if (row["key"] == "floor") {
      md << bench::phases_text(row) << " | | | | | | |\n";
      continue;
    }
    md << share_text(row, "paths") << " | " << share_text(row, "harmonic_map") << " | "
       << share_text(row, "quasi_harmonic") << " (" << bench::integer(row, "quasi_harmonic_phases")
       << ") | " << share_text(row, "relaxation") << " | " << share_text(row, "metrics") << " | "
       << share_text(row, "other") << " | "
       << bench::fixed(Json(row["wall_seconds"].get<double>() - row["seconds"].get<double>()), 3)
       << " |\n";
  }

  if (!results["growth"].empty()) {
    md << "\n## How it grows with size\n\n"
       << "Each scaling mesh at its sizes: the figure at each size and the growth exponent between "
       << "consecutive sizes, log(t2 / t1) / log(faces2 / faces1) (1 = linear in the faces).\n\n"
       << "| mesh | row | part | faces | values | exponents |\n|---|---|---|---|---|---|\n";
    for (const Json& entry : results["growth"]) {
      std::string faces, values, exponents;
      for (std::size_t k = 0; k < entry["faces"].size(); ++k) {
        append_item(faces, std::to_string(entry["faces"][k].get<int>()));
        append_item(values, bench::fixed(entry["values"][k], entry["part"] == "peak_MB" ? 0 : 3));
      }
      for (const Json& exponent : entry["exponents"]) {
        append_item(exponents, bench::fixed(exponent, 2));
      }
      md << "| " << entry["base"].get<std::string>() << " | " << entry["key"].get<std::string>()
         << " | " << entry["part"].get<std::string>() << " | " << faces << " | " << values << " | "
         << exponents << " |\n";
    }
  }

  bool any_fallback = false;
  for (const Json& row : results["runs"]) {
    if (row.contains("fallbacks") && !row["fallbacks"].empty()) any_fallback = true;
  }
  if (any_fallback) {
    md << "\n## Fall-backs (report.fallbacks)\n\n| mesh | row | fall-backs |\n|---|---|---|\n";
    for (const Json& row : results["runs"]) {
      if (!row.contains("fallbacks") || row["fallbacks"].empty()) continue;
      std::string text;
      for (const Json& fallback : row["fallbacks"]) {
        append_item(text, fallback.get<std::string>(), "; ");
      }
      md << "| " << row["mesh"].get<std::string>() << " | " << row["key"].get<std::string>()
         << " | " << text << " |\n";
    }
  }

  md << "\n## Targets (CPU)\n\n| target | measured | limit | met | note |\n|---|---|---|---|---|\n";
  for (const Json& target : results["targets"]) {
    md << "| " << target["target"].get<std::string>() << " | "
       << target["measured"].get<std::string>() << " | " << target["limit"].get<std::string>()
       << " | " << (target["met"].is_null() ? "n/a" : target["met"].get<bool>() ? "yes" : "NO")
       << " | "
       << target["note"].get<std::string>() << " |\n";
  }
  return md.str();
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse_options(argc, argv, &options)) {
    print_usage();
    return 2;
  }
  harmonia::set_blas_thread_policy(options.blas_threads);  // Inherited by every forked child.
  const fs::path closed_dir = bench::shared_data_dir() / "closed";
  std::vector<fs::path> corpus;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(closed_dir, error)) {
    if (entry.path().extension() == ".obj") corpus.push_back(entry.path());
  }
  if (corpus.empty()) {
    std::cerr << "corpus_sphere_benchmark: corpus absent (" << closed_dir
              << " has no .obj files)\n";
    return 1;
  }
  std::sort(corpus.begin(), corpus.end());
  const std::vector<MeshCase> cases = mesh_cases(corpus, options);

  // The cut-open disks of the floor are written here, one at a time, and removed at the end.
  const fs::path scratch =
      fs::temp_directory_path() / ("harmonia-sphere-bench-" + std::to_string(::getpid()));
  fs::create_directories(scratch, error);

  Json results{{"cpu", cpu_model()},
               {"cores", static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN))},
               {"load_start", load_average()},
               {"repeat", options.repeat},
               {"timeout", options.timeout_seconds},
               {"blas_threads", options.blas_threads == harmonia::BlasThreadPolicy::leave_alone
                                    ? "leave"
                                    : "hold"},
               {"runs", Json::array()}};
  for (const MeshCase& mesh_case : cases) {
    std::cerr << "[" << mesh_case.name << "] floor" << std::flush;
    const Json floor = floor_row(mesh_case, scratch, options);
    const double floor_seconds = floor.contains("x_floor") ? floor["seconds"].get<double>() : 0.0;
    results["runs"].push_back(floor);
    std::cerr << " " << bench::fixed(floor.value("seconds", Json()), 3) << " s";
    for (const SphereVariant& variant : sphere_variants()) {
      std::cerr << ", " << variant.key << std::flush;
      const Json row = sphere_row(mesh_case, variant, floor_seconds, options);
      std::cerr << " " << bench::fixed(row.value("seconds", Json()), 3) << " s";
      results["runs"].push_back(row);
    }
    std::cerr << "\n";
  }
  fs::remove_all(scratch, error);

  results["load_end"] = load_average();
  results["growth"] = growth(results["runs"]);
  results["targets"] = targets(results["runs"]);

  const std::string report = markdown(results);
  std::cout << report;
  std::ofstream(options.out_md) << report;
  std::ofstream(options.out_json) << results.dump(2) << "\n";
  return 0;
}
