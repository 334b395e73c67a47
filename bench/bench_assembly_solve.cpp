// Google Benchmark: Laplacian assembly and the planar maps on the face scan at 1x, 4x and 16x its
// size (51,712 / 206,848 / 827,392 faces; the larger ones by midpoint subdivision), next to the
// floor: one supernodal CHOLMOD analyze + factorize + solve of the same mesh's cotangent Dirichlet
// system (see bench/README.md).
//
// Sizes: --max_size=N (or $HARMONIA_BENCH_MAX_SIZE) keeps the factors <= N, e.g. --max_size=1 for a
// quick run. Every benchmark reports items_per_second = faces per second.

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_support.h"
#include "harmonia/blas_threads.h"
#include "harmonia/fixed_boundary_map.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/lscm.h"
#include "harmonia/quasi_harmonic_map.h"

namespace {

using harmonia::Mesh;
using harmonia::WeightScheme;

constexpr int size_factors[] = {1, 4, 16};

//! The face scan at `factor` times its size, read once per process; nullptr (and `message`) when
//! the corpus or the subdivision tool is missing.
const Mesh* face_mesh(int factor, std::string* message) {
  static std::map<int, std::unique_ptr<Mesh>> loaded;
  static std::map<int, std::string> failures;
  if (const auto found = loaded.find(factor); found != loaded.end()) return found->second.get();
  if (const auto failed = failures.find(factor); failed != failures.end()) {
    *message = failed->second;
    return nullptr;
  }
  const auto path = harmonia::bench::scaled_mesh(
      harmonia::bench::shared_data_dir() / "disk" / "face.obj", factor, message);
  if (!path) {
    failures[factor] = *message;
    return nullptr;
  }
  try {
    auto mesh = std::make_unique<Mesh>(harmonia::read_mesh(*path));
    return (loaded[factor] = std::move(mesh)).get();
  } catch (const std::exception& error) {
    *message = failures[factor] = std::string("corpus absent: ") + error.what();
    return nullptr;
  }
}

//! The mesh for this benchmark's size argument, or nullptr after SkipWithError.
const Mesh* mesh_or_skip(benchmark::State& state) {
  std::string message;
  const Mesh* mesh = face_mesh(static_cast<int>(state.range(0)), &message);
  if (mesh == nullptr) {
    // SkipWithError keeps a pointer to the text, so it must outlive this call.
    static std::map<int, std::string> messages;
    const std::string& kept = messages[static_cast<int>(state.range(0))] = message;
    state.SkipWithError(kept.c_str());
  }
  return mesh;
}

void report_faces(benchmark::State& state, const Mesh& mesh) {
  state.SetItemsProcessed(state.iterations() * mesh.face_count());
  state.counters["faces"] = mesh.face_count();
}

//! Skips the benchmark with the report's message when a method did not succeed.
bool succeeded(benchmark::State& state, const harmonia::SolveReport& report) {
  if (report.ok()) return true;
  static std::vector<std::unique_ptr<std::string>> messages;
  messages.push_back(std::make_unique<std::string>(std::string(harmonia::to_string(report.status)) +
                                                   ": " + report.message));
  state.SkipWithError(messages.back()->c_str());
  return false;
}

void laplacian_assembly(benchmark::State& state, WeightScheme scheme) {
  const Mesh* mesh = mesh_or_skip(state);
  if (mesh == nullptr) return;
  for (auto _ : state) {
    Eigen::SparseMatrix<double> operator_matrix = harmonia::laplacian(*mesh, scheme);
    benchmark::DoNotOptimize(operator_matrix.valuePtr());
  }
  report_faces(state, *mesh);
}

// Manual time: only analyze + factorize + solve count; the system is assembled beforehand.
void cholmod_floor(benchmark::State& state) {
  const Mesh* mesh = mesh_or_skip(state);
  if (mesh == nullptr) return;
  const harmonia::bench::DirichletSystem system =
      harmonia::bench::dirichlet_system(*mesh, harmonia::laplacian(*mesh, WeightScheme::cotangent));
  double analyze = 0.0;
  double factorize = 0.0;
  double solve = 0.0;
  for (auto _ : state) {
    const harmonia::bench::FloorMeasurement floor = harmonia::bench::measure_floor(system);
    if (!floor.available) {
      static std::string message;
      message = floor.message;
      state.SkipWithError(message.c_str());
      return;
    }
    state.SetIterationTime(floor.total_seconds());
    analyze += floor.analyze_seconds;
    factorize += floor.factorize_seconds;
    solve += floor.solve_seconds;
  }
  report_faces(state, *mesh);
  const auto iterations = static_cast<double>(state.iterations());
  state.counters["analyze_ms"] = 1e3 * analyze / iterations;
  state.counters["factorize_ms"] = 1e3 * factorize / iterations;
  state.counters["solve_ms"] = 1e3 * solve / iterations;
}

void fixed_boundary_cotangent(benchmark::State& state) {
  const Mesh* mesh = mesh_or_skip(state);
  if (mesh == nullptr) return;
  harmonia::FixedBoundaryOptions options;
  options.weights = WeightScheme::cotangent;
  options.solver.backend = harmonia::BackendChoice::cpu;
  for (auto _ : state) {
    const harmonia::MapResult result = harmonia::fixed_boundary_map(*mesh, options);
    if (!succeeded(state, result.report)) return;
    benchmark::DoNotOptimize(result.uv.data());
  }
  report_faces(state, *mesh);
}

void least_squares_conformal(benchmark::State& state) {
  const Mesh* mesh = mesh_or_skip(state);
  if (mesh == nullptr) return;
  harmonia::LscmOptions options;
  options.solver.backend = harmonia::BackendChoice::cpu;
  for (auto _ : state) {
    const harmonia::MapResult result = harmonia::lscm(*mesh, options);
    if (!succeeded(state, result.report)) return;
    benchmark::DoNotOptimize(result.uv.data());
  }
  report_faces(state, *mesh);
}

void quasi_harmonic(benchmark::State& state) {
  const Mesh* mesh = mesh_or_skip(state);
  if (mesh == nullptr) return;
  harmonia::QuasiHarmonicOptions options;
  options.solver.backend = harmonia::BackendChoice::cpu;
  int rounds = 0;
  for (auto _ : state) {
    const harmonia::QuasiHarmonicResult result = harmonia::quasi_harmonic_map(*mesh, options);
    if (!succeeded(state, result.report)) return;
    rounds = result.report.rounds;
    benchmark::DoNotOptimize(result.uv.data());
  }
  report_faces(state, *mesh);
  state.counters["rounds"] = rounds;
}

//! Largest size factor to run: --max_size=N (removed from argv), else $HARMONIA_BENCH_MAX_SIZE,
//! else 16.
int take_max_size(int* argc, char** argv) {
  int max_size = 16;
  if (const char* from_environment = std::getenv("HARMONIA_BENCH_MAX_SIZE")) {
    max_size = std::atoi(from_environment);
  }
  int kept = 1;
  for (int index = 1; index < *argc; ++index) {
    constexpr const char* flag = "--max_size=";
    if (std::strncmp(argv[index], flag, std::strlen(flag)) == 0) {
      max_size = std::atoi(argv[index] + std::strlen(flag));
    } else {
      argv[kept++] = argv[index];
    }
  }
  *argc = kept;
  return max_size;
}

//! Adds the size arguments; times are wall clock (manual for the floor, which times itself).
void with_sizes(benchmark::internal::Benchmark* benchmark, int max_size, bool manual_time = false) {
  for (const int factor : size_factors) {
    if (factor <= max_size) benchmark->Arg(factor);
  }
  benchmark->ArgName("size")->Unit(benchmark::kMillisecond);
  if (manual_time) {
    benchmark->UseManualTime();
  } else {
    benchmark->UseRealTime();
  }
}

}  // namespace

