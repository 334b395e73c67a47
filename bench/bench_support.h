#pragma once
// Shared by the benchmark programs. Header-only on purpose: every bench_*.cpp and corpus_*.cpp is
// its own executable (bench/CMakeLists.txt), so there is no library to put a .cpp into.
//
// Four things live here:
//  * where the corpus, the tools and the cache of subdivided meshes are, and those meshes;
//  * the programs' own command-line flags and the description of the host in their reports;
//  * the Dirichlet system of a disk mesh (interior block of a Laplacian, boundary on a circle),
//    built without the library's own boundary code so the yardstick does not depend on what it
//    measures;
//  * the "floor": one supernodal CHOLMOD factorization and solve of that system (2 right-hand
//    sides, u and v) — the least work any fixed-boundary method must do on the same mesh.

#include <unistd.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fallback/serial_openmp_regions.h"
#include "harmonia/blas_threads.h"
#include "harmonia/io.h"
#include "harmonia/mesh.h"

#ifdef HARMONIA_HAVE_CHOLMOD
#include <cholmod.h>
#endif

#ifndef HARMONIA_SHARED_DATA_DIR
#define HARMONIA_SHARED_DATA_DIR "../shared/data"
#endif
#ifndef HARMONIA_SHARED_TOOLS_DIR
#define HARMONIA_SHARED_TOOLS_DIR "../shared/tools"
#endif

namespace harmonia::bench {

// ---------------------------------------------------------------------------------------------
// Locations

//! The corpus root: $HARMONIA_SHARED_DATA if set, else the compile-time ../shared/data.
inline std::filesystem::path shared_data_dir() {
  if (const char* from_environment = std::getenv("HARMONIA_SHARED_DATA")) return from_environment;
  return HARMONIA_SHARED_DATA_DIR;
}

//! Where subdivide.py lives: $HARMONIA_SHARED_TOOLS if set, else the compile-time ../shared/tools.
inline std::filesystem::path shared_tools_dir() {
  if (const char* from_environment = std::getenv("HARMONIA_SHARED_TOOLS")) return from_environment;
  return HARMONIA_SHARED_TOOLS_DIR;
}

//! Cache of subdivided meshes: $HARMONIA_BENCH_CACHE, else $TMPDIR/harmonia-bench-meshes, else
//! /tmp/harmonia-bench-meshes.
inline std::filesystem::path mesh_cache_dir() {
  if (const char* from_environment = std::getenv("HARMONIA_BENCH_CACHE")) return from_environment;
  const char* temporary = std::getenv("TMPDIR");
  const std::filesystem::path root =
      temporary != nullptr && *temporary != '\0' ? temporary : "/tmp";
  return root / "harmonia-bench-meshes";
}

//! Number of 1->4 subdivision steps that multiply the face count by `factor` (1, 4, 16, 64, ...),
//! or -1 when `factor` is not a power of four.
inline int subdivision_steps(int factor) {
  int steps = 0;
  while (factor > 1 && factor % 4 == 0) {
    factor /= 4;
    ++steps;
  }
  return factor == 1 ? steps : -1;
}

//! Path of `base` with its face count multiplied by `factor` (midpoint subdivision, geometry
//! unchanged). factor 1 is `base` itself; larger ones are made once with subdivide.py into the
//! cache as STEM-xFACTOR.obj. Returns nothing and fills `message` when the base mesh, the tool or
//! python3 is missing or the tool fails.
inline std::optional<std::filesystem::path> scaled_mesh(const std::filesystem::path& base,
                                                        int factor, std::string* message) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::exists(base, error)) {
    if (message != nullptr) *message = "corpus absent: " + base.string() + " does not exist";
    return std::nullopt;
  }
  const int steps = subdivision_steps(factor);
  if (steps < 0) {
    if (message != nullptr)
      *message = "size factor " + std::to_string(factor) + " is not a power of 4";
    return std::nullopt;
  }
  if (steps == 0) return base;
  const fs::path cached =
      mesh_cache_dir() / (base.stem().string() + "-x" + std::to_string(factor) + ".obj");
  if (fs::exists(cached, error)) return cached;

  const fs::path tool = shared_tools_dir() / "subdivide.py";
  if (!fs::exists(tool, error)) {
    if (message != nullptr) *message = "corpus absent: " + tool.string() + " does not exist";
    return std::nullopt;
  }
  fs::create_directories(mesh_cache_dir(), error);
  // Written beside the target and renamed, so a concurrent or interrupted run never sees half a
  // file.
  const fs::path partial = cached.string() + ".partial-" + std::to_string(::getpid());
  const std::string command = "python3 '" + tool.string() + "' '" + base.string() + "' '" +
                              partial.string() + "' --times " + std::to_string(steps) +
                              " >/dev/null 2>&1";
  if (std::system(command.c_str()) != 0 || !fs::exists(partial, error)) {
    fs::remove(partial, error);
    if (message != nullptr)
      *message = "could not subdivide " + base.string() + " (" + command + ")";
    return std::nullopt;
  }
  fs::rename(partial, cached, error);
  if (error) {
    if (message != nullptr) *message = "could not move " + partial.string() + " into place";
    return std::nullopt;
  }
  return cached;
}

