// corpus_benchmark: every planar method (the fixed-boundary maps, LSCM, quasi-harmonic maps,
// linear ABF and ABF with each of its step solvers) on every disk mesh of the corpus (plus the
// face scan at 4x and 16x its size), on the CPU and, with --backends cpu,vulkan, on the Vulkan
// device, next to the floor of the same mesh, with peak memory and map quality.
//
// Each (mesh, method, backend) runs in its own forked process (corpus_child.h), so its peak
// resident size (VmHWM) is its own. Output: a markdown table (stdout and --out-md) and a JSON
// file (--out-json). See bench/README.md for the options and columns.

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_support.h"
#include "bench/corpus_child.h"
#include "bench/corpus_methods.h"
#include "bench/corpus_report.h"
#include "harmonia/blas_threads.h"

namespace {

namespace fs = std::filesystem;
namespace bench = harmonia::bench;
using bench::Json;
using bench::Method;
using bench::RowBackend;

struct Options {
  std::vector<int> sizes{1, 4, 16};  // Size factors of the scaling mesh.
  std::vector<std::string> meshes;   // Corpus names to run (empty: all).
  std::vector<std::string> methods;  // Method keys to run (empty: all).
  std::vector<RowBackend> backends{RowBackend::cpu};
  std::string scaling_mesh = "face";
  bool scale_all = false;  // Every corpus mesh at every size, not only the scaling mesh.
  int repeat = 1;                  // Timed repetitions per run; the fastest counts.
  int timeout_seconds = 900;       // Per child process.
  int slow_max_faces = 20000;      // Largest mesh for the slow ABF step solvers.
  int software_max_faces = 60000;  // Largest mesh for Vulkan rows on a software device.
  bool read_timing = true;
  // What harmonia may do with OpenBLAS's process-wide thread count (harmonia/blas_threads.h): by
  // default what the harmonia program does; --blas-threads leave measures the library's default.
  harmonia::BlasThreadPolicy blas_threads =
      harmonia::BlasThreadPolicy::hold_during_split_factorizations;
  fs::path out_md = "bench-results.md";
  fs::path out_json = "bench-results.json";
};

struct MeshCase {
  std::string name;  // e.g. "face-x16".
  fs::path path;
  int factor = 1;
};

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

std::string slow_solver_names() {
  std::string names;
  for (const Method& method : bench::all_methods()) {
    if (!method.slow) continue;
    names += (names.empty() ? "" : ", ") + method.key;
  }
  return names;
}

// ---------------------------------------------------------------------------------------------

void print_usage() {
  std::cout
      << "usage: corpus_benchmark [--sizes 1,4,16] [--meshes a,b] [--methods m1,m2]\n"
         "                        [--backends cpu,vulkan] [--repeat N] [--timeout S]\n"
         "                        [--slow-max-faces F] [--software-max-faces F]\n"
         "                        [--scale-all] [--no-read-timing] [--out-md FILE]\n"
         "                        [--out-json FILE] [--blas-threads hold|leave]\n"
         "methods: conformal-cotangent, conformal-mean-value, conformal-uniform, lscm, qhm,\n"
         "         linabf, abf, abf-schur-minres, abf-uzawa, abf-full-minres, abf-full-cgnr,\n"
         "         abf-schur-direct\n"
         "--sizes applies to the scaling mesh (face); other corpus meshes run at their own size,\n"
         "or at every size too with --scale-all.\n"
         "--blas-threads: hold (default, as the harmonia program) lets harmonia hold OpenBLAS's\n"
         "thread count while it factorizes two halves side by side; leave (the library's default)\n"
         "forbids it, and large systems are factorized whole.\n";
}

bool parse_backends(const std::string& value, Options* options) {
  options->backends.clear();
  for (const std::string& name : split_list(value)) {
    if (name == "cpu") {
      options->backends.push_back(RowBackend::cpu);
    } else if (name == "vulkan") {
      options->backends.push_back(RowBackend::vulkan);
    } else {
      std::cerr << "corpus_benchmark: unknown backend " << name << " (cpu, vulkan)\n";
      return false;
    }
  }
  return !options->backends.empty();
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
    } else if (flag == "--scale-all") {
      options->scale_all = true;
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
      } else if (flag == "--backends") {
        if (!parse_backends(value, options)) return false;
      } else if (flag == "--repeat") {
        options->repeat = std::max(1, std::stoi(value));
      } else if (flag == "--timeout") {
        options->timeout_seconds = std::max(1, std::stoi(value));
      } else if (flag == "--slow-max-faces") {
        options->slow_max_faces = std::max(0, std::stoi(value));
      } else if (flag == "--software-max-faces") {
        options->software_max_faces = std::max(0, std::stoi(value));
      } else if (flag == "--out-md") {
        options->out_md = value;
      } else if (flag == "--out-json") {
        options->out_json = value;
      } else if (flag == "--blas-threads" && (value == "hold" || value == "leave")) {
        options->blas_threads = value == "hold"
                                    ? harmonia::BlasThreadPolicy::hold_during_split_factorizations
                                    : harmonia::BlasThreadPolicy::leave_alone;
      } else {
        std::cerr << "corpus_benchmark: unknown option " << flag << "\n";
        return false;
      }
    }
  }
  for (const std::string& key : options->methods) {
    const auto& methods = bench::all_methods();
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

std::vector<MeshCase> mesh_cases(const std::vector<fs::path>& corpus, const Options& options) {
  std::vector<MeshCase> cases;
  for (const fs::path& path : corpus) {
    const std::string name = path.stem().string();
    if (!wanted(options.meshes, name)) continue;
    if (name != options.scaling_mesh && !options.scale_all) {
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
  return cases;
}

//! Why a (mesh, method, backend) row is not run, or empty. `faces` is the mesh's (from its floor).
std::string skip_reason(const Method& method, RowBackend backend, int faces, const Options& options,
                        const bench::VulkanProbe& vulkan) {
  if (backend == RowBackend::vulkan && !vulkan.available) return "no Vulkan device";
  if (backend == RowBackend::vulkan && vulkan.software && faces > options.software_max_faces) {
    return "software Vulkan device: only up to " + std::to_string(options.software_max_faces) +
           " faces (--software-max-faces)";
  }
  if (method.slow && faces > options.slow_max_faces) {
    return "slow solver: only up to " + std::to_string(options.slow_max_faces) +
           " faces (--slow-max-faces)";
  }
  return {};
}

//! The floor row of one mesh (measured in a child).
Json floor_row(const MeshCase& mesh_case, const Options& options) {
  Json floor = bench::run_in_child(
      [&] { return bench::measure_floor_child(mesh_case.path, options.repeat); },
      options.timeout_seconds);
  Json row{{"mesh", mesh_case.name},
           {"key", "floor"},
           {"method", "floor"},
           {"variant", "cotangent"},
           {"backend_choice", "cpu"}};
  row.update(floor);
  if (row.value("status", std::string()) == "ok") row["x_floor"] = 1.0;
  return row;
}

void time_reading(const fs::path& disk_dir, const Options& options, Json& results) {
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
    Json row = bench::run_in_child([&] { return bench::measure_reading(*path, options.repeat); },
                                   options.timeout_seconds);
    if (!row.contains("file")) row["file"] = path->filename().string();
    std::cerr << " " << bench::fixed(row.value("seconds", Json()), 3) << " s\n";
    results["reading"].push_back(row);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse_options(argc, argv, &options)) {
    print_usage();
    return 2;
  }
  harmonia::set_blas_thread_policy(options.blas_threads);  // Inherited by every forked child.
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
  const std::vector<MeshCase> cases = mesh_cases(corpus, options);

  bench::VulkanProbe vulkan;
  vulkan.device = "not asked for (--backends cpu)";
  if (std::find(options.backends.begin(), options.backends.end(), RowBackend::vulkan) !=
      options.backends.end()) {
    vulkan = bench::probe_vulkan(options.timeout_seconds);
    std::cerr << (vulkan.available ? "vulkan device: " : "no Vulkan device, no vulkan rows: ")
              << vulkan.device << (vulkan.software ? " (software)" : "") << "\n";
  }

  Json results{{"cpu", cpu_model()},
               {"cores", static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN))},
               {"load_start", load_average()},
               {"repeat", options.repeat},
               {"timeout", options.timeout_seconds},
               {"blas_threads", options.blas_threads == harmonia::BlasThreadPolicy::leave_alone
                                    ? "leave"
                                    : "hold"},
               {"slow_solvers", slow_solver_names()},
               {"slow_max_faces", options.slow_max_faces},
               {"software_max_faces", options.software_max_faces},
               {"vulkan", Json{{"available", vulkan.available},
                               {"device", vulkan.device},
                               {"software", vulkan.software}}},
               {"runs", Json::array()},
               {"reading", Json::array()}};
  std::string largest_mesh;
  int largest_factor = 0;
  for (const MeshCase& mesh_case : cases) {
    // The targets are about the scaling mesh at its largest size run.
    if (mesh_case.name.rfind(options.scaling_mesh, 0) == 0 && mesh_case.factor > largest_factor) {
      largest_factor = mesh_case.factor;
      largest_mesh = mesh_case.name;
    }
    std::cerr << "[" << mesh_case.name << "] floor" << std::flush;
    const Json floor = floor_row(mesh_case, options);
    const double floor_seconds = floor.contains("x_floor") ? floor["seconds"].get<double>() : 0.0;
    const int faces = floor.value("faces", 0);
    results["runs"].push_back(floor);
    std::cerr << " " << bench::fixed(floor.value("seconds", Json()), 3) << " s";

    for (const Method& method : bench::all_methods()) {
      if (!wanted(options.methods, method.key)) continue;
      for (const RowBackend backend : options.backends) {
        // Without a device the vulkan rows are left out altogether (the header says why).
        if (backend == RowBackend::vulkan && !vulkan.available) continue;
        Json row{{"mesh", mesh_case.name},
                 {"key", method.key},
                 {"method", method.method},
                 {"variant", method.variant},
                 {"backend_choice", bench::to_string(backend)},
                 {"faces", faces}};
        const std::string skip = skip_reason(method, backend, faces, options, vulkan);
        if (!skip.empty()) {
          row["status"] = "skipped";
          row["message"] = skip;
          results["runs"].push_back(row);
          continue;
        }
        std::cerr << ", " << method.key << "/" << bench::to_string(backend) << std::flush;
        row.update(bench::run_in_child(
            [&] { return bench::measure_method(mesh_case.path, method, backend, options.repeat); },
            options.timeout_seconds));
        // Only rows that computed a map (ok or not) get a multiple of the floor.
        if (floor_seconds > 0.0 && row.contains("seconds") && row.contains("flips")) {
          row["x_floor"] = row["seconds"].get<double>() / floor_seconds;
        }
        std::cerr << " " << bench::fixed(row.value("seconds", Json()), 3) << " s";
        results["runs"].push_back(row);
      }
    }
    std::cerr << "\n";
  }

  if (options.read_timing) time_reading(disk_dir, options, results);
  results["load_end"] = load_average();
  results["targets"] = bench::targets(results["runs"], results["reading"], largest_mesh);

  const std::string table = bench::markdown(results);
  std::cout << table;
  std::ofstream(options.out_md) << table;
  std::ofstream(options.out_json) << results.dump(2) << "\n";
  return 0;
}