int main(int argc, char** argv) {
  // As the harmonia program: two halves of a large system may be factorized side by side, with
  // OpenBLAS held to one thread per call (harmonia/blas_threads.h).
  harmonia::set_blas_thread_policy(harmonia::BlasThreadPolicy::hold_during_split_factorizations);
  const int max_size = take_max_size(&argc, argv);
  const std::pair<const char*, WeightScheme> schemes[] = {
      {"laplacian/uniform", WeightScheme::uniform},
      {"laplacian/chord", WeightScheme::chord_length},
      {"laplacian/cotangent", WeightScheme::cotangent},
      {"laplacian/mean-value", WeightScheme::mean_value},
  };
  for (const auto& [name, scheme] : schemes) {
    with_sizes(benchmark::RegisterBenchmark(name, laplacian_assembly, scheme), max_size);
  }
  with_sizes(benchmark::RegisterBenchmark("floor/cholmod-supernodal", cholmod_floor), max_size,
             /*manual_time=*/true);
  with_sizes(benchmark::RegisterBenchmark("fixed_boundary_map/cotangent", fixed_boundary_cotangent),
             max_size);
  with_sizes(benchmark::RegisterBenchmark("lscm", least_squares_conformal), max_size);
  with_sizes(benchmark::RegisterBenchmark("quasi_harmonic_map", quasi_harmonic), max_size);

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