//! scaled_mesh, read: each (base, factor) is made and read once per process and kept, since a
//! Google benchmark calls its function several times. nullptr, with the reason in `message`, when
//! it cannot be had.
inline const Mesh* cached_scaled_mesh(const std::filesystem::path& base, int factor,
                                      std::string* message) {
  struct Entry {
    std::unique_ptr<Mesh> mesh;
    std::string failure;
  };
  static std::map<std::pair<std::string, int>, Entry> cache;
  const auto [slot, fresh] = cache.try_emplace({base.string(), factor});
  Entry& entry = slot->second;
  if (fresh) {
    if (const auto path = scaled_mesh(base, factor, &entry.failure)) {
      try {
        entry.mesh = std::make_unique<Mesh>(read_mesh(*path));
      } catch (const std::exception& error) {
        entry.failure = std::string("corpus absent: ") + error.what();
      }
    }
  }
  if (entry.mesh == nullptr && message != nullptr) *message = entry.failure;
  return entry.mesh.get();
}

// ---------------------------------------------------------------------------------------------
// Command lines and the host

//! Removes every "--NAME=VALUE" from argv, so that Google Benchmark never sees a flag it does not
//! know, and returns the last VALUE (nothing when the flag is absent).
inline std::optional<std::string> take_flag_value(int* argc, char** argv, std::string_view name) {
  const std::string prefix = "--" + std::string(name) + "=";
  std::optional<std::string> value;
  int kept = 1;
  for (int index = 1; index < *argc; ++index) {
    const std::string_view argument = argv[index];
    if (argument.starts_with(prefix)) {
      value = std::string(argument.substr(prefix.size()));
    } else {
      argv[kept++] = argv[index];
    }
  }
  *argc = kept;
  return value;
}

//! The largest size factor a Google benchmark runs: --max_size=N (taken out of argv), else
//! $HARMONIA_BENCH_MAX_SIZE, else `default_factor`.
inline int max_size_factor(int* argc, char** argv, int default_factor = 16) {
  const std::optional<std::string> flag = take_flag_value(argc, argv, "max_size");
  if (flag) return std::atoi(flag->c_str());
  const char* from_environment = std::getenv("HARMONIA_BENCH_MAX_SIZE");
  return from_environment != nullptr ? std::atoi(from_environment) : default_factor;
}

//! The non-empty items of a comma-separated option value ("a,b,,c" -> a, b, c).
inline std::vector<std::string> comma_separated(const std::string& text) {
  std::vector<std::string> items;
  std::istringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    if (!item.empty()) items.push_back(std::move(item));
  }
  return items;
}

