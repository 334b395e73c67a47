// corpus_atlas_benchmark: the texture atlas (harmonia::texture_atlas, CPU backend) side by side
// with its peer xatlas (github jpcy/xatlas, MIT), built from source in ../shared/tools/xatlas as
// the bench target xatlas_run (bench/CMakeLists.txt; never copied into the project).
//
// Meshes: every closed corpus mesh (../shared/data/closed) at --sizes (default 1 and 16: the base
// mesh and its 16x midpoint subdivision), plus the timing mesh (--time-mesh, default cow) at
// --time-sizes (default 16, 64, 256: 88,320, 353,280 and 1,413,120 faces). Subdivided meshes are
// made once by subdivide.py into the cache of bench_support.h's scaled_mesh.
//
// Per mesh:
//   harmonia  texture_atlas(mesh, {resolution 1024, padding 2, defaults otherwise}) on the CPU,
//             in a forked child (corpus_child.h): wall and CPU time of the call (fastest of
//             --repeat), its per-phase timings (report.timings) and peak resident size; the atlas
//             is written with write_atlas_obj.
//   xatlas    xatlas_run MESH --out ATLAS --target-res 1024 --padding 2 as a subprocess (a
//             process group, killed after --xatlas-timeout s, default 900): its JSON line gives
//             the timings (t_generate = ComputeCharts + PackCharts, wall; cpu_generate: CPU of
//             every thread), charts and the atlas size W x H; --skip-xatlas-above FACES skips the
//             largest meshes.
//   measured  both OBJs read back with the same code (read_textured_obj, the `g chart_<c>[_a<k>]`
//             lines, the `# xatlas_atlas W H N` comment) into a TextureAtlas and measured with
//             detail::measure_atlas, whose definitions are atlaseval.py's, in a child each.
//             xatlas's atlas is W x H, not square: it is measured in a square of R = max(W, H)
//             texels with its UVs scaled by (W / R, H / R), so that every texel keeps its
//             position; "coverage (W x H)" is atlaseval's (covered texels / W H) and "coverage
//             (square)" covered texels / R^2, the fair comparison with a square atlas.
//   atlaseval on the base meshes only (it is slow on big ones), python3 atlaseval.py MESH ATLAS
//             for both atlases as an independent check: whether its figures agree with ours.
//
// Then the batch over the closed corpus: `harmonia batch DIR --out OUT -j 1` and `-j 2` (wall
// time, fastest of --repeat), when the harmonia program has a working batch command; otherwise a
// row says it was not run.
//
// Output: a markdown report (stdout and --out-md) and a JSON file (--out-json). See
// bench/README.md.

#include <poll.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "atlas/atlas_metrics.h"
#include "bench/bench_support.h"
#include "bench/corpus_child.h"
#include "bench/corpus_methods.h"
#include "bench/corpus_report.h"
#include "harmonia/atlas_io.h"
#include "harmonia/blas_threads.h"
#include "harmonia/io.h"
#include "harmonia/texture_atlas.h"

#ifndef HARMONIA_XATLAS_RUN
#define HARMONIA_XATLAS_RUN ""
#endif
#ifndef HARMONIA_CLI_PROGRAM
#define HARMONIA_CLI_PROGRAM ""
#endif

