#pragma once
// corpus_benchmark's measurements, each the body of one child process (corpus_child.h): the
// methods it knows, one method on one mesh and one backend, the floor, a read_mesh timing, and
// the probe that tells whether a Vulkan device exists.

#include <Eigen/Core>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/bench_support.h"
#include "bench/corpus_child.h"
#include "harmonia/abf.h"
#include "harmonia/fixed_boundary_map.h"
#include "harmonia/free_boundary_map.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/linear_abf.h"
#include "harmonia/lscm.h"
#include "harmonia/metrics.h"
#include "harmonia/quasi_harmonic_map.h"

#ifdef HARMONIA_HAVE_VULKAN
#include "harmonia/vulkan_context.h"
#endif

namespace harmonia::bench {

//! One row kind of the table.
struct Method {
  std::string key;           //!< Command-line name, e.g. "conformal-cotangent", "abf-uzawa".
  std::string method;        //!< Column "method".
  std::string variant;       //!< Column "variant": weights, or the ABF step solver.
  bool angle_based = false;  //!< ABF or linear ABF: has an ABF energy and Newton steps/rounds.
  //! A slow ABF step solver: run only on meshes up to --slow-max-faces.
  bool slow = false;
  AbfSolver solver = AbfSolver::automatic;  //!< For the ABF rows.
};

inline const std::vector<Method>& all_methods() {
  static const std::vector<Method> methods{
      {"conformal-cotangent", "conformal", "cotangent"},
      {"conformal-mean-value", "conformal", "mean-value"},
      {"conformal-uniform", "conformal", "uniform"},
      {"lscm", "lscm", "-"},
      {"qhm", "qhm", "tensor-cotangent"},
      {"free", "free", "cotangent"},
      {"free-polish", "free", "cotangent, polish"},
      {"linabf", "linear-abf", "-", true},
      {"abf", "abf", "automatic", true, false, AbfSolver::automatic},
      {"abf-schur-minres", "abf", "schur-minres", true, true, AbfSolver::schur_minres},
      {"abf-uzawa", "abf", "uzawa", true, true, AbfSolver::uzawa},
      {"abf-full-minres", "abf", "full-minres", true, true, AbfSolver::full_minres},
      {"abf-full-cgnr", "abf", "full-cgnr", true, true, AbfSolver::full_cgnr},
      {"abf-schur-direct", "abf", "schur-direct", true, false, AbfSolver::schur_direct},
  };
  return methods;
}

//! Where the linear algebra of a row runs.
enum class RowBackend { cpu, vulkan };

inline std::string to_string(RowBackend backend) {
  return backend == RowBackend::cpu ? "cpu" : "vulkan";
}

//! Whether Vulkan has a device, and which (filled by probe_vulkan, in a child process so that
//! the parent never holds a Vulkan instance across fork()).
struct VulkanProbe {
  bool available = false;
  bool software = false;  //!< DeviceType::cpu, e.g. lavapipe.
  std::string device;     //!< Name, or why there is none.
};

//! The device ContextOptions of the benchmark: the best device, or the one whose name contains
//! $HARMONIA_BENCH_VULKAN_DEVICE.
#ifdef HARMONIA_HAVE_VULKAN
inline vulkan::ContextOptions benchmark_context_options() {
  vulkan::ContextOptions options;
  if (const char* name = std::getenv("HARMONIA_BENCH_VULKAN_DEVICE")) options.device_name = name;
  return options;
}
#endif

//! Child body: creates a context and describes its device.
inline Json probe_vulkan_child() {
#ifdef HARMONIA_HAVE_VULKAN
  try {
    const vulkan::Context context = vulkan::Context::create(benchmark_context_options());
    const vulkan::DeviceInfo& device = context.device();
    return Json{{"status", "ok"},
                {"device", device.name},
                {"type", std::string(vulkan::to_string(device.type))},
                {"software", device.type == vulkan::DeviceType::cpu}};
  } catch (const Error& error) {
    return Json{{"status", "unavailable"}, {"device", error.what()}};
  }
#else
  return Json{{"status", "unavailable"}, {"device", "built without Vulkan"}};
#endif
}

inline VulkanProbe probe_vulkan(int timeout_seconds) {
  const Json answer = run_in_child(probe_vulkan_child, timeout_seconds);
  VulkanProbe probe;
  probe.available = answer.value("status", std::string()) == "ok";
  probe.software = answer.value("software", false);
  probe.device = answer.value("device", answer.value("message", std::string("no answer")));
  return probe;
}

//! What one map computation gives back, whatever the method.
struct MapOutcome {
  Eigen::MatrixX2d uv;
  SolveReport report;
  std::optional<double> abf_energy;  //!< Angle-based methods only.
};

//! One call of `method` on `mesh` with `solver` (backend and device already chosen).
inline MapOutcome compute_map(const Mesh& mesh, const Method& method, const SolverOptions& solver) {
  const std::string& key = method.key;
  if (key == "linabf" || key.rfind("abf", 0) == 0) {
    AngleMapResult result;
    if (key == "linabf") {
      LinearAbfOptions options;
      options.solver_options = solver;
      result = linear_abf(mesh, options);
    } else {
      AbfOptions options;
      options.solver = method.solver;
      options.solver_options = solver;
      result = abf(mesh, options);
    }
    MapOutcome outcome{std::move(result.uv), std::move(result.report), std::nullopt};
    if (result.angles.rows() == mesh.face_count()) outcome.abf_energy = result.abf_energy;
    return outcome;
  }
  if (key == "lscm") {
    LscmOptions options;
    options.solver = solver;
    MapResult result = lscm(mesh, options);
    return {std::move(result.uv), std::move(result.report), std::nullopt};
  }
  if (key == "free" || key == "free-polish") {
    FreeBoundaryOptions options;
    options.solver = solver;
    options.polish = key == "free-polish";
    FreeBoundaryResult result = free_boundary_map(mesh, options);
    return {std::move(result.uv), std::move(result.report), std::nullopt};
  }
  if (key == "qhm") {
    QuasiHarmonicOptions options;
    options.solver = solver;
    QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
    return {std::move(result.uv), std::move(result.report), std::nullopt};
  }
  FixedBoundaryOptions options;
  options.solver = solver;
  options.weights = weight_scheme_from_string(key.substr(std::string("conformal-").size())).value();
  MapResult result = fixed_boundary_map(mesh, options);
  return {std::move(result.uv), std::move(result.report), std::nullopt};
}

inline Json phases_json(const SolveReport& report) {
  Json phases = Json::array();
  for (const PhaseTiming& timing : report.timings) {
    phases.push_back(Json{{"phase", timing.phase}, {"seconds", timing.seconds}});
  }
  return phases;
}

//! Child body for one method on one mesh and backend: read, create the Vulkan context (not
//! timed: an application keeps one), time `repeat` runs (fastest counts), measure the peak
//! resident size of the runs, then evaluate the fastest run's map.
inline Json measure_method(const std::filesystem::path& mesh_path, const Method& method,
                           RowBackend backend, int repeat) {
  Stopwatch reading;
  const Mesh mesh = read_mesh(mesh_path);
  const double read_seconds = reading.seconds();

  SolverOptions solver;
  solver.backend = backend == RowBackend::cpu ? BackendChoice::cpu : BackendChoice::vulkan;
  double context_seconds = 0.0;
#ifdef HARMONIA_HAVE_VULKAN
  if (backend == RowBackend::vulkan) {
    Stopwatch creating;
    solver.vulkan_context =
        std::make_shared<vulkan::Context>(vulkan::Context::create(benchmark_context_options()));
    context_seconds = creating.seconds();
  }
#endif
  const double resident_before = process_status_megabytes("VmRSS");
  const bool peak_reset = reset_peak_resident_size();

  double best_seconds = std::numeric_limits<double>::infinity();
  MapOutcome best;
  for (int run = 0; run < repeat; ++run) {
    Stopwatch stopwatch;
    MapOutcome outcome = compute_map(mesh, method, solver);
    const double seconds = stopwatch.seconds();
    if (seconds < best_seconds) {
      best_seconds = seconds;
      best = std::move(outcome);
    }
  }
  const double peak = process_status_megabytes("VmHWM");

  const SolveReport& report = best.report;
  Json result{{"status", std::string(to_string(report.status))},
              {"message", report.message},
              {"faces", mesh.face_count()},
              {"vertices", mesh.vertex_count()},
              {"backend", std::string(to_string(report.backend))},
              {"solver", report.solver},
              {"device", report.device},
              {"precision", report.precision},
              {"seconds", best_seconds},
              {"read_seconds", read_seconds},
              {"context_seconds", context_seconds},
              {"peak_MB", peak},
              {"rss_before_MB", resident_before},
              {"peak_is_per_method", peak_reset},
              {"rounds", report.rounds},
              {"iterations", report.iterations},
              {"residual", report.residual},
              {"constraint_residual", report.constraint_residual},
              {"phases", phases_json(report)},
              {"fallbacks", report.fallbacks}};
  if (best.abf_energy) result["abf_energy"] = *best.abf_energy;
  if (best.uv.rows() == mesh.vertex_count() && best.uv.allFinite()) {
    const DistortionMetrics metrics = evaluate_map(mesh, best.uv, mesh.faces);
    result["flips"] = metrics.flipped_triangles;
    result["zero_area"] = metrics.zero_area_triangles;
    result["boundary_self_intersections"] = metrics.boundary_self_intersections;
    result["conformal_mean"] = metrics.conformal_distortion_mean;
    result["area_distortion_mean"] = metrics.area_distortion_mean;
    // The ABF measure of the layout's own angles (metrics.h), comparable across every method.
    result["uv_abf_energy"] = metrics.abf_energy;
  }
  return result;
}

//! Child body for the floor: assemble the cotangent Dirichlet system (not timed), then time
//! analyze + factorize + solve `repeat` times (fastest counts).
inline Json measure_floor_child(const std::filesystem::path& mesh_path, int repeat) {
  const Mesh mesh = read_mesh(mesh_path);
  Stopwatch assembling;
  const Eigen::SparseMatrix<double> laplacian = harmonia::laplacian(mesh, WeightScheme::cotangent);
  const double assembly_seconds = assembling.seconds();
  const DirichletSystem system = dirichlet_system(mesh, laplacian);
  const double resident_before = process_status_megabytes("VmRSS");
  const bool peak_reset = reset_peak_resident_size();

  FloorMeasurement best;
  best.analyze_seconds = std::numeric_limits<double>::infinity();
  for (int run = 0; run < repeat; ++run) {
    FloorMeasurement floor = measure_floor(system);
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
      {"backend", "cpu"},
      {"solver", "cholmod-supernodal"},
      {"seconds", best.total_seconds()},
      {"peak_MB", process_status_megabytes("VmHWM")},
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

//! Child body: the fastest of max(repeat, 2) read_mesh calls (the first may meet a cold page
//! cache).
inline Json measure_reading(const std::filesystem::path& path, int repeat) {
  double best = std::numeric_limits<double>::infinity();
  int faces = 0;
  for (int run = 0; run < std::max(repeat, 2); ++run) {
    Stopwatch stopwatch;
    const Mesh mesh = read_mesh(path);
    best = std::min(best, stopwatch.seconds());
    faces = mesh.face_count();
  }
  std::error_code error;
  return Json{
      {"status", "ok"},
      {"file", path.filename().string()},
      {"faces", faces},
      {"file_MB", static_cast<double>(std::filesystem::file_size(path, error)) / (1024.0 * 1024.0)},
      {"seconds", best},
      {"peak_MB", process_status_megabytes("VmHWM")}};
}

}  // namespace harmonia::bench