//! The options the corpus programs share.
struct CorpusRunOptions {
  int repeat = 1;             //!< Timed runs per measurement; the fastest counts.
  int timeout_seconds = 900;  //!< Per child process (corpus_child.h).
  //! What harmonia may do with OpenBLAS's process-wide thread count (harmonia/blas_threads.h): by
  //! default what the harmonia program does.
  BlasThreadPolicy blas_threads = BlasThreadPolicy::hold_during_split_factorizations;
  std::filesystem::path out_md;    //!< The markdown report (also printed to stdout).
  std::filesystem::path out_json;  //!< Every field of the report.
};

//! Reads `value` into `options` when `flag` is one of the shared options: --repeat N, --timeout S,
//! --blas-threads hold|leave, --out-md FILE, --out-json FILE. False for any other flag or policy.
inline bool parse_corpus_run_option(const std::string& flag, const std::string& value,
                                    CorpusRunOptions* options) {
  if (flag == "--repeat") {
    options->repeat = std::max(1, std::stoi(value));
  } else if (flag == "--timeout") {
    options->timeout_seconds = std::max(1, std::stoi(value));
  } else if (flag == "--blas-threads" && value == "hold") {
    options->blas_threads = BlasThreadPolicy::hold_during_split_factorizations;
  } else if (flag == "--blas-threads" && value == "leave") {
    options->blas_threads = BlasThreadPolicy::leave_alone;
  } else if (flag == "--out-md") {
    options->out_md = value;
  } else if (flag == "--out-json") {
    options->out_json = value;
  } else {
    return false;
  }
  return true;
}

//! The policy as --blas-threads names it.
inline const char* blas_policy_name(BlasThreadPolicy policy) {
  return policy == BlasThreadPolicy::leave_alone ? "leave" : "hold";
}

//! The processor's name as /proc/cpuinfo gives it, for the header of a report.
inline std::string host_cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    const std::size_t colon = line.find(':');
    if (line.starts_with("model name") && colon != std::string::npos) {
      return line.substr(colon + 2);
    }
  }
  return "unknown CPU";
}

//! The 1-, 5- and 15-minute load averages ("0.52 0.61 0.70"): a timing means little on a busy
//! machine, so reports print them at their start and end.
inline std::string host_load_average() {
  std::ifstream loadavg("/proc/loadavg");
  std::string minute, five_minutes, fifteen_minutes;
  loadavg >> minute >> five_minutes >> fifteen_minutes;
  return minute + " " + five_minutes + " " + fifteen_minutes;
}

// ---------------------------------------------------------------------------------------------
// Timing and memory

//! Wall-clock stopwatch (steady clock), started on construction.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  void restart() { start_ = std::chrono::steady_clock::now(); }
  [[nodiscard]] double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

//! A "Vm...:   N kB" field of /proc/self/status in megabytes (2^20 bytes); -1 if unavailable.
inline double process_status_megabytes(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(field + ":", 0) == 0) {
      return std::strtod(line.c_str() + field.size() + 1, nullptr) / 1024.0;
    }
  }
  return -1.0;
}

//! Sets the peak resident size (VmHWM) back to the current resident size (Linux >= 4.0, writing 5
//! to /proc/self/clear_refs). Returns false where that is not allowed.
inline bool reset_peak_resident_size() {
  std::ofstream clear_refs("/proc/self/clear_refs");
  if (!clear_refs) return false;
  clear_refs << "5";
  clear_refs.flush();
  return static_cast<bool>(clear_refs);
}

// ---------------------------------------------------------------------------------------------
// The Dirichlet system of a disk