namespace {

namespace fs = std::filesystem;
namespace bench = harmonia::bench;
using bench::Json;

// ---------------------------------------------------------------------------------------------
// Options

constexpr int kResolution = 1024;  // Both atlases: 1024 x 1024 texels (xatlas: that budget).
constexpr int kPadding = 2;

// The targets.
constexpr double kCoverageAim = 0.70;
constexpr double kChartGrowthLimit = 2.0;  // charts at 16x <= 2 x charts of the base mesh.
constexpr int kChartGrowthFactor = 16;
constexpr double kAssetChartsLimit = 1.25;  // an asset's charts <= 1.25 x xatlas's.
constexpr double kTimeShareOfXatlas = 0.2;  // ours <= 1/5 of xatlas's time.
constexpr double kBatchSpeedup = 1.6;       // -j2 at least 1.6x faster than -j1.
// Time aims on the timing mesh: factor -> seconds (2-core machine).
const std::map<int, double>& time_aims() {
  static const std::map<int, double> aims{{16, 3.0}, {64, 12.0}};
  return aims;
}
constexpr int kFinishedFactor = 256;  // "the 1.4M-face case finished".

struct Options {
  std::string set = "closed";                    // closed, assets or all (see print_usage).
  std::vector<int> sizes{1, 16};                 // Size factors of every closed mesh.
  std::vector<std::string> meshes;               // Closed corpus names to run (empty: all).
  std::string time_mesh = "cow";                 // The timing mesh ...
  std::vector<int> time_sizes{16, 64, 256};      // ... at these factors.
  fs::path xatlas = HARMONIA_XATLAS_RUN;         // The peer's driver ("" or absent: no peer).
  int xatlas_timeout_seconds = 900;              // Per xatlas run.
  long skip_xatlas_above = 0;                    // Faces; 0: never skip.
  bool atlaseval = true;                         // The independent check on the base meshes.
  fs::path harmonia_program = HARMONIA_CLI_PROGRAM;  // For the batch rows.
  bool batch = true;
  bool join_charts = false;  // TextureAtlasOptions::join_charts for harmonia's atlases.
  int batch_repeat = 0;  // Runs of each batch row (0: --repeat).
  fs::path keep_atlases;  // Where to keep the atlas OBJs (empty: a temporary folder, removed).
  bench::CorpusRunOptions run{.repeat = 1,
                              .out_md = "atlas-bench-results.md",
                              .out_json = "atlas-bench-results.json"};
};

void print_usage() {
  std::cout
      << "usage: corpus_atlas_benchmark [--set closed|assets|all] [--sizes 1,16] [--meshes a,b]\n"
         "                              [--time-mesh cow]\n"
         "                              [--time-sizes 16,64,256] [--xatlas PATH]\n"
         "                              [--xatlas-timeout S] [--skip-xatlas-above FACES]\n"
         "                              [--no-atlaseval] [--harmonia PATH] [--no-batch]\n"
         "                              [--join-charts]\n"
         "                              [--batch-repeat N]\n"
         "                              [--keep-atlases DIR] [--repeat N] [--timeout S]\n"
         "                              [--out-md FILE] [--out-json FILE]\n"
         "                              [--blas-threads hold|leave]\n"
         "harmonia::texture_atlas (1024 x 1024, padding 2, CPU) next to xatlas (xatlas_run\n"
         "--target-res 1024 --padding 2) on every closed corpus mesh at --sizes and on the\n"
         "timing mesh at --time-sizes; both atlases measured with the same code (atlaseval.py's\n"
         "definitions), atlaseval.py itself run on the base meshes' atlases; then `harmonia\n"
         "batch` over the closed corpus at -j 1 and -j 2. Timings: fastest of --repeat runs\n"
         "(default 1); --timeout caps each harmonia child (default 900 s), --xatlas-timeout\n"
         "each xatlas run (default 900 s). --set assets runs instead the real assets: every OBJ\n"
         "of ../shared/data/assets (game assets, vertices split at their seams) and every file\n"
         "of ../shared/data/wild that holds a surface (read by harmonia, written as OBJ for\n"
         "both), with their own targets (charts <= 1.25 x xatlas's, coverage and L2 at least as\n"
         "good, the whole set in no more time); --set all runs both.\n";
}

std::optional<std::vector<int>> size_factors(const std::string& flag, const std::string& value) {
  std::vector<int> sizes;
  for (const std::string& item : bench::comma_separated(value)) {
    const int size = std::atoi(item.c_str());
    if (size <= 0 || bench::subdivision_steps(size) < 0) {
      std::cerr << "corpus_atlas_benchmark: " << flag << ": " << item
                << " is not a power of 4\n";
      return std::nullopt;
    }
    sizes.push_back(size);
  }
  return sizes;
}

std::optional<Options> parse_options(int argc, char** argv) {
  Options options;
  const std::vector<std::string> arguments(argv + 1, argv + argc);
  for (std::size_t index = 0; index < arguments.size(); ++index) {
    const std::string& flag = arguments[index];
    if (flag == "--help" || flag == "-h") {
      print_usage();
      std::exit(0);
    } else if (flag == "--no-atlaseval") {
      options.atlaseval = false;
    } else if (flag == "--no-batch") {
      options.batch = false;
    } else if (flag == "--join-charts") {
      options.join_charts = true;
    } else if (index + 1 == arguments.size()) {
      std::cerr << "corpus_atlas_benchmark: " << flag << " needs a value (or is unknown)\n";
      return std::nullopt;
      // Every flag from here on takes the next argument as its value.
    } else if (const std::string& value = arguments[++index]; flag == "--set") {
      if (value != "closed" && value != "assets" && value != "all") {
        std::cerr << "corpus_atlas_benchmark: --set takes closed, assets or all\n";
        return std::nullopt;
      }
      options.set = value;
    } else if (flag == "--sizes") {
      const auto sizes = size_factors(flag, value);
      if (!sizes) return std::nullopt;
      options.sizes = *sizes;
    } else if (flag == "--time-sizes") {
      const auto sizes = size_factors(flag, value);
      if (!sizes) return std::nullopt;
      options.time_sizes = *sizes;
    } else if (flag == "--meshes") {
      options.meshes = bench::comma_separated(value);
    } else if (flag == "--time-mesh") {
      options.time_mesh = value;
    } else if (flag == "--xatlas") {
      options.xatlas = value;
    } else if (flag == "--xatlas-timeout") {
      options.xatlas_timeout_seconds = std::max(1, std::stoi(value));
    } else if (flag == "--skip-xatlas-above") {
      options.skip_xatlas_above = std::max(0L, std::stol(value));
    } else if (flag == "--harmonia") {
      options.harmonia_program = value;
    } else if (flag == "--batch-repeat") {
      options.batch_repeat = std::max(1, std::stoi(value));
    } else if (flag == "--keep-atlases") {
      options.keep_atlases = value;
    } else if (!bench::parse_corpus_run_option(flag, value, &options.run)) {
      std::cerr << "corpus_atlas_benchmark: unknown option " << flag << " " << value << "\n";
      return std::nullopt;
    }
  }
  return options;
}

// ---------------------------------------------------------------------------------------------
// The meshes

struct MeshCase {
  std::string name;  // e.g. "cow-x16".
  std::string base;  // The corpus mesh it was made from, e.g. "cow".
  fs::path path;
  int factor = 1;
  long faces = 0;
  bool quality = false;  // A closed mesh at one of --sizes: the quality targets apply.
  bool timing = false;   // The timing mesh at one of --time-sizes.
  bool asset = false;    // A real asset (--set assets): the assets' targets apply.
};

bool contains(const std::vector<int>& list, int value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

//! Faces of an OBJ file: its `f` lines (the corpus and subdivide.py write triangles).
long count_faces(const fs::path& path) {
  std::ifstream file(path);
  long faces = 0;
  for (std::string line; std::getline(file, line);) {
    if (line.size() > 1 && line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) ++faces;
  }
  return faces;
}

//! The real assets: every OBJ of ../shared/data/assets as it is, and every file of
//! ../shared/data/wild that harmonia reads to a mesh with faces, written as OBJ into `folder`
//! (xatlas_run reads OBJ only), smallest first.
std::vector<MeshCase> asset_cases(const fs::path& folder) {
  std::vector<MeshCase> cases;
  std::error_code error;
  std::vector<fs::path> assets;
  for (const auto& entry : fs::directory_iterator(bench::shared_data_dir() / "assets", error))
    if (entry.path().extension() == ".obj") assets.push_back(entry.path());
  std::sort(assets.begin(), assets.end());
  for (const fs::path& path : assets) {
    MeshCase mesh_case{"assets/" + path.stem().string(), path.stem().string(), path, 1};
    mesh_case.faces = count_faces(path);
    mesh_case.asset = true;
    cases.push_back(mesh_case);
  }
  std::vector<fs::path> wild;
  for (const auto& entry : fs::directory_iterator(bench::shared_data_dir() / "wild", error))
    if (entry.is_regular_file() && entry.path().extension() != ".md") wild.push_back(entry.path());
  std::sort(wild.begin(), wild.end());
  fs::create_directories(folder, error);
  for (const fs::path& path : wild) {
    try {
      const harmonia::Mesh mesh = harmonia::read_mesh(path);
      const fs::path obj = folder / (path.filename().string() + ".obj");
      harmonia::write_mesh(obj, mesh);
      MeshCase mesh_case{"wild/" + path.filename().string(), path.filename().string(), obj, 1};
      mesh_case.faces = mesh.face_count();
      mesh_case.asset = true;
      cases.push_back(mesh_case);
    } catch (const harmonia::Error&) {
      // No surface in it (empty, points, lines): refused by every command, not an atlas case.
    }
  }
  std::stable_sort(cases.begin(), cases.end(),
                   [](const MeshCase& a, const MeshCase& b) { return a.faces < b.faces; });
  return cases;
}

//! Every closed mesh at --sizes and the timing mesh at --time-sizes, each once, smallest first.
std::vector<MeshCase> mesh_cases(const std::vector<fs::path>& corpus, const Options& options) {
  std::vector<MeshCase> cases;
  for (const fs::path& path : corpus) {
    const std::string name = path.stem().string();
    const bool listed = options.meshes.empty() || std::find(options.meshes.begin(),
                                                            options.meshes.end(),
                                                            name) != options.meshes.end();
    std::vector<int> factors;
    if (listed) factors = options.sizes;
    if (name == options.time_mesh) {
      for (const int factor : options.time_sizes) {
        if (!contains(factors, factor)) factors.push_back(factor);
      }
    }
    for (const int factor : factors) {
      std::string message;
      const auto scaled = bench::scaled_mesh(path, factor, &message);
      if (!scaled) {
        std::cerr << "corpus_atlas_benchmark: " << message << "\n";
        continue;
      }
      MeshCase mesh_case{factor == 1 ? name : name + "-x" + std::to_string(factor), name, *scaled,
                         factor};
      mesh_case.faces = count_faces(*scaled);
      mesh_case.quality = listed && contains(options.sizes, factor);
      mesh_case.timing = name == options.time_mesh && contains(options.time_sizes, factor);
      cases.push_back(mesh_case);
    }
  }
  std::stable_sort(cases.begin(), cases.end(), [](const MeshCase& a, const MeshCase& b) {
    return a.factor != b.factor ? a.factor < b.factor : a.name < b.name;
  });
  return cases;
}

// ---------------------------------------------------------------------------------------------
// Subprocesses (xatlas_run, atlaseval.py, harmonia batch)

struct ProcessRun {
  bool started = false;
  bool timed_out = false;
  int exit_code = -1;        // The exit status, or -1 when killed by a signal.
  std::string signal_name;   // The signal that ended it, if one did.
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;  // User + system time of the process and its waited-for children.
  double peak_MB = -1.0;     // Its peak resident size (ru_maxrss).
  std::string out;
  std::string err;
};

//! The process group of the subprocess running now (0: none), for the signal handler below.
volatile sig_atomic_t running_group = 0;

//! SIGINT / SIGTERM / SIGHUP: the subprocess runs in its own process group, out of reach of a
//! signal sent to ours, so it is killed here (an xatlas run may otherwise go on for half an
//! hour); then the signal ends this program as it would have.
extern "C" void kill_running_group_and_exit(int signal_number) {
  if (running_group > 0) ::kill(-static_cast<pid_t>(running_group), SIGKILL);
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

//! Runs `arguments` (argv[0] found on PATH) in a process group of its own, capturing stdout and
//! stderr; the group is killed (SIGKILL) when it runs past `timeout_seconds`.
ProcessRun run_process(const std::vector<std::string>& arguments, int timeout_seconds) {
  ProcessRun run;
  int out_pipe[2];
  int err_pipe[2];
  if (::pipe(out_pipe) != 0) return run;
  if (::pipe(err_pipe) != 0) {
    ::close(out_pipe[0]);
    ::close(out_pipe[1]);
    return run;
  }
  std::vector<char*> argv;
  for (const std::string& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  std::cout.flush();
  std::cerr.flush();
  const double start = steady_seconds();
  const double deadline = start + timeout_seconds;
  const pid_t child = ::fork();
  if (child < 0) {
    for (const int fd : {out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1]}) ::close(fd);
    return run;
  }
  if (child == 0) {
    ::setpgid(0, 0);
    ::dup2(out_pipe[1], STDOUT_FILENO);
    ::dup2(err_pipe[1], STDERR_FILENO);
    for (const int fd : {out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1]}) ::close(fd);
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  ::setpgid(child, child);  // Also in the parent, so the group exists before any kill.
  running_group = child;
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  run.started = true;
  const auto kill_group = [&] {
    if (!run.timed_out) {
      ::kill(-child, SIGKILL);
      run.timed_out = true;
    }
  };
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&run.out, &run.err};
  int open = 2;
  char buffer[65536];
  while (open > 0) {
    int wait_ms = -1;
    if (!run.timed_out) {
      const double remaining = deadline - steady_seconds();
      if (remaining <= 0.0) {
        kill_group();
        continue;
      }
      wait_ms = static_cast<int>(std::min(remaining * 1000.0 + 1.0, static_cast<double>(INT_MAX)));
    }
    const int ready = ::poll(fds, 2, wait_ms);
    if (ready < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int k = 0; k < 2; ++k) {
      if (fds[k].fd < 0 || (fds[k].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
      const ssize_t got = ::read(fds[k].fd, buffer, sizeof buffer);
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) {
        ::close(fds[k].fd);
        fds[k].fd = -1;
        --open;
      } else {
        sinks[k]->append(buffer, static_cast<std::size_t>(got));
      }
    }
  }
  for (pollfd& fd : fds) {
    if (fd.fd >= 0) ::close(fd.fd);
  }
  // Its output is closed; it may still be running (or have left its output to a grandchild).
  int status = 0;
  rusage usage{};
  for (;;) {
    const pid_t done = ::wait4(child, &status, WNOHANG, &usage);
    if (done == child) break;
    if (done < 0 && errno != EINTR) break;
    if (steady_seconds() > deadline) kill_group();
    ::usleep(10000);
  }
  running_group = 0;
  run.wall_seconds = steady_seconds() - start;
  run.cpu_seconds = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                    1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  run.peak_MB = static_cast<double>(usage.ru_maxrss) / 1024.0;
  if (WIFEXITED(status)) {
    run.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    run.signal_name = ::strsignal(WTERMSIG(status));
  }
  return run;
}

//! The last line of `text` that parses as a JSON object; null when none does.
Json last_json_line(const std::string& text) {
  std::istringstream stream(text);
  Json found;
  for (std::string line; std::getline(stream, line);) {
    if (line.empty() || line[0] != '{') continue;
    try {
      found = Json::parse(line);
    } catch (const std::exception&) {
    }
  }
  return found;
}

//! The last `characters` of `text` on one line, for a message.
std::string tail_text(const std::string& text, std::size_t characters = 300) {
  std::string tail = text.size() > characters ? text.substr(text.size() - characters) : text;
  std::replace(tail.begin(), tail.end(), '\n', ' ');
  std::replace(tail.begin(), tail.end(), '|', '/');
  while (!tail.empty() && tail.back() == ' ') tail.pop_back();
  return tail;
}

//! What went wrong with a process that did not exit 0.
std::string failure_text(const ProcessRun& run) {
  if (!run.started) return "could not start";
  if (run.exit_code == 127) return "could not run (exit 127)";
  if (!run.signal_name.empty()) return "killed by " + run.signal_name + ": " + tail_text(run.err);
  return "exit " + std::to_string(run.exit_code) + ": " + tail_text(run.err);
}

bool is_executable(const fs::path& path) {
  return !path.empty() && ::access(path.c_str(), X_OK) == 0 && fs::is_regular_file(path);
}

// ---------------------------------------------------------------------------------------------
// Reading an atlas OBJ back and measuring it (both atlases, the same code)

double process_cpu_seconds() {
  timespec now{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

//! What read_textured_obj leaves out: the chart of each face from the `g chart_<c>[_a<k>]` lines
//! (before the first one: chart -1), the atlas of each face, and the `# xatlas_atlas W H N` size.
struct AtlasGroups {
  std::vector<int> chart_of_face;
  std::vector<int> atlas_of_face;
  int width = 0;
  int height = 0;
  int atlas_count = 0;
};

AtlasGroups read_atlas_groups(const fs::path& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error("cannot open " + path.string());
  AtlasGroups groups;
  int chart = -1;
  int atlas = 0;
  for (std::string line; std::getline(file, line);) {
    if (line.size() < 2) continue;
    if (line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) {
      groups.chart_of_face.push_back(chart);
      groups.atlas_of_face.push_back(atlas);
    } else if (line[0] == 'g' && line[1] == ' ') {
      std::istringstream words(line.substr(2));
      std::string name;
      words >> name;
      if (name.rfind("chart_", 0) != 0) continue;
      const std::string rest = name.substr(6);
      const std::size_t split = rest.find("_a");
      chart = std::stoi(rest.substr(0, split));
      atlas = split == std::string::npos ? 0 : std::stoi(rest.substr(split + 2));
    } else if (line.rfind("# xatlas_atlas", 0) == 0) {
      std::istringstream words(line.substr(14));
      words >> groups.width >> groups.height >> groups.atlas_count;
    }
  }
  return groups;
}

//! Child body: reads `mesh_path` (the positions, as atlaseval.py takes them) and the atlas OBJ at
//! `atlas_path` (faces, UVs, charts, size), builds a TextureAtlas in a square of max(W, H) texels
//! (UVs scaled so every texel keeps its place) and measures it with detail::measure_atlas.
Json measure_atlas_child(const fs::path& mesh_path, const fs::path& atlas_path) {
  const harmonia::Mesh input = harmonia::read_mesh(mesh_path);
  const harmonia::TexturedMesh textured = harmonia::read_textured_obj(atlas_path);
  const AtlasGroups groups = read_atlas_groups(atlas_path);
  const int faces = textured.mesh.face_count();
  if (static_cast<int>(groups.chart_of_face.size()) != faces) {
    return Json{{"status", "failed"},
                {"message", "the atlas has " + std::to_string(groups.chart_of_face.size()) +
                                " f lines but " + std::to_string(faces) + " triangles"}};
  }
  if (faces != input.face_count() || textured.mesh.vertex_count() != input.vertex_count()) {
    return Json{{"status", "failed"},
                {"message", "the atlas' vertices / faces (" +
                                std::to_string(textured.mesh.vertex_count()) + " / " +
                                std::to_string(faces) + ") differ from the mesh's"}};
  }
  int face_index_mismatch = 0;
  for (int f = 0; f < faces; ++f) {
    if (textured.mesh.faces.row(f) != input.faces.row(f)) ++face_index_mismatch;
  }
  const int width = groups.width > 0 ? groups.width : kResolution;
  const int height = groups.height > 0 ? groups.height : kResolution;
  const int side = std::max(width, height);
  std::set<int> atlases;
  for (int f = 0; f < faces; ++f) {
    if (groups.chart_of_face[static_cast<std::size_t>(f)] >= 0)
      atlases.insert(groups.atlas_of_face[static_cast<std::size_t>(f)]);
  }

  // Positions from the mesh, faces from the atlas (atlaseval.py's reading).
  const harmonia::Mesh mesh{input.vertices, textured.mesh.faces};
  harmonia::TextureAtlas atlas;
  atlas.resolution = side;
  atlas.chart_of_face.assign(static_cast<std::size_t>(faces), -1);
  atlas.corner_uv.resize(faces, 6);
  std::map<int, int> compact;  // File chart id -> 0..charts-1, in order of first use.
  const double scale_u = static_cast<double>(width) / side;
  const double scale_v = static_cast<double>(height) / side;
  for (int f = 0; f < faces; ++f) {
    const int file_chart = groups.chart_of_face[static_cast<std::size_t>(f)];
    if (file_chart >= 0) {
      const auto [slot, fresh] = compact.try_emplace(file_chart, static_cast<int>(compact.size()));
      if (fresh) atlas.charts.emplace_back();
      atlas.charts[static_cast<std::size_t>(slot->second)].faces.push_back(f);
      atlas.chart_of_face[static_cast<std::size_t>(f)] = slot->second;
    }
    for (int k = 0; k < 3; ++k) {
      const int row = textured.uv_faces(f, k);
      atlas.corner_uv(f, 2 * k) = textured.uv(row, 0) * scale_u;
      atlas.corner_uv(f, 2 * k + 1) = textured.uv(row, 1) * scale_v;
    }
  }
  bench::Stopwatch measuring;
  const harmonia::AtlasMetrics metrics = harmonia::detail::measure_atlas(mesh, atlas);
  const double measure_seconds = measuring.seconds();
  int single_face_charts = 0;
  for (const harmonia::AtlasChart& chart : atlas.charts) {
    if (chart.faces.size() == 1) ++single_face_charts;
  }
  const double covered = metrics.coverage * static_cast<double>(side) * side;
  return Json{{"status", "ok"},
              {"faces", faces},
              {"width", width},
              {"height", height},
              {"square", side},
              {"atlas_count", groups.atlas_count},
              {"atlases_used", static_cast<int>(atlases.size())},
              {"face_index_mismatch", face_index_mismatch},
              {"charts", metrics.charts},
              {"single_face_charts", single_face_charts},
              {"covered_texels", std::llround(covered)},
              {"coverage", covered / (static_cast<double>(width) * height)},
              {"coverage_square", metrics.coverage},
              {"l2_stretch", metrics.l2_stretch},
              {"angle_distortion", metrics.angle_distortion},
              {"area_distortion", metrics.area_distortion},
              {"texels_per_unit", metrics.texels_per_unit},
              {"flips", metrics.flipped_triangles},
              {"mirrored", metrics.mirrored_charts},
              {"overlaps", metrics.overlapping_texels},
              {"crossings", metrics.boundary_crossings},
              {"dropped", metrics.dropped_faces},
              {"measure_seconds", measure_seconds}};
}

// ---------------------------------------------------------------------------------------------
// harmonia's atlas

//! Child body: reads the mesh, times `repeat` calls of texture_atlas (1024, padding 2, CPU; the
//! fastest wall time counts), reads the peak resident size, writes the fastest call's atlas.
Json harmonia_child(const fs::path& mesh_path, const fs::path& atlas_path, int repeat, bool join_charts) {
  bench::Stopwatch reading;
  const harmonia::Mesh mesh = harmonia::read_mesh(mesh_path);
  const double read_seconds = reading.seconds();
  harmonia::TextureAtlasOptions options;
  options.resolution = kResolution;
  options.padding = kPadding;
  options.solver.backend = harmonia::BackendChoice::cpu;
  options.join_charts = join_charts;

  const double resident_before = bench::process_status_megabytes("VmRSS");
  const bool peak_reset = bench::reset_peak_resident_size();
  harmonia::TextureAtlas best;
  double best_seconds = std::numeric_limits<double>::infinity();
  double best_cpu_seconds = 0.0;
  for (int run = 0; run < repeat; ++run) {
    const double cpu_start = process_cpu_seconds();
    bench::Stopwatch stopwatch;
    harmonia::TextureAtlas atlas = harmonia::texture_atlas(mesh, options);
    const double seconds = stopwatch.seconds();
    const double cpu_seconds = process_cpu_seconds() - cpu_start;
    if (seconds < best_seconds) {
      best_seconds = seconds;
      best_cpu_seconds = cpu_seconds;
      best = std::move(atlas);
    }
  }
  const double peak = bench::process_status_megabytes("VmHWM");
  const harmonia::SolveReport& report = best.report;
  Json phase_seconds = Json::object();
  for (const harmonia::PhaseTiming& timing : report.timings) {
    phase_seconds[timing.phase] = phase_seconds.value(timing.phase, 0.0) + timing.seconds;
  }
  std::map<std::string, int> methods;
  int single_face_charts = 0;
  for (const harmonia::AtlasChart& chart : best.charts) {
    ++methods[std::string(harmonia::to_string(chart.method))];
    if (chart.faces.size() == 1) ++single_face_charts;
  }
  const harmonia::AtlasMetrics& metrics = best.metrics;
  Json row{{"status", std::string(harmonia::to_string(report.status))},
           {"message", report.message},
           {"faces", mesh.face_count()},
           {"vertices", mesh.vertex_count()},
           {"seconds", best_seconds},
           {"cpu_seconds", best_cpu_seconds},
           {"library_seconds", report.total_seconds()},
           {"read_seconds", read_seconds},
           {"peak_MB", peak},
           {"rss_before_MB", resident_before},
           {"peak_is_per_call", peak_reset},
           {"threads", static_cast<int>(std::thread::hardware_concurrency())},
           {"phase_seconds", phase_seconds},
           {"phases", bench::phases_json(report)},
           {"fallbacks", report.fallbacks},
           {"charts", static_cast<int>(best.charts.size())},
           {"single_face_charts", single_face_charts},
           {"chart_methods", methods},
           // The library's own figures (measure_atlas inside texture_atlas), to compare with
           // the same measure of the OBJ read back.
           {"library_metrics",
            Json{{"coverage", metrics.coverage},
                 {"l2_stretch", metrics.l2_stretch},
                 {"angle_distortion", metrics.angle_distortion},
                 {"area_distortion", metrics.area_distortion},
                 {"texels_per_unit", metrics.texels_per_unit},
                 {"flips", metrics.flipped_triangles},
                 {"mirrored", metrics.mirrored_charts},
                 {"overlaps", metrics.overlapping_texels},
                 {"crossings", metrics.boundary_crossings},
                 {"dropped", metrics.dropped_faces}}}};
  if (report.ok()) {
    bench::Stopwatch writing;
    harmonia::write_atlas_obj(atlas_path, mesh, best);
    row["write_seconds"] = writing.seconds();
    row["atlas_obj"] = atlas_path.string();
  }
  return row;
}

// ---------------------------------------------------------------------------------------------
// xatlas

//! xatlas_run on one mesh, `repeat` times (the fastest t_generate counts), each run capped at
//! --xatlas-timeout.
Json xatlas_row(const MeshCase& mesh_case, const fs::path& atlas_path, const Options& options) {
  if (!is_executable(options.xatlas)) {
    return Json{{"status", "skipped"},
                {"message", "xatlas_run not built" +
                                (options.xatlas.empty() ? std::string()
                                                        : " (" + options.xatlas.string() + ")")}};
  }
  if (options.skip_xatlas_above > 0 && mesh_case.faces > options.skip_xatlas_above) {
    return Json{{"status", "skipped"},
                {"message", "--skip-xatlas-above " + std::to_string(options.skip_xatlas_above)}};
  }
  Json best;
  double best_seconds = std::numeric_limits<double>::infinity();
  for (int run = 0; run < options.run.repeat; ++run) {
    const ProcessRun process =
        run_process({options.xatlas.string(), mesh_case.path.string(), "--out",
                     atlas_path.string(), "--target-res", std::to_string(kResolution), "--padding",
                     std::to_string(kPadding)},
                    options.xatlas_timeout_seconds);
    if (process.timed_out) {
      return Json{{"status", "timeout"},
                  {"message", "timed out after " + std::to_string(options.xatlas_timeout_seconds) +
                                  " s"},
                  {"timeout_seconds", options.xatlas_timeout_seconds},
                  {"process_cpu_seconds", process.cpu_seconds},
                  {"peak_MB", process.peak_MB}};
    }
    const Json line = last_json_line(process.out);
    if (process.exit_code != 0 || !line.is_object() || line.contains("error")) {
      return Json{{"status", "failed"},
                  {"message", line.is_object() && line.contains("error")
                                  ? line["error"].get<std::string>()
                                  : failure_text(process)}};
    }
    const double seconds = line.value("t_generate", std::numeric_limits<double>::infinity());
    if (seconds < best_seconds) {
      best_seconds = seconds;
      best = Json{{"status", "ok"},
                  {"message", ""},
                  {"faces", line.value("F", 0)},
                  {"seconds", line["t_generate"]},
                  {"cpu_seconds", line.value("cpu_generate", Json())},
                  {"t_addmesh", line.value("t_addmesh", Json())},
                  {"t_computecharts", line.value("t_computecharts", Json())},
                  {"t_packcharts", line.value("t_packcharts", Json())},
                  {"cpu_computecharts", line.value("cpu_computecharts", Json())},
                  {"cpu_packcharts", line.value("cpu_packcharts", Json())},
                  {"process_wall_seconds", process.wall_seconds},
                  {"process_cpu_seconds", process.cpu_seconds},
                  {"peak_MB", process.peak_MB},
                  {"threads", line.value("threads", 0)},
                  {"charts", line.value("charts", 0)},
                  {"width", line.value("width", 0)},
                  {"height", line.value("height", 0)},
                  {"atlas_count", line.value("atlas_count", 0)},
                  {"texels_per_unit", line.value("texels_per_unit", Json())},
                  {"utilization", line.value("utilization", Json::array())},
                  {"unassigned_faces", line.value("unassigned_faces", 0)},
                  {"atlas_obj", atlas_path.string()},
                  {"xatlas_json", line}};
    }
  }
  return best;
}

// ---------------------------------------------------------------------------------------------
// atlaseval.py, the independent check

struct Figure {
  const char* ours;         // Field of the measured row.
  const char* eval;         // Path in atlaseval.py's JSON ("a/b").
  bool exact;               // A count: must be equal; else within kEvalTolerance (relative).
};
constexpr double kEvalTolerance = 2e-5;  // atlaseval prints 6 significant digits.

const std::vector<Figure>& compared_figures() {
  static const std::vector<Figure> figures{
      {"charts", "charts", true},
      {"single_face_charts", "chart_faces/single_face_charts", true},
      {"flips", "flipped", true},
      {"mirrored", "mirrored_charts", true},
      {"overlaps", "overlap_texels", true},
      {"crossings", "boundary_crossings", true},  // between_charts + within_chart
      {"dropped", "unassigned_faces", true},
      {"coverage", "coverage", false},
      {"l2_stretch", "stretch/L2", false},
      {"angle_distortion", "conformal/mean", false},
      {"area_distortion", "area_global/mean_abs_log", false},
  };
  return figures;
}

Json eval_value(const Json& eval, const std::string& path) {
  if (path == "boundary_crossings") {
    const Json& crossings = eval.value("boundary_crossings", Json::object());
    if (!crossings.contains("between_charts")) return Json();
    return crossings["between_charts"].get<long>() + crossings["within_chart"].get<long>();
  }
  const Json* node = &eval;
  std::istringstream parts(path);
  for (std::string part; std::getline(parts, part, '/');) {
    if (!node->is_object() || !node->contains(part)) return Json();
    node = &(*node)[part];
  }
  return *node;
}

//! Runs atlaseval.py on the atlas of `row` and compares its figures with the measured ones.
Json atlaseval_check(const MeshCase& mesh_case, const Json& measured, const fs::path& atlas_path,
                     const Options& options) {
  const fs::path tool = bench::shared_tools_dir() / "atlaseval.py";
  if (!fs::exists(tool)) {
    return Json{{"status", "skipped"}, {"message", tool.string() + " does not exist"}};
  }
  const ProcessRun process = run_process(
      {"python3", tool.string(), mesh_case.path.string(), atlas_path.string()},
      options.run.timeout_seconds);
  if (process.timed_out) {
    return Json{{"status", "timeout"},
                {"message", "atlaseval.py timed out after " +
                                std::to_string(options.run.timeout_seconds) + " s"}};
  }
  const Json eval = last_json_line(process.out);
  if (process.exit_code != 0 || !eval.is_object() || eval.contains("error")) {
    return Json{{"status", "failed"},
                {"message", eval.is_object() && eval.contains("error")
                                ? "atlaseval.py: " + eval["error"].get<std::string>()
                                : "atlaseval.py " + failure_text(process)}};
  }
  Json differences = Json::array();
  Json figures = Json::object();
  for (const Figure& figure : compared_figures()) {
    const Json ours = measured.value(figure.ours, Json());
    const Json theirs = eval_value(eval, figure.eval);
    figures[figure.ours] = Json{{"ours", ours}, {"atlaseval", theirs}};
    bool agree = ours.is_number() && theirs.is_number();
    if (agree) {
      const double a = ours.get<double>();
      const double b = theirs.get<double>();
      agree = figure.exact ? a == b
                           : std::abs(a - b) <= kEvalTolerance * std::max(1.0, std::abs(b));
    }
    if (!agree) {
      differences.push_back(std::string(figure.ours) + " " + ours.dump() + " vs " +
                            theirs.dump());
    }
  }
  return Json{{"status", "ok"},
              {"agree", differences.empty()},
              {"differences", differences},
              {"figures", figures},
              {"valid", eval.value("valid", false)},
              {"atlas_size", eval.value("atlas_size", Json())},
              {"seconds", process.wall_seconds}};
}

// ---------------------------------------------------------------------------------------------
// One mesh

Json mesh_row(const MeshCase& mesh_case, const fs::path& folder, const Options& options) {
  const fs::path ours_obj = folder / (mesh_case.name + ".harmonia.obj");
  const fs::path peer_obj = folder / (mesh_case.name + ".xatlas.obj");
  std::error_code folder_error;
  fs::create_directories(ours_obj.parent_path(), folder_error);  // "assets/Duck": a subfolder
  const int timeout = options.run.timeout_seconds;
  const int repeat = options.run.repeat;
  Json row{{"mesh", mesh_case.name},      {"base", mesh_case.base},
           {"factor", mesh_case.factor},  {"faces", mesh_case.faces},
           {"quality", mesh_case.quality}, {"timing", mesh_case.timing},
           {"asset", mesh_case.asset}};

  std::cerr << "[" << mesh_case.name << ", " << mesh_case.faces << " faces] harmonia"
            << std::flush;
  Json ours = bench::run_in_child(
      [&] { return harmonia_child(mesh_case.path, ours_obj, repeat, options.join_charts); }, timeout);
  std::cerr << " " << bench::fixed(ours.value("seconds", Json()), 3) << " s ("
            << ours["status"].get<std::string>() << "), xatlas" << std::flush;
  Json peer = xatlas_row(mesh_case, peer_obj, options);
  std::cerr << " " << bench::fixed(peer.value("seconds", Json()), 3) << " s ("
            << peer["status"].get<std::string>() << ")" << std::flush;

  for (auto [tool, obj] : {std::pair<Json*, fs::path>{&ours, ours_obj}, {&peer, peer_obj}}) {
    if ((*tool)["status"] != "ok" || !fs::exists(obj)) continue;
    std::cerr << ", measure" << std::flush;
    (*tool)["measured"] =
        bench::run_in_child([&] { return measure_atlas_child(mesh_case.path, obj); }, timeout);
    if (options.atlaseval && mesh_case.factor == 1 && (*tool)["measured"]["status"] == "ok") {
      std::cerr << ", atlaseval" << std::flush;
      (*tool)["atlaseval"] = atlaseval_check(mesh_case, (*tool)["measured"], obj, options);
    }
  }
  // The library's own figures against the same measure of its OBJ read back.
  if (ours.contains("measured") && ours["measured"]["status"] == "ok") {
    Json differences = Json::array();
    for (const auto& [field, value] : ours["library_metrics"].items()) {
      if (field == "texels_per_unit") continue;  // The library stores the packing's density.
      const Json read_back =
          ours["measured"].value(field == "coverage" ? "coverage_square" : field, Json());
      if (!read_back.is_number() ||
          std::abs(read_back.get<double>() - value.get<double>()) >
              1e-9 * std::max(1.0, std::abs(value.get<double>()))) {
        differences.push_back(field + " " + value.dump() + " vs " + read_back.dump());
      }
    }
    ours["library_vs_obj_differences"] = differences;
  }
  std::cerr << "\n";
  if (options.keep_atlases.empty()) {
    std::error_code error;
    fs::remove(ours_obj, error);
    fs::remove(peer_obj, error);
  }
  row["harmonia"] = ours;
  row["xatlas"] = peer;
  return row;
}

// ---------------------------------------------------------------------------------------------
// The batch over the closed corpus

Json batch_rows(const fs::path& closed_dir, const fs::path& scratch, const Options& options) {
  Json result{{"status", "not_run"}, {"runs", Json::array()}};
  const fs::path program = options.harmonia_program;
  if (!is_executable(program)) {
    result["message"] = "not run: batch command not built (no harmonia program" +
                        (program.empty() ? std::string() : " at " + program.string()) + ")";
    return result;
  }
  const ProcessRun probe = run_process({program.string(), "batch", "--help"}, 60);
  if (probe.exit_code != 0) {
    result["message"] = "not run: batch command not built (`" + program.filename().string() +
                        " batch --help`: " + failure_text(probe) + ")";
    return result;
  }
  std::map<int, double> fastest;
  for (const int jobs : {1, 2}) {
    Json run_row{{"jobs", jobs}, {"seconds", Json()}, {"status", "ok"}, {"message", ""}};
    double best = std::numeric_limits<double>::infinity();
    const int repeat = options.batch_repeat > 0 ? options.batch_repeat : options.run.repeat;
    for (int run = 0; run < repeat; ++run) {
      const fs::path out = scratch / ("batch-j" + std::to_string(jobs) + "-" + std::to_string(run));
      std::error_code error;
      fs::remove_all(out, error);
      std::cerr << "[batch -j " << jobs << "]" << std::flush;
      const ProcessRun process =
          run_process({program.string(), "batch", closed_dir.string(), "--out", out.string(), "-j",
                       std::to_string(jobs)},
                      options.run.timeout_seconds);
      fs::remove_all(out, error);
      std::cerr << " " << bench::fixed(Json(process.wall_seconds), 3) << " s\n";
      if (process.timed_out || process.exit_code != 0) {
        run_row["status"] = process.timed_out ? "timeout" : "failed";
        run_row["message"] = process.timed_out ? "timed out after " +
                                                     std::to_string(options.run.timeout_seconds) +
                                                     " s"
                                               : failure_text(process);
        break;
      }
      best = std::min(best, process.wall_seconds);
      run_row["cpu_seconds"] = process.cpu_seconds;
    }
    if (run_row["status"] == "ok") {
      run_row["seconds"] = best;
      fastest[jobs] = best;
    }
    result["runs"].push_back(run_row);
  }
  result["repeat"] = options.batch_repeat > 0 ? options.batch_repeat : options.run.repeat;
  result["command"] = program.string() + " batch " + closed_dir.string() + " --out DIR -j N";
  if (fastest.size() == 2) {
    result["status"] = "ok";
    result["message"] = "";
    result["speedup"] = fastest[1] / fastest[2];
  } else {
    result["status"] = "failed";
    result["message"] = "a batch run did not finish";
  }
  return result;
}

// ---------------------------------------------------------------------------------------------
// Targets

//! `met` is null when the run has no row the target is about.
void add_target(Json& list, const std::string& name, const std::string& measured,
                const std::string& limit, const Json& met, const std::string& note = {}) {
  list.push_back(Json{
      {"target", name}, {"measured", measured}, {"limit", limit}, {"met", met}, {"note", note}});
}

void append_item(std::string& text, const std::string& item, const char* separator = ", ") {
  if (!text.empty()) text += separator;
  text += item;
}

const Json& measured_of(const Json& tool) {
  static const Json none = Json::object();
  return tool.contains("measured") && tool["measured"]["status"] == "ok" ? tool["measured"] : none;
}

const Json* find_row(const Json& rows, const std::string& base, int factor) {
  for (const Json& row : rows) {
    if (row["base"] == base && row["factor"] == factor) return &row;
  }
  return nullptr;
}

//! `scope`: which meshes the quality targets cover, e.g. "every closed mesh, x1 and x16".
// Zero defects, coverage of the square atlas at least xatlas's (and, with `coverage_aim`, the
// aim), Sander L2 stretch at most xatlas's: on the rows `in_scope` takes, described as `scope`.
void quality_targets(Json& list, const Json& rows, const std::function<bool(const Json&)>& in_scope,
                     const std::string& scope, bool coverage_aim) {
  // Zero defects.
  const std::vector<std::pair<const char*, const char*>> defects{
      {"flips", "flips"},
      {"overlaps", "overlapping texels"},
      {"crossings", "chart boundary crossings"},
      {"dropped", "dropped faces"},
      {"mirrored", "mirrored charts"}};
  for (const auto& [field, words] : defects) {
    int atlases = 0;
    std::string failing;
    std::string peer_failing;
    for (const Json& row : rows) {
      if (!in_scope(row)) continue;
      ++atlases;
      const Json& ours = measured_of(row["harmonia"]);
      const Json value = ours.value(field, Json());
      if (!value.is_number() || value.get<long>() != 0) {
        append_item(failing, row["mesh"].get<std::string>() + " " +
                                 (value.is_number() ? value.dump()
                                                    : bench::status_text(row["harmonia"])));
      }
      const Json peer = measured_of(row["xatlas"]).value(field, Json());
      if (peer.is_number() && peer.get<long>() != 0) {
        append_item(peer_failing, row["mesh"].get<std::string>() + " " + peer.dump());
      }
    }
    if (atlases == 0) continue;
    add_target(list, std::string("0 ") + words + " (" + scope + ")",
               failing.empty() ? "0 on all " + std::to_string(atlases) : failing, "0",
               failing.empty(), peer_failing.empty() ? "xatlas: 0 everywhere it ran"
                                                     : "xatlas: " + peer_failing);
  }
  // Coverage of the square atlas >= xatlas's, and the aim.
  {
    std::string figures;
    std::string below_aim;
    bool met = true;
    bool any = false;
    double lowest = std::numeric_limits<double>::infinity();
    for (const Json& row : rows) {
      if (!in_scope(row)) continue;
      const Json ours = measured_of(row["harmonia"]).value("coverage_square", Json());
      const Json peer = measured_of(row["xatlas"]).value("coverage_square", Json());
      if (ours.is_number()) {
        lowest = std::min(lowest, ours.get<double>());
        if (ours.get<double>() < kCoverageAim) {
          append_item(below_aim, row["mesh"].get<std::string>() + " " + bench::fixed(ours, 3));
        }
      }
      if (!ours.is_number() || !peer.is_number()) continue;
      any = true;
      if (ours.get<double>() < peer.get<double>()) {
        met = false;
        append_item(figures, row["mesh"].get<std::string>() + " " + bench::fixed(ours, 3) +
                                 " < " + bench::fixed(peer, 3));
      }
    }
    add_target(list, "coverage of the square atlas >= xatlas's (" + scope + ")",
               !any ? "no mesh with both atlases"
               : met ? "at least xatlas's on every mesh"
                     : "below on " + figures,
               ">= xatlas (square of max(W, H))", any ? Json(met) : Json());
    if (coverage_aim)
    add_target(list, "coverage aim (" + scope + ")",
               std::isfinite(lowest) ? "lowest " + bench::fixed(Json(lowest), 3) +
                                           (below_aim.empty() ? "" : "; below: " + below_aim)
                                     : "no atlas",
               ">= " + bench::fixed(Json(kCoverageAim), 2),
               std::isfinite(lowest) ? Json(below_aim.empty()) : Json(), "aim");
  }
  // L2 stretch <= xatlas's.
  {
    std::string figures;
    bool met = true;
    bool any = false;
    for (const Json& row : rows) {
      if (!in_scope(row)) continue;
      const Json ours = measured_of(row["harmonia"]).value("l2_stretch", Json());
      const Json peer = measured_of(row["xatlas"]).value("l2_stretch", Json());
      if (!ours.is_number() || !peer.is_number()) continue;
      any = true;
      if (ours.get<double>() > peer.get<double>()) {
        met = false;
        append_item(figures, row["mesh"].get<std::string>() + " " + bench::fixed(ours, 4) +
                                 " > " + bench::fixed(peer, 4));
      }
    }
    add_target(list, "Sander L2 stretch <= xatlas's (" + scope + ")",
               !any ? "no mesh with both atlases"
               : met ? "at most xatlas's on every mesh"
                     : "above on " + figures,
               "<= xatlas", any ? Json(met) : Json());
  }
}

// The real assets (--set assets): charts at most 1.25 x xatlas's on every asset, and the whole
// set in no more time than xatlas's (aim: half).
void asset_targets(Json& list, const Json& rows) {
  std::string failing;
  bool any = false;
  double ours_total = 0.0, peer_total = 0.0;
  bool timed = true;
  for (const Json& row : rows) {
    if (!row.value("asset", false)) continue;
    const Json ours = row["harmonia"].value("charts", Json());
    const Json peer = row["xatlas"].value("charts", Json());
    const Json ours_seconds = row["harmonia"].value("seconds", Json());
    const Json peer_seconds = row["xatlas"].value("seconds", Json());
    if (ours_seconds.is_number() && peer_seconds.is_number()) {
      ours_total += ours_seconds.get<double>();
      peer_total += peer_seconds.get<double>();
    } else {
      timed = false;
    }
    if (!ours.is_number() || !peer.is_number()) continue;
    any = true;
    if (ours.get<double>() > kAssetChartsLimit * peer.get<double>())
      append_item(failing, row["mesh"].get<std::string>() + " " + ours.dump() + " > " +
                               bench::fixed(Json(kAssetChartsLimit * peer.get<double>()), 1));
  }
  if (!any) return;
  add_target(list, "charts <= 1.25 x xatlas's (every asset)",
             failing.empty() ? "within on every asset" : "over on " + failing, "<= 1.25 x xatlas",
             failing.empty());
  const Json ratio = timed && peer_total > 0.0 ? Json(ours_total / peer_total) : Json();
  add_target(list, "the assets' total time / xatlas's",
             timed ? bench::fixed(ratio, 3) + " (" + bench::fixed(Json(ours_total), 2) + " s / " +
                         bench::fixed(Json(peer_total), 2) + " s)"
                   : "not every asset timed by both",
             "<= 1.00 (aim 0.50)", timed ? Json(ours_total <= peer_total) : Json(),
             "wall: the calls vs t_generate");
}

Json targets(const Json& rows, const Json& batch, const std::string& time_mesh,
             const std::string& scope) {
  Json list = Json::array();
  quality_targets(list, rows, [](const Json& row) { return row["quality"].get<bool>(); }, scope, true);
  quality_targets(list, rows, [](const Json& row) { return row.value("asset", false); }, "every asset", false);
  asset_targets(list, rows);
  // Charts at 16x <= 2 x base.
  {
    std::string figures;
    std::string failing;
    bool any = false;
    for (const Json& row : rows) {
      if (row["factor"] != kChartGrowthFactor || !row["quality"].get<bool>()) continue;
      const Json* base = find_row(rows, row["base"].get<std::string>(), 1);
      if (base == nullptr) continue;
      const Json big = row["harmonia"].value("charts", Json());
      const Json small = (*base)["harmonia"].value("charts", Json());
      if (!big.is_number() || !small.is_number() || small.get<double>() <= 0.0) continue;
      any = true;
      const double ratio = big.get<double>() / small.get<double>();
      if (ratio > kChartGrowthLimit) {
        append_item(failing, row["base"].get<std::string>() + " " + small.dump() + " -> " +
                                 big.dump() + " (" + bench::fixed(Json(ratio), 2) + "x)");
      }
      append_item(figures, row["base"].get<std::string>() + " " + bench::fixed(Json(ratio), 2));
    }
    add_target(list, "charts at x16 <= 2 x the base mesh's (every closed mesh)",
               any ? (failing.empty() ? figures : "over on " + failing) : "no base/x16 pair",
               "<= 2.00", any ? Json(failing.empty()) : Json());
  }
  // Time.
  for (const auto& [factor, aim] : time_aims()) {
    const Json* row = find_row(rows, time_mesh, factor);
    const std::string name = time_mesh + "-x" + std::to_string(factor);
    if (row == nullptr) {
      add_target(list, name + " time <= 1/5 of xatlas's", "not in this run", "<= 0.20", Json());
      continue;
    }
    const Json ours = (*row)["harmonia"].value("seconds", Json());
    const Json peer = (*row)["xatlas"].value("seconds", Json());
    const std::string faces = std::to_string((*row)["faces"].get<long>());
    if (ours.is_number() && peer.is_number()) {
      const double ratio = ours.get<double>() / peer.get<double>();
      add_target(list, name + " (" + faces + " faces) time / xatlas's",
                 bench::fixed(Json(ratio), 3) + " (" + bench::fixed(ours, 2) + " s / " +
                     bench::fixed(peer, 2) + " s)",
                 "<= 0.20", ratio <= kTimeShareOfXatlas, "wall: the call vs t_generate");
    } else {
      add_target(list, name + " (" + faces + " faces) time / xatlas's",
                 "harmonia " + bench::status_text((*row)["harmonia"]) + ", xatlas " +
                     bench::status_text((*row)["xatlas"]),
                 "<= 0.20", Json());
    }
    add_target(list, name + " time aim (2 cores)",
               ours.is_number() ? bench::fixed(ours, 2) + " s"
                                : bench::status_text((*row)["harmonia"]),
               "<= " + bench::fixed(Json(aim), 0) + " s",
               ours.is_number() ? Json(ours.get<double>() <= aim) : Json(), "aim");
  }
  {
    const Json* row = find_row(rows, time_mesh, kFinishedFactor);
    const std::string name = time_mesh + "-x" + std::to_string(kFinishedFactor);
    if (row == nullptr) {
      add_target(list, name + " finished", "not in this run", "status ok", Json());
    } else {
      const Json& ours = (*row)["harmonia"];
      const Json& measured = measured_of(ours);
      const bool valid = measured.value("flips", 1) == 0 && measured.value("overlaps", 1) == 0 &&
                         measured.value("crossings", 1) == 0 && measured.value("dropped", 1) == 0;
      add_target(list,
                 name + " (" + std::to_string((*row)["faces"].get<long>()) + " faces) finished",
                 ours["status"] == "ok" ? "ok in " + bench::fixed(ours["seconds"], 2) + " s" +
                                              (valid ? ", valid" : ", NOT valid")
                                        : bench::status_text(ours),
                 "finished", ours["status"] == "ok",
                 "xatlas: " + ((*row)["xatlas"]["status"] == "ok"
                                   ? bench::fixed((*row)["xatlas"]["seconds"], 2) + " s"
                                   : bench::status_text((*row)["xatlas"])));
    }
  }
  // Batch.
  if (batch["status"] == "ok") {
    add_target(list, "batch over the closed corpus: -j1 / -j2 wall time",
               bench::fixed(batch["speedup"], 2) + "x",
               ">= " + bench::fixed(Json(kBatchSpeedup), 1) + "x",
               batch["speedup"].get<double>() >= kBatchSpeedup);
  } else {
    add_target(list, "batch over the closed corpus: -j1 / -j2 wall time",
               batch.value("message", std::string("-")), ">= 1.6x", Json(), "not run");
  }
  return list;
}

// ---------------------------------------------------------------------------------------------
// Markdown

std::string count_text(const Json& measured, const char* field) {
  return bench::integer(measured, field);
}

std::string size_text(const Json& measured) {
  if (!measured.contains("width")) return "-";
  return std::to_string(measured["width"].get<int>()) + "x" +
         std::to_string(measured["height"].get<int>());
}

std::string seconds_text(const Json& value) { return bench::fixed(value, 3); }

std::string tool_status(const Json& tool) {
  if (tool["status"] != "ok") return bench::status_text(tool);
  const Json& measured = tool.value("measured", Json::object());
  if (measured.value("status", std::string("ok")) != "ok") {
    return "measure: " + bench::status_text(measured);
  }
  return "ok";
}

void quality_markdown(const Json& rows, std::ostringstream& md) {
  md << "\n## 1. Quality per mesh (both atlases measured by the same code)\n\n"
     << "coverage (WxH): texel centres covered / W H, atlaseval.py's definition; coverage (sq): "
     << "covered / max(W, H)^2, the share of the square atlas it would take (the same for a "
     << "square atlas). L2: Sander L2 stretch, each chart scaled to its 3D area (1 = isometry); "
     << "angle: 3D-area-weighted mean sigma1/sigma2; area: mean |log area ratio| with one scale "
     << "(texel density uniformity). 1-face: single-face charts. flips, overlaps (texels), "
     << "crossings (chart boundary edge pairs), mirrored (charts), dropped (faces).\n\n"
     << "| mesh | faces | atlas | charts | 1-face | size | coverage (WxH) | coverage (sq) | L2 | "
        "angle | area | flips | overlaps | crossings | mirrored | dropped | status |\n"
     << "|---|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const Json& row : rows) {
    for (const char* tool : {"harmonia", "xatlas"}) {
      const Json& entry = row[tool];
      const Json& measured = measured_of(entry);
      md << "| " << row["mesh"].get<std::string>() << " | " << row["faces"].get<long>() << " | "
         << tool << " | " << bench::integer(entry, "charts") << " | "
         << count_text(measured, "single_face_charts") << " | " << size_text(measured) << " | "
         << bench::fixed(measured.value("coverage", Json()), 3) << " | "
         << bench::fixed(measured.value("coverage_square", Json()), 3) << " | "
         << bench::fixed(measured.value("l2_stretch", Json()), 4) << " | "
         << bench::fixed(measured.value("angle_distortion", Json()), 4) << " | "
         << bench::fixed(measured.value("area_distortion", Json()), 4) << " | "
         << count_text(measured, "flips") << " | " << count_text(measured, "overlaps") << " | "
         << count_text(measured, "crossings") << " | " << count_text(measured, "mirrored")
         << " | " << count_text(measured, "dropped") << " | " << tool_status(entry) << " |\n";
    }
  }
}

void atlaseval_markdown(const Json& rows, std::ostringstream& md) {
  bool any = false;
  for (const Json& row : rows) {
    any = any || row["harmonia"].contains("atlaseval") || row["xatlas"].contains("atlaseval");
  }
  if (!any) return;
  md << "\n## Independent check: atlaseval.py on the base meshes' atlases\n\n"
     << "python3 atlaseval.py MESH ATLAS on both OBJs; compared with the figures above: counts "
     << "(charts, single-face charts, flips, mirrored, overlaps, crossings = between + within "
     << "charts, dropped = unassigned faces) exactly, coverage (WxH), L2, angle and area within "
     << "a relative " << kEvalTolerance << " (atlaseval prints 6 digits).\n\n"
     << "| mesh | atlas | agrees | differences | atlaseval valid | atlaseval s |\n"
     << "|---|---|---|---|---|---:|\n";
  for (const Json& row : rows) {
    for (const char* tool : {"harmonia", "xatlas"}) {
      if (!row[tool].contains("atlaseval")) continue;
      const Json& check = row[tool]["atlaseval"];
      std::string differences;
      for (const Json& difference : check.value("differences", Json::array())) {
        append_item(differences, difference.get<std::string>(), "; ");
      }
      md << "| " << row["mesh"].get<std::string>() << " | " << tool << " | "
         << (check["status"] != "ok" ? bench::status_text(check)
                                     : check["agree"].get<bool>() ? "yes" : "NO")
         << " | " << (differences.empty() ? "-" : differences) << " | "
         << (check.contains("valid") ? (check["valid"].get<bool>() ? "yes" : "no") : "-") << " | "
         << seconds_text(check.value("seconds", Json())) << " |\n";
    }
  }
  std::string mismatches;
  for (const Json& row : rows) {
    const Json& ours = row["harmonia"];
    if (!ours.contains("library_vs_obj_differences")) continue;
    for (const Json& difference : ours["library_vs_obj_differences"]) {
      append_item(mismatches, row["mesh"].get<std::string>() + ": " + difference.get<std::string>(),
                  "; ");
    }
  }
  md << "\nharmonia's own figures (atlas.metrics) against the same measure of its OBJ read back: "
     << (mismatches.empty() ? "identical on every mesh." : "DIFFER: " + mismatches) << "\n";
}

void chart_growth_markdown(const Json& rows, std::ostringstream& md) {
  md << "\n## 2. Chart count, base mesh vs x16\n\n"
     << "| mesh | faces | faces x16 | harmonia base | harmonia x16 | ratio | xatlas base | "
        "xatlas x16 | ratio |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Json& row : rows) {
    if (row["factor"] != 1 || !row["quality"].get<bool>()) continue;
    const Json* big = find_row(rows, row["base"].get<std::string>(), kChartGrowthFactor);
    if (big == nullptr) continue;
    md << "| " << row["base"].get<std::string>() << " | " << row["faces"].get<long>() << " | "
       << (*big)["faces"].get<long>();
    for (const char* tool : {"harmonia", "xatlas"}) {
      const Json small = row[tool].value("charts", Json());
      const Json large = (*big)[tool].value("charts", Json());
      const Json ratio = small.is_number() && large.is_number() && small.get<double>() > 0
                             ? Json(large.get<double>() / small.get<double>())
                             : Json();
      md << " | " << bench::integer(row[tool], "charts") << " | "
         << bench::integer((*big)[tool], "charts") << " | " << bench::fixed(ratio, 2);
    }
    md << " |\n";
  }
}

void time_markdown(const Json& rows, const std::string& time_mesh, std::ostringstream& md) {
  md << "\n## 3. Time (wall seconds; CPU seconds of all threads)\n\n"
     << "harmonia: the texture_atlas call (wall), its phases (report.timings: segmentation, "
     << "flattening, packing, and metrics = the measure of the finished atlas inside the call; "
     << "validation not shown) and the CPU time of the call. xatlas: t_generate = ComputeCharts "
     << "+ PackCharts (wall; AddMesh and the file excluded), its two halves and cpu_generate. "
     << "ratio = harmonia total / xatlas t_generate (target <= 0.20). Every mesh of the run is "
     << "listed; the timing mesh is " << time_mesh << ".\n\n"
     << "| mesh | faces | harmonia | segmentation | flattening | packing | metrics | harmonia "
        "CPU | peak MB | xatlas | compute charts | pack charts | xatlas CPU | xatlas peak MB | "
        "ratio |\n"
     << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Json& row : rows) {
    const Json& ours = row["harmonia"];
    const Json& peer = row["xatlas"];
    const Json phases = ours.value("phase_seconds", Json::object());
    const Json ours_seconds = ours.value("seconds", Json());
    const Json peer_seconds = peer.value("seconds", Json());
    const Json ratio = ours_seconds.is_number() && peer_seconds.is_number()
                           ? Json(ours_seconds.get<double>() / peer_seconds.get<double>())
                           : Json();
    md << "| " << row["mesh"].get<std::string>() << (row["timing"].get<bool>() ? " (timing)" : "")
       << " | " << row["faces"].get<long>() << " | "
       << (ours["status"] == "ok" ? seconds_text(ours_seconds) : bench::status_text(ours))
       << " | " << seconds_text(phases.value("segmentation", Json())) << " | "
       << seconds_text(phases.value("flattening", Json())) << " | "
       << seconds_text(phases.value("packing", Json())) << " | "
       << seconds_text(phases.value("metrics", Json())) << " | "
       << seconds_text(ours.value("cpu_seconds", Json())) << " | "
       << bench::fixed(ours.value("peak_MB", Json()), 0) << " | "
       << (peer["status"] == "ok" ? seconds_text(peer_seconds) : bench::status_text(peer))
       << " | " << seconds_text(peer.value("t_computecharts", Json())) << " | "
       << seconds_text(peer.value("t_packcharts", Json())) << " | "
       << seconds_text(peer.value("cpu_seconds", Json())) << " | "
       << bench::fixed(peer.value("peak_MB", Json()), 0) << " | " << bench::fixed(ratio, 3)
       << " |\n";
  }
}

void batch_markdown(const Json& batch, std::ostringstream& md) {
  md << "\n## 4. Batch over the closed corpus\n\n";
  if (batch["status"] == "not_run") {
    md << "| jobs | wall s | note |\n|---:|---:|---|\n| 1 | - | **"
       << batch["message"].get<std::string>() << "** |\n| 2 | - | not run |\n";
    return;
  }
  md << "`" << batch.value("command", std::string()) << "`: wall time, fastest of "
     << batch.value("repeat", 1) << " run(s).\n\n"
     << "| jobs | wall s | CPU s | status |\n|---:|---:|---:|---|\n";
  for (const Json& run : batch["runs"]) {
    md << "| " << run["jobs"].get<int>() << " | " << seconds_text(run["seconds"]) << " | "
       << seconds_text(run.value("cpu_seconds", Json())) << " | " << bench::status_text(run)
       << " |\n";
  }
  md << "| -j1 / -j2 | " << bench::fixed(batch.value("speedup", Json()), 2) << "x | | target >= "
     << kBatchSpeedup << "x |\n";
}

void targets_markdown(const Json& targets, std::ostringstream& md) {
  md << "\n## 5. Targets\n\n| target | measured | limit | met | note |\n|---|---|---|---|---|\n";
  for (const Json& target : targets) {
    const Json& met = target["met"];
    md << "| " << target["target"].get<std::string>() << " | "
       << target["measured"].get<std::string>() << " | " << target["limit"].get<std::string>()
       << " | " << (met.is_boolean() ? (met.get<bool>() ? "yes" : "NO") : "n/a") << " | "
       << target["note"].get<std::string>() << " |\n";
  }
}

std::string markdown(const Json& results) {
  std::ostringstream md;
  const Json& host = results["host"];
  md << "# harmonia texture atlas vs xatlas\n\n"
     << "Host: " << host["cpu"].get<std::string>() << ", " << host["cores"]
     << " cores; load average " << host["load_start"].get<std::string>() << " at start, "
     << host["load_end"].get<std::string>() << " at end. harmonia: texture_atlas, resolution "
     << kResolution << ", padding " << kPadding
     << (results.value("join_charts", false) ? ", join_charts on" : ", default options") << ", CPU backend, "
     << "flattening threads = cores. xatlas: " << results["xatlas"].get<std::string>()
     << " --target-res " << kResolution << " --padding " << kPadding
     << " (jpcy/xatlas built from source, -O2, its default options; threads = cores). Timings: "
     << "fastest of " << results["repeat"] << " run(s); each harmonia atlas in its own process, "
     << "capped at " << results["timeout"] << " s; each xatlas run capped at "
     << results["xatlas_timeout"] << " s"
     << (results["skip_xatlas_above"].get<long>() > 0
             ? ", skipped above " + std::to_string(results["skip_xatlas_above"].get<long>()) +
                   " faces"
             : std::string())
     << ".\n";
  quality_markdown(results["meshes"], md);
  atlaseval_markdown(results["meshes"], md);
  chart_growth_markdown(results["meshes"], md);
  time_markdown(results["meshes"], results["time_mesh"].get<std::string>(), md);
  batch_markdown(results["batch"], md);
  targets_markdown(results["targets"], md);
  return md.str();
}

}  // namespace

int main(int argc, char** argv) {
  const std::optional<Options> parsed = parse_options(argc, argv);
  if (!parsed) {
    print_usage();
    return 2;
  }
  const Options& options = *parsed;
  harmonia::set_blas_thread_policy(options.run.blas_threads);  // Inherited by every forked child.
  const fs::path closed_dir = bench::shared_data_dir() / "closed";
  std::vector<fs::path> corpus;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(closed_dir, error)) {
    if (entry.path().extension() == ".obj") corpus.push_back(entry.path());
  }
  const bool closed_set = options.set != "assets", asset_set = options.set != "closed";
  if (corpus.empty() && closed_set) {
    std::cerr << "corpus_atlas_benchmark: corpus absent (" << closed_dir
              << " has no .obj files)\n";
    return 1;
  }
  std::sort(corpus.begin(), corpus.end());
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    ::signal(signal_number, kill_running_group_and_exit);
  }
  if (!is_executable(options.xatlas)) {
    std::cerr << "corpus_atlas_benchmark: xatlas_run not built ("
              << (options.xatlas.empty() ? std::string("no path") : options.xatlas.string())
              << "): harmonia's rows only\n";
  }
  const fs::path scratch =
      fs::temp_directory_path() / ("harmonia-atlas-bench-" + std::to_string(::getpid()));
  fs::create_directories(scratch, error);
  std::vector<MeshCase> cases;
  if (closed_set) cases = mesh_cases(corpus, options);
  if (asset_set)
    for (const MeshCase& asset : asset_cases(scratch / "wild-obj")) cases.push_back(asset);
  const fs::path atlas_folder = options.keep_atlases.empty() ? scratch : options.keep_atlases;
  fs::create_directories(atlas_folder, error);

  Json results{{"host", Json{{"cpu", bench::host_cpu_model()},
                             {"cores", static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN))},
                             {"load_start", bench::host_load_average()}}},
               {"blas_threads", bench::blas_policy_name(options.run.blas_threads)},
               {"repeat", options.run.repeat},
               {"join_charts", options.join_charts},
               {"timeout", options.run.timeout_seconds},
               {"xatlas", options.xatlas.empty() ? std::string("xatlas_run (not built)")
                                                 : options.xatlas.filename().string()},
               {"xatlas_path", options.xatlas.string()},
               {"xatlas_timeout", options.xatlas_timeout_seconds},
               {"skip_xatlas_above", options.skip_xatlas_above},
               {"time_mesh", options.time_mesh},
               {"resolution", kResolution},
               {"padding", kPadding},
               {"meshes", Json::array()}};
  std::string scope = options.meshes.empty() ? "every closed mesh" : "the closed meshes run";
  for (std::size_t k = 0; k < options.sizes.size(); ++k) {
    scope += (k == 0 ? ", x" : k + 1 == options.sizes.size() ? " and x" : ", x") +
             std::to_string(options.sizes[k]);
  }
  // Both reports are written after every mesh (marked unfinished), so a long run that is
  // stopped keeps what it measured; the markdown goes to stdout once, at the end.
  const auto write_reports = [&](bool finished) {
    results["finished"] = finished;
    results["host"]["load_end"] = bench::host_load_average();
    results["targets"] = targets(results["meshes"], results["batch"], options.time_mesh, scope);
    std::string report = markdown(results);
    if (!finished) report += "\n**Unfinished run: the rows so far.**\n";
    std::ofstream(options.run.out_md) << report;
    std::ofstream(options.run.out_json) << results.dump(2) << "\n";
    return report;
  };
  results["batch"] = Json{
      {"status", "not_run"}, {"message", "not run yet"}, {"runs", Json::array()}};
  for (const MeshCase& mesh_case : cases) {
    results["meshes"].push_back(mesh_row(mesh_case, atlas_folder, options));
    write_reports(false);
  }
  results["batch"] = options.batch && closed_set ? batch_rows(closed_dir, scratch, options)
                                   : Json{{"status", "not_run"},
                                          {"message", "not run (--no-batch)"},
                                          {"runs", Json::array()}};
  fs::remove_all(scratch, error);
  std::cout << write_reports(true);
  return 0;
}
