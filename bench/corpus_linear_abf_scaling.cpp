// Linear ABF at scale: phase times and peak memory on a mesh and its 4x / 16x subdivisions, each
// beside the floor (one supernodal Cholesky of the cotangent Laplacian's Dirichlet system).
//
//   corpus_linear_abf_scaling [MESH.obj] [FACTOR ...] [--no-floor] [--memory-trace]
//
// Defaults: ../shared/data/disk/face.obj, factors 1 4 16. The floor runs after linear ABF in the
// same process, so run with --no-floor (one factor per process) to read linear ABF's own peak
// memory, e.g. under /usr/bin/time -v; --memory-trace prints the resident size at each phase.
// Plain text output, one block per size.

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench/bench_support.h"
#include "harmonia/blas_threads.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/linear_abf.h"

int main(int argc, char** argv) {
  // As the harmonia program: two halves of a large system may be factorized side by side, with
  // OpenBLAS held to one thread per call (harmonia/blas_threads.h).
  harmonia::set_blas_thread_policy(harmonia::BlasThreadPolicy::hold_during_split_factorizations);
  using namespace harmonia;
  std::filesystem::path base = bench::shared_data_dir() / "disk" / "face.obj";
  std::vector<int> factors;
  bool floor = true;
  bool memory_trace = false;
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--no-floor") == 0) {
      floor = false;
    } else if (std::strcmp(argv[a], "--memory-trace") == 0) {
      memory_trace = true;
    } else if (std::strstr(argv[a], ".obj") != nullptr) {
      base = argv[a];
    } else {
      factors.push_back(std::atoi(argv[a]));
    }
  }
  if (factors.empty()) factors = {1, 4, 16};
  for (const int factor : factors) {
    std::string message;
    const auto path = bench::scaled_mesh(base, factor, &message);
    if (!path) {
      std::printf("%s x%d: %s\n", base.filename().c_str(), factor, message.c_str());
      continue;
    }
    const Mesh mesh = read_mesh(*path);
    bench::reset_peak_resident_size();
    const double resident_before = bench::process_status_megabytes("VmRSS");
    LinearAbfOptions options;
    options.solver_options.backend = BackendChoice::cpu;
    if (memory_trace)
      options.solver_options.progress = [](const Progress& progress) {
        std::printf("    -> %-15s RSS %6.0f MB, peak so far %6.0f MB\n",
                    std::string(progress.stage).c_str(), bench::process_status_megabytes("VmRSS"),
                    bench::process_status_megabytes("VmHWM"));
        return true;
      };
    const bench::Stopwatch stopwatch;
    const AngleMapResult result = linear_abf(mesh, options);
    const double seconds = stopwatch.seconds();
    const double peak = bench::process_status_megabytes("VmHWM");
    std::printf("%s x%d: %d faces, status %s, rounds %d, flips %d, %.3f s, peak RSS %.0f MB "
                "(%.0f MB before)\n",
                base.filename().c_str(), factor, mesh.face_count(),
                std::string(to_string(result.report.status)).c_str(), result.report.rounds,
                result.report.flipped_triangles, seconds, peak, resident_before);
    std::printf("  solver %s; nonlinear residual %.2e; abf energy %.4f (/3F %.3e)\n",
                result.report.solver.c_str(), result.report.constraint_residual,
                result.abf_energy, result.abf_energy / (3.0 * mesh.face_count()));
    std::printf("  phases:");
    for (const PhaseTiming& timing : result.report.timings)
      std::printf(" %s %.3f;", timing.phase.c_str(), timing.seconds);
    std::printf("\n");
    if (!floor) continue;
    const bench::DirichletSystem system =
        bench::dirichlet_system(mesh, laplacian(mesh, WeightScheme::cotangent));
    const bench::FloorMeasurement measured = bench::measure_floor(system);
    if (!measured.available) {
      std::printf("  floor: %s\n", measured.message.c_str());
      continue;
    }
    std::printf("  floor %.3f s (analyze %.3f, factorize %.3f, solve %.3f; %ld unknowns, factor "
                "%.1fM entries): linear ABF = %.2f x\n",
                measured.total_seconds(), measured.analyze_seconds, measured.factorize_seconds,
                measured.solve_seconds, measured.unknowns, measured.factor_nonzeros / 1e6,
                seconds / measured.total_seconds());
  }
  return 0;
}