//! The longest boundary loop of an edge-manifold, consistently oriented mesh, following the
//! boundary half-edges (those whose twin is missing) so that the mesh lies to the left. Starts at
//! the smallest vertex index on the loop (deterministic). Empty for a closed mesh.
inline std::vector<int> longest_boundary_loop(const Mesh& mesh) {
  std::vector<std::pair<int, int>> half_edges;
  half_edges.reserve(static_cast<std::size_t>(mesh.face_count()) * 3);
  for (int face = 0; face < mesh.face_count(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      half_edges.emplace_back(mesh.faces(face, corner), mesh.faces(face, (corner + 1) % 3));
    }
  }
  std::sort(half_edges.begin(), half_edges.end());
  // next_on_boundary[a] = b for the boundary half-edge a -> b.
  std::vector<int> next_on_boundary(static_cast<std::size_t>(mesh.vertex_count()), -1);
  for (const auto& [from, to] : half_edges) {
    if (!std::binary_search(half_edges.begin(), half_edges.end(), std::make_pair(to, from))) {
      next_on_boundary[static_cast<std::size_t>(from)] = to;
    }
  }
  std::vector<bool> visited(next_on_boundary.size(), false);
  std::vector<int> longest;
  for (int start = 0; start < mesh.vertex_count(); ++start) {
    if (next_on_boundary[static_cast<std::size_t>(start)] < 0 ||
        visited[static_cast<std::size_t>(start)]) {
      continue;
    }
    std::vector<int> loop;
    for (int vertex = start; vertex >= 0 && !visited[static_cast<std::size_t>(vertex)];
         vertex = next_on_boundary[static_cast<std::size_t>(vertex)]) {
      visited[static_cast<std::size_t>(vertex)] = true;
      loop.push_back(vertex);
    }
    if (loop.size() > longest.size()) longest = std::move(loop);
  }
  return longest;
}

//! Positions of `loop` on the unit circle, counter-clockwise from loop[0], spaced by 3D arc length.
inline Eigen::MatrixX2d circle_positions(const Mesh& mesh, const std::vector<int>& loop) {
  const std::size_t count = loop.size();
  std::vector<double> arc_length(count + 1, 0.0);
  for (std::size_t k = 0; k < count; ++k) {
    const auto from = mesh.vertices.row(loop[k]);
    const auto to = mesh.vertices.row(loop[(k + 1) % count]);
    arc_length[k + 1] = arc_length[k] + (to - from).norm();
  }
  Eigen::MatrixX2d positions(static_cast<Eigen::Index>(count), 2);
  for (std::size_t k = 0; k < count; ++k) {
    const double angle = 2.0 * std::numbers::pi * arc_length[k] / arc_length[count];
    positions(static_cast<Eigen::Index>(k), 0) = std::cos(angle);
    positions(static_cast<Eigen::Index>(k), 1) = std::sin(angle);
  }
  return positions;
}

//! L_II x = -L_IB u_B: the interior block of a #V by #V Laplacian and the right-hand sides for
//! u and v with the boundary on the unit circle (thesis eq. 6.1).
struct DirichletSystem {
  Eigen::SparseMatrix<double> interior_matrix;  //!< #I by #I, column-major, compressed.
  Eigen::MatrixXd right_hand_sides;             //!< #I by 2.
  std::vector<int> interior_vertices;           //!< Mesh index of each unknown.
  std::vector<int> boundary_loop;               //!< The fixed vertices, in loop order.
};

