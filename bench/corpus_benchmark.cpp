// corpus_benchmark: every planar method on every disk mesh of the corpus (plus the face scan at 4x
// and 16x its size), next to the floor of the same mesh, with peak memory and map quality.
//
// Each (mesh, method) runs in its own forked process, so its peak resident size (VmHWM) is its
// own; the child sends its measurements back through a pipe as JSON. Output: a markdown table
// (stdout and --out-md) and a JSON file (--out-json). See bench/README.md for the columns.

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_support.h"
#include "harmonia/fixed_boundary_map.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/lscm.h"
#include "harmonia/metrics.h"
#include "harmonia/quasi_harmonic_map.h"

namespace {

namespace fs = std::filesystem;
namespace bench = harmonia::bench;
using Json = nlohmann::ordered_json;

struct Options {
  std::vector<int> sizes{1, 4, 16};  // Size factors of the scaling mesh.
  std::vector<std::string> meshes;   // Corpus names to run (empty: all).
  std::vector<std::string> methods;  // Method keys to run (empty: all).
  std::string scaling_mesh = "face";
  int repeat = 1;             // Timed repetitions per run; the fastest counts.
  int timeout_seconds = 900;  // Per child process.
  bool read_timing = true;
  fs::path out_md = "bench-results.md";
  fs::path out_json = "bench-results.json";
};

struct MeshCase {
  std::string name;  // e.g. "face-x16".
  fs::path path;
  int factor = 1;
};

struct Method {
  std::string key;      // Command-line name, e.g. "conformal-cotangent".
  std::string method;   // Column "method".
  std::string weights;  // Column "weights".
};

const std::vector<Method>& all_methods() {
  static const std::vector<Method> methods{
      {"conformal-cotangent", "conformal", "cotangent"},
      {"conformal-mean-value", "conformal", "mean-value"},
      {"conformal-uniform", "conformal", "uniform"},
      {"lscm", "lscm", "-"},
      {"qhm", "qhm", "tensor-cotangent"},
  };
  return methods;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

bool wanted(const std::vector<std::string>& filter, const std::string& name) {
  return filter.empty() || std::find(filter.begin(), filter.end(), name) != filter.end();
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

// ---------------------------------------------------------------------------------------------
// Child processes

//! Runs `work` in a forked child and returns what it sent back. A child that crashes, times out
//! or sends nothing readable gives {"status": "crashed", "message": ...}.
Json run_in_child(const std::function<Json()>& work, int timeout_seconds) {
  std::cout.flush();
  std::cerr.flush();
  int channel[2];
  if (::pipe(channel) != 0) return Json{{"status", "crashed"}, {"message", "pipe() failed"}};
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(channel[0]);
    ::close(channel[1]);
    return Json{{"status", "crashed"}, {"message", "fork() failed"}};
  }
  if (child == 0) {
    ::close(channel[0]);
    ::alarm(static_cast<unsigned>(timeout_seconds));
    Json result;
    try {
      result = work();
    } catch (const std::exception& error) {
      result = Json{{"status", "exception"}, {"message", error.what()}};
    }
    const std::string text = result.dump();
    std::size_t written = 0;
    while (written < text.size()) {
      const ssize_t step = ::write(channel[1], text.data() + written, text.size() - written);
      if (step < 0 && errno == EINTR) continue;
      if (step <= 0) break;
      written += static_cast<std::size_t>(step);
    }
    ::close(channel[1]);
    ::_exit(0);  // No destructors or atexit handlers of the parent's state in the child.
  }
  ::close(channel[1]);
  std::string text;
  char buffer[65536];
  for (;;) {
    const ssize_t got = ::read(channel[0], buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    text.append(buffer, static_cast<std::size_t>(got));
  }
  ::close(channel[0]);
  int wait_status = 0;
  while (::waitpid(child, &wait_status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(wait_status)) {
    const int signal_number = WTERMSIG(wait_status);
    return Json{{"status", signal_number == SIGALRM ? "timeout" : "crashed"},
                {"message", signal_number == SIGALRM
                                ? "no result within " + std::to_string(timeout_seconds) + " s"
                                : std::string("killed by signal ") + ::strsignal(signal_number)}};
  }
  try {
    return Json::parse(text);
  } catch (const std::exception&) {
    return Json{{"status", "crashed"}, {"message", "the child sent no readable result"}};
  }
}

//! What one map computation gives back, whatever the method.
struct MapOutcome {
  Eigen::MatrixX2d uv;
  harmonia::SolveReport report;
};

MapOutcome compute_map(const harmonia::Mesh& mesh, const std::string& key) {
  harmonia::SolverOptions solver;
  solver.backend = harmonia::BackendChoice::cpu;
  if (key == "lscm") {
    harmonia::LscmOptions options;
    options.solver = solver;
    harmonia::MapResult result = harmonia::lscm(mesh, options);
    return {std::move(result.uv), std::move(result.report)};
  }
  if (key == "qhm") {
    harmonia::QuasiHarmonicOptions options;
    options.solver = solver;
    harmonia::QuasiHarmonicResult result = harmonia::quasi_harmonic_map(mesh, options);
    return {std::move(result.uv), std::move(result.report)};
  }
  harmonia::FixedBoundaryOptions options;
  options.solver = solver;
  const std::string scheme = key.substr(std::string("conformal-").size());
  options.weights = harmonia::weight_scheme_from_string(scheme).value();
  harmonia::MapResult result = harmonia::fixed_boundary_map(mesh, options);
  return {std::move(result.uv), std::move(result.report)};
}

Json phases_json(const harmonia::SolveReport& report) {
  Json phases = Json::array();
  for (const harmonia::PhaseTiming& timing : report.timings) {
    phases.push_back(Json{{"phase", timing.phase}, {"seconds", timing.seconds}});
  }
  return phases;
}

//! Child body for one method on one mesh: read, time `repeat` runs (fastest counts), measure the
//! peak resident size of the runs, then evaluate the fastest run's map.
Json measure_method(const MeshCase& mesh_case, const Method& method, int repeat) {
  bench::Stopwatch reading;
  const harmonia::Mesh mesh = harmonia::read_mesh(mesh_case.path);
  const double read_seconds = reading.seconds();
  const double resident_before = bench::process_status_megabytes("VmRSS");
  const bool peak_reset = bench::reset_peak_resident_size();

  double best_seconds = std::numeric_limits<double>::infinity();
  MapOutcome best;
  for (int run = 0; run < repeat; ++run) {
    bench::Stopwatch stopwatch;
    MapOutcome outcome = compute_map(mesh, method.key);
    const double seconds = stopwatch.seconds();
    if (seconds < best_seconds) {
      best_seconds = seconds;
      best = std::move(outcome);
    }
  }
  const double peak = bench::process_status_megabytes("VmHWM");

  Json result{
      {"status", std::string(harmonia::to_string(best.report.status))},
      {"message", best.report.message},
      {"faces", mesh.face_count()},
      {"vertices", mesh.vertex_count()},
      {"backend", std::string(harmonia::to_string(best.report.backend)) + "/" + best.report.solver},
      {"seconds", best_seconds},
      {"read_seconds", read_seconds},
      {"peak_MB", peak},
      {"rss_before_MB", resident_before},
      {"peak_is_per_method", peak_reset},
      {"rounds", best.report.rounds},
      {"iterations", best.report.iterations},
      {"residual", best.report.residual},
      {"phases", phases_json(best.report)}};
  if (best.uv.rows() == mesh.vertex_count() && best.uv.allFinite()) {
    const harmonia::DistortionMetrics metrics = harmonia::evaluate_map(mesh, best.uv, mesh.faces);
    result["flips"] = metrics.flipped_triangles;
    result["zero_area"] = metrics.zero_area_triangles;
    result["boundary_self_intersections"] = metrics.boundary_self_intersections;
    result["conformal_mean"] = metrics.conformal_distortion_mean;
    result["area_distortion_mean"] = metrics.area_distortion_mean;
  }
  return result;
}

//! Child body for the floor: assemble the cotangent Dirichlet system (not timed), then time
//! analyze + factorize + solve `repeat` times (fastest counts).
Json measure_floor_child(const MeshCase& mesh_case, int repeat) {
  const harmonia::Mesh mesh = harmonia::read_mesh(mesh_case.path);
  bench::Stopwatch assembling;
  const Eigen::SparseMatrix<double> laplacian =
      harmonia::laplacian(mesh, harmonia::WeightScheme::cotangent);
  const double assembly_seconds = assembling.seconds();
  const bench::DirichletSystem system = bench::dirichlet_system(mesh, laplacian);
  const double resident_before = bench::process_status_megabytes("VmRSS");
  const bool peak_reset = bench::reset_peak_resident_size();

  bench::FloorMeasurement best;
  best.analyze_seconds = std::numeric_limits<double>::infinity();
  for (int run = 0; run < repeat; ++run) {
    bench::FloorMeasurement floor = bench::measure_floor(system);
    if (!floor.available) {
      return Json{
          {"status", "unavailable"}, {"message", floor.message}, {"faces", mesh.face_count()}};
    }
    if (floor.total_seconds() < best.total_seconds()) best = std::move(floor);
  }
  return Json{
      {"status", "ok"},
      {"message", ""},
      {"faces", mesh.face_count()},
      {"vertices", mesh.vertex_count()},
      {"backend", "cpu/cholmod-supernodal"},
      {"seconds", best.total_seconds()},
      {"peak_MB", bench::process_status_megabytes("VmHWM")},
      {"rss_before_MB", resident_before},
      {"peak_is_per_method", peak_reset},
      {"unknowns", best.unknowns},
      {"factor_nonzeros", best.factor_nonzeros},
      {"residual", best.relative_residual},
      {"laplacian_assembly_seconds", assembly_seconds},
      {"phases", Json::array({Json{{"phase", "analyze"}, {"seconds", best.analyze_seconds}},
                              Json{{"phase", "factorize"}, {"seconds", best.factorize_seconds}},
                              Json{{"phase", "solve"}, {"seconds", best.solve_seconds}}})}};
}

Json measure_reading(const fs::path& path, int repeat) {
  double best = std::numeric_limits<double>::infinity();
  int faces = 0;
  for (int run = 0; run < std::max(repeat, 2);
       ++run) {  // The first run may meet a cold page cache.
    bench::Stopwatch stopwatch;
    const harmonia::Mesh mesh = harmonia::read_mesh(path);
    best = std::min(best, stopwatch.seconds());
    faces = mesh.face_count();
  }
  std::error_code error;
  return Json{{"status", "ok"},
              {"file", path.filename().string()},
              {"faces", faces},
              {"file_MB", static_cast<double>(fs::file_size(path, error)) / (1024.0 * 1024.0)},
              {"seconds", best},
              {"peak_MB", bench::process_status_megabytes("VmHWM")}};
}

// ---------------------------------------------------------------------------------------------
// Output

std::string fixed(const Json& value, int decimals) {
  if (!value.is_number()) return "-";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value.get<double>());
  return text;
}

std::string phases_text(const Json& row) {
  if (!row.contains("phases") || row["phases"].empty()) return "-";
  std::string text;
  double accounted = 0.0;
  for (const Json& phase : row["phases"]) {
    if (!text.empty()) text += ", ";
    text += phase["phase"].get<std::string>() + " " + fixed(phase["seconds"], 3);
    accounted += phase["seconds"].get<double>();
  }
  if (row["seconds"].is_number()) {
    text += ", (untimed " + fixed(row["seconds"].get<double>() - accounted, 3) + ")";
  }
  return text;
}

std::string markdown(const Json& results) {
  std::ostringstream md;
  md << "# harmonia corpus benchmark\n\n"
     << "Host: " << results["cpu"].get<std::string>() << ", " << results["cores"]
     << " cores; load average " << results["load_start"].get<std::string>() << " at start, "
     << results["load_end"].get<std::string>() << " at end. Wall-clock seconds, fastest of "
     << results["repeat"] << " run(s); each (mesh, method) in its own process. x_floor = seconds / "
     << "floor (CHOLMOD supernodal analyze + factorize + solve of the same mesh's cotangent "
     << "Dirichlet system, assembly excluded). peak_MB: peak resident size of that process during "
     << "the method (mesh included).\n\n";
  md << "| mesh | faces | method | weights | backend | seconds | x_floor | peak_MB | flips | "
        "conformal_mean | area_distortion_mean | status |\n"
     << "|---|---:|---|---|---|---:|---:|---:|---:|---:|---:|---|\n";
  for (const Json& row : results["runs"]) {
    md << "| " << row["mesh"].get<std::string>() << " | " << row.value("faces", 0) << " | "
       << row["method"].get<std::string>() << " | " << row["weights"].get<std::string>() << " | "
       << row.value("backend", std::string("-")) << " | " << fixed(row.value("seconds", Json()), 3)
       << " | " << fixed(row.value("x_floor", Json()), 2) << " | "
       << fixed(row.value("peak_MB", Json()), 0) << " | "
       << (row.contains("flips") ? std::to_string(row["flips"].get<int>()) : std::string("-"))
       << " | " << fixed(row.value("conformal_mean", Json()), 4) << " | "
       << fixed(row.value("area_distortion_mean", Json()), 4) << " | "
       << row["status"].get<std::string>()
       << (row.value("message", std::string()).empty() ? ""
                                                       : ": " + row["message"].get<std::string>())
       << " |\n";
  }
  md << "\n## Where the time goes (SolveReport phases, seconds)\n\n"
     << "| mesh | method | weights | seconds | phases |\n|---|---|---|---:|---|\n";
  for (const Json& row : results["runs"]) {
    md << "| " << row["mesh"].get<std::string>() << " | " << row["method"].get<std::string>()
       << " | " << row["weights"].get<std::string>() << " | "
       << fixed(row.value("seconds", Json()), 3) << " | " << phases_text(row) << " |\n";
  }
  if (!results["reading"].empty()) {
    md << "\n## read_mesh (target <= 1 s)\n\n| file | faces | file_MB | seconds | MB/s |\n"
       << "|---|---:|---:|---:|---:|\n";
    for (const Json& row : results["reading"]) {
      if (row["status"] != "ok") {
        md << "| " << row.value("file", std::string("?")) << " | - | - | "
           << row["status"].get<std::string>() << ": " << row.value("message", std::string())
           << " | - |\n";
        continue;
      }
      md << "| " << row["file"].get<std::string>() << " | " << row["faces"] << " | "
         << fixed(row["file_MB"], 1) << " | " << fixed(row["seconds"], 3) << " | "
         << fixed(row["file_MB"].get<double>() / row["seconds"].get<double>(), 0) << " |\n";
    }
  }
  if (!results["targets"].empty()) {
    md << "\n## Targets\n\n| target | measured | limit | met |\n|---|---:|---:|---|\n";
    for (const Json& target : results["targets"]) {
      md << "| " << target["target"].get<std::string>() << " | " << fixed(target["measured"], 2)
         << " | " << fixed(target["limit"], 2) << " | "
         << (target["met"].get<bool>() ? "yes" : "NO") << " |\n";
    }
  }
  return md.str();
}

//! The report's targets: fixed-boundary conformal <= 1.3x floor and quasi-harmonic <= 5x floor on
//! the largest scaled mesh, read_mesh <= 1 s for every timed file.
Json targets(const Json& runs, const Json& reading, const std::string& largest_mesh) {
  Json list = Json::array();
  for (const Json& row : runs) {
    if (row["mesh"] != largest_mesh || !row.contains("x_floor")) continue;
    const std::string key = row["key"].get<std::string>();
    const double limit = key == "conformal-cotangent" ? 1.3 : key == "qhm" ? 5.0 : 0.0;
    if (limit == 0.0) continue;
    const double measured = row["x_floor"].get<double>();
    list.push_back(Json{{"target", largest_mesh + " " + key + " (x floor)"},
                        {"measured", measured},
                        {"limit", limit},
                        {"met", measured <= limit}});
  }
  for (const Json& row : reading) {
    if (row["status"] != "ok") continue;
    const double measured = row["seconds"].get<double>();
    list.push_back(Json{{"target", "read_mesh " + row["file"].get<std::string>() + " (s)"},
                        {"measured", measured},
                        {"limit", 1.0},
                        {"met", measured <= 1.0}});
  }
  return list;
}

// ---------------------------------------------------------------------------------------------

void print_usage() {
  std::cout
      << "usage: corpus_benchmark [--sizes 1,4,16] [--meshes a,b] [--methods m1,m2] [--repeat N]\n"
         "                        [--timeout S] [--no-read-timing] [--out-md FILE] [--out-json "
         "FILE]\n"
         "methods: conformal-cotangent, conformal-mean-value, conformal-uniform, lscm, qhm\n"
         "--sizes applies to the scaling mesh (face); other corpus meshes run at their own size.\n";
}

bool parse_options(int argc, char** argv, Options* options) {
  for (int index = 1; index < argc; ++index) {
    const std::string flag = argv[index];
    const bool has_value = index + 1 < argc;
    if (flag == "--help" || flag == "-h") {
      print_usage();
      std::exit(0);
    } else if (flag == "--no-read-timing") {
      options->read_timing = false;
    } else if (!has_value) {
      std::cerr << "corpus_benchmark: " << flag << " needs a value (or is unknown)\n";
      return false;
    } else {
      const std::string value = argv[++index];
      if (flag == "--sizes") {
        options->sizes.clear();
        for (const std::string& size : split_list(value)) options->sizes.push_back(std::stoi(size));
      } else if (flag == "--meshes") {
        options->meshes = split_list(value);
      } else if (flag == "--methods") {
        options->methods = split_list(value);
      } else if (flag == "--repeat") {
        options->repeat = std::max(1, std::stoi(value));
      } else if (flag == "--timeout") {
        options->timeout_seconds = std::max(1, std::stoi(value));
      } else if (flag == "--out-md") {
        options->out_md = value;
      } else if (flag == "--out-json") {
        options->out_json = value;
      } else {
        std::cerr << "corpus_benchmark: unknown option " << flag << "\n";
        return false;
      }
    }
  }
  for (const std::string& key : options->methods) {
    const auto& methods = all_methods();
    if (std::none_of(methods.begin(), methods.end(),
                     [&](const Method& m) { return m.key == key; })) {
      std::cerr << "corpus_benchmark: unknown method " << key << "\n";
      return false;
    }
  }
  for (const int size : options->sizes) {
    if (bench::subdivision_steps(size) < 0) {
      std::cerr << "corpus_benchmark: size " << size << " is not a power of 4\n";
      return false;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse_options(argc, argv, &options)) {
    print_usage();
    return 2;
  }
  const fs::path disk_dir = bench::shared_data_dir() / "disk";
  std::vector<fs::path> corpus;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(disk_dir, error)) {
    if (entry.path().extension() == ".obj") corpus.push_back(entry.path());
  }
  if (corpus.empty()) {
    std::cerr << "corpus_benchmark: corpus absent (" << disk_dir << " has no .obj files)\n";
    return 1;
  }
  std::sort(corpus.begin(), corpus.end());

  std::vector<MeshCase> cases;
  for (const fs::path& path : corpus) {
    const std::string name = path.stem().string();
    if (!wanted(options.meshes, name)) continue;
    if (name != options.scaling_mesh) {
      cases.push_back({name, path, 1});
      continue;
    }
    for (const int factor : options.sizes) {
      std::string message;
      const auto scaled = bench::scaled_mesh(path, factor, &message);
      if (!scaled) {
        std::cerr << "corpus_benchmark: " << message << "\n";
        continue;
      }
      cases.push_back({factor == 1 ? name : name + "-x" + std::to_string(factor), *scaled, factor});
    }
  }

  Json results{
      {"cpu", cpu_model()},           {"cores", static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN))},
      {"load_start", load_average()}, {"repeat", options.repeat},
      {"runs", Json::array()},        {"reading", Json::array()}};
  std::string largest_mesh;
  int largest_factor = 0;
  for (const MeshCase& mesh_case : cases) {
    if (mesh_case.factor > largest_factor) {
      largest_factor = mesh_case.factor;
      largest_mesh = mesh_case.name;
    }
    std::cerr << "[" << mesh_case.name << "] floor" << std::flush;
    Json floor = run_in_child([&] { return measure_floor_child(mesh_case, options.repeat); },
                              options.timeout_seconds);
    const double floor_seconds =
        floor.value("status", std::string()) == "ok" ? floor["seconds"].get<double>() : 0.0;
    Json floor_row{
        {"mesh", mesh_case.name}, {"key", "floor"}, {"method", "floor"}, {"weights", "cotangent"}};
    floor_row.update(floor);
    if (floor_seconds > 0.0) floor_row["x_floor"] = 1.0;
    results["runs"].push_back(floor_row);
    std::cerr << " " << fixed(floor.value("seconds", Json()), 3) << " s";

    for (const Method& method : all_methods()) {
      if (!wanted(options.methods, method.key)) continue;
      std::cerr << ", " << method.key << std::flush;
      Json measured =
          run_in_child([&] { return measure_method(mesh_case, method, options.repeat); },
                       options.timeout_seconds);
      Json row{{"mesh", mesh_case.name},
               {"key", method.key},
               {"method", method.method},
               {"weights", method.weights}};
      row.update(measured);
      if (floor_seconds > 0.0 && row.contains("seconds")) {
        row["x_floor"] = row["seconds"].get<double>() / floor_seconds;
      }
      results["runs"].push_back(row);
      std::cerr << " " << fixed(row.value("seconds", Json()), 3) << " s";
    }
    std::cerr << "\n";
  }

  if (options.read_timing) {
    const fs::path to_read[] = {disk_dir / "face.obj", disk_dir / "lion-head.obj"};
    const int factors[] = {16, 64};
    for (int k = 0; k < 2; ++k) {
      std::string message;
      const auto path = bench::scaled_mesh(to_read[k], factors[k], &message);
      if (!path) {
        results["reading"].push_back(Json{
            {"status", "absent"}, {"file", to_read[k].filename().string()}, {"message", message}});
        continue;
      }
      std::cerr << "read_mesh " << path->filename().string() << std::flush;
      Json row = run_in_child([&] { return measure_reading(*path, options.repeat); },
                              options.timeout_seconds);
      if (!row.contains("file")) row["file"] = path->filename().string();
      std::cerr << " " << fixed(row.value("seconds", Json()), 3) << " s\n";
      results["reading"].push_back(row);
    }
  }
  results["load_end"] = load_average();
  results["targets"] = targets(results["runs"], results["reading"], largest_mesh);

  const std::string table = markdown(results);
  std::cout << table;
  std::ofstream(options.out_md) << table;
  std::ofstream(options.out_json) << results.dump(2) << "\n";
  return 0;
}