//! Builds the system from `laplacian` (PSD convention, as harmonia::laplacian returns it).
//! Returns an empty system (no unknowns) when the mesh has no boundary.
inline DirichletSystem dirichlet_system(const Mesh& mesh,
                                        const Eigen::SparseMatrix<double>& laplacian) {
  DirichletSystem system;
  system.boundary_loop = longest_boundary_loop(mesh);
  if (system.boundary_loop.empty()) return system;
  const Eigen::MatrixX2d boundary_uv = circle_positions(mesh, system.boundary_loop);

  // unknown_of[v] = index among the unknowns, or -1 for a fixed vertex; loop_position[v] = row of
  // boundary_uv for a fixed vertex.
  std::vector<int> unknown_of(static_cast<std::size_t>(mesh.vertex_count()), 0);
  std::vector<int> loop_position(unknown_of.size(), -1);
  for (std::size_t k = 0; k < system.boundary_loop.size(); ++k) {
    unknown_of[static_cast<std::size_t>(system.boundary_loop[k])] = -1;
    loop_position[static_cast<std::size_t>(system.boundary_loop[k])] = static_cast<int>(k);
  }
  for (int vertex = 0; vertex < mesh.vertex_count(); ++vertex) {
    if (unknown_of[static_cast<std::size_t>(vertex)] < 0) continue;
    unknown_of[static_cast<std::size_t>(vertex)] =
        static_cast<int>(system.interior_vertices.size());
    system.interior_vertices.push_back(vertex);
  }

  const auto unknowns = static_cast<Eigen::Index>(system.interior_vertices.size());
  system.right_hand_sides = Eigen::MatrixXd::Zero(unknowns, 2);
  // The renumbering keeps the order of the interior vertices, so every kept column stays sorted
  // and the compressed arrays can be written directly.
  std::vector<int> outer{0};
  std::vector<int> inner;
  std::vector<double> values;
  inner.reserve(static_cast<std::size_t>(laplacian.nonZeros()));
  values.reserve(static_cast<std::size_t>(laplacian.nonZeros()));
  for (int column = 0; column < laplacian.outerSize(); ++column) {
    const int column_unknown = unknown_of[static_cast<std::size_t>(column)];
    for (Eigen::SparseMatrix<double>::InnerIterator entry(laplacian, column); entry; ++entry) {
      const int row_unknown = unknown_of[static_cast<std::size_t>(entry.row())];
      if (row_unknown < 0) continue;
      if (column_unknown >= 0) {
        inner.push_back(row_unknown);
        values.push_back(entry.value());
      } else {
        system.right_hand_sides.row(row_unknown) -=
            entry.value() * boundary_uv.row(loop_position[static_cast<std::size_t>(column)]);
      }
    }
    if (column_unknown >= 0) outer.push_back(static_cast<int>(inner.size()));
  }
  system.interior_matrix = Eigen::Map<const Eigen::SparseMatrix<double>>(
      unknowns, unknowns, static_cast<Eigen::Index>(inner.size()), outer.data(), inner.data(),
      values.data());
  return system;
}

// ---------------------------------------------------------------------------------------------
// The floor

//! Times of one floor measurement (seconds) and what it did.
struct FloorMeasurement {
  bool available = false;          //!< False without CHOLMOD or when the factorization failed.
  std::string message;             //!< Why it is not available.
  double analyze_seconds = 0.0;    //!< cholmod_analyze: fill-reducing ordering + symbolic.
  double factorize_seconds = 0.0;  //!< cholmod_factorize: supernodal numeric Cholesky.
  double solve_seconds = 0.0;      //!< cholmod_solve with both right-hand sides at once.
  long unknowns = 0;
  double factor_nonzeros = 0.0;    //!< Entries of the Cholesky factor (CHOLMOD's lnz).
  double relative_residual = 0.0;  //!< max over u, v of ||A x - b|| / ||b|| (checked, not timed).
  Eigen::MatrixXd solution;        //!< #I by 2.
  [[nodiscard]] double total_seconds() const {
    return analyze_seconds + factorize_seconds + solve_seconds;
  }
};

//! One analyze + factorize + solve of `system` with CHOLMOD's supernodal Cholesky and its default
//! ordering. The matrix is handed over without copying (CHOLMOD reads its lower triangle).
inline FloorMeasurement measure_floor(const DirichletSystem& system) {
  FloorMeasurement floor;
  floor.unknowns = static_cast<long>(system.interior_matrix.rows());
#ifndef HARMONIA_HAVE_CHOLMOD
  (void)system;
  floor.message = "built without CHOLMOD: no floor";
  return floor;
#else
  if (floor.unknowns == 0) {
    floor.message = "no interior vertices (closed mesh or boundary only)";
    return floor;
  }
  cholmod_common common;
  cholmod_start(&common);
  common.supernodal = CHOLMOD_SUPERNODAL;

  // Views of the Eigen arrays in CHOLMOD's structs (CHOLMOD does not modify its inputs).
  auto& matrix = const_cast<Eigen::SparseMatrix<double>&>(system.interior_matrix);
  cholmod_sparse matrix_view{};
  matrix_view.nrow = static_cast<std::size_t>(matrix.rows());
  matrix_view.ncol = static_cast<std::size_t>(matrix.cols());
  matrix_view.nzmax = static_cast<std::size_t>(matrix.nonZeros());
  matrix_view.p = matrix.outerIndexPtr();
  matrix_view.i = matrix.innerIndexPtr();
  matrix_view.x = matrix.valuePtr();
  matrix_view.stype = -1;  // Symmetric, lower triangle used.
  matrix_view.itype = CHOLMOD_INT;
  matrix_view.xtype = CHOLMOD_REAL;
  matrix_view.dtype = CHOLMOD_DOUBLE;
  matrix_view.sorted = 1;
  matrix_view.packed = 1;

  auto& right_hand_sides = const_cast<Eigen::MatrixXd&>(system.right_hand_sides);
  cholmod_dense rhs_view{};
  rhs_view.nrow = static_cast<std::size_t>(right_hand_sides.rows());
  rhs_view.ncol = static_cast<std::size_t>(right_hand_sides.cols());
  rhs_view.nzmax = rhs_view.nrow * rhs_view.ncol;
  rhs_view.d = rhs_view.nrow;
  rhs_view.x = right_hand_sides.data();
  rhs_view.xtype = CHOLMOD_REAL;
  rhs_view.dtype = CHOLMOD_DOUBLE;

  Stopwatch stopwatch;
  cholmod_factor* factor = cholmod_analyze(&matrix_view, &common);
  floor.analyze_seconds = stopwatch.seconds();
  if (factor == nullptr) {
    floor.message = "cholmod_analyze failed (status " + std::to_string(common.status) + ")";
    cholmod_finish(&common);
    return floor;
  }
  stopwatch.restart();
  int factorized = 0;
  {
    // With the calling thread's OpenMP regions serial, as the library's own factorizations run
    // (serial_openmp_regions.h): the floor is the best plain Cholesky this machine does.
    const detail::SerialOpenMpRegions serial_regions;
    factorized = cholmod_factorize(&matrix_view, factor, &common);
  }
  floor.factorize_seconds = stopwatch.seconds();
  if (factorized == 0 || common.status != CHOLMOD_OK) {
    floor.message = "cholmod_factorize failed (status " + std::to_string(common.status) +
                    (common.status == CHOLMOD_NOT_POSDEF ? ", not positive definite)" : ")");
    cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
    return floor;
  }
  stopwatch.restart();
  cholmod_dense* solution = cholmod_solve(CHOLMOD_A, factor, &rhs_view, &common);
  floor.solve_seconds = stopwatch.seconds();
  floor.factor_nonzeros = common.lnz;
  if (solution == nullptr) {
    floor.message = "cholmod_solve failed (status " + std::to_string(common.status) + ")";
  } else {
    floor.solution = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(solution->x),
                                                       right_hand_sides.rows(), 2);
    floor.available = true;
    cholmod_free_dense(&solution, &common);
  }
  cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);

  if (floor.available) {
    // The residual proves the yardstick solved the right system; it is outside the timed part.
    for (int column = 0; column < 2; ++column) {
      const Eigen::VectorXd residual =
          system.interior_matrix * floor.solution.col(column) - system.right_hand_sides.col(column);
      const double scale = std::max(system.right_hand_sides.col(column).norm(), 1e-300);
      floor.relative_residual = std::max(floor.relative_residual, residual.norm() / scale);
    }
  }
  return floor;
#endif
}

}  // namespace harmonia::bench
