// Google Benchmark: the surface editor (harmonia/surface_editor.h) on the closed bunny at 1x, 4x
// and 16x its size (6,966 / 27,864 / 111,456 faces; the larger ones by midpoint subdivision), CPU
// backend, with the geometric edit of bench/surface_edit_support.h: the lowest 10 % of the height
// fixed, the highest 10 % turned 45 degrees and lifted.
//
//   surface_editor/setup  the SurfaceEditor constructor: validation, analysis, the one
//                         factorization and the handle's harmonic field;
//   surface_editor/frame  one SurfaceEditor::deform on a ready editor, the edit played as 20
//                         frames (partial(t), t = 1/20 .. 1), one frame per iteration.
//
// Sizes: --max_size=N (or $HARMONIA_BENCH_MAX_SIZE) keeps the factors <= N. Every benchmark reports
// items_per_second = faces per second and the counters faces and vertices; the frame also the
// mean blending / assembly / solve / check milliseconds of SurfaceEditResult::timing.

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_support.h"
#include "bench/surface_edit_support.h"
#include "harmonia/blas_threads.h"
#include "harmonia/surface_editor.h"

namespace {

using harmonia::Mesh;

constexpr int size_factors[] = {1, 4, 16};
//! Frames of the played edit; iteration k shows frame k mod 20 + 1.
constexpr int frames_per_edit = 20;

//! Skips the benchmark with `message`; Google Benchmark keeps a pointer to the text, so it is kept
//! here for the rest of the process.
void skip(benchmark::State& state, std::string message) {
  static std::vector<std::unique_ptr<std::string>> messages;
  messages.push_back(std::make_unique<std::string>(std::move(message)));
  state.SkipWithError(messages.back()->c_str());
}

//! The bunny at this benchmark's size, or nullptr after skipping (corpus or tool missing).
const Mesh* bunny_or_skip(benchmark::State& state) {
  std::string message;
  const Mesh* mesh = harmonia::bench::cached_scaled_mesh(
      harmonia::bench::shared_data_dir() / "closed" / "bunny.obj", static_cast<int>(state.range(0)),
      &message);
  if (mesh == nullptr) skip(state, message);
  return mesh;
}

bool succeeded(benchmark::State& state, const harmonia::SolveReport& report) {
  if (report.ok()) return true;
  skip(state, std::string(harmonia::to_string(report.status)) + ": " + report.message);
  return false;
}

harmonia::SurfaceEditOptions cpu_options() {
  harmonia::SurfaceEditOptions options;
  options.solver.backend = harmonia::BackendChoice::cpu;
  return options;
}

void report_size(benchmark::State& state, const Mesh& mesh) {
  state.SetItemsProcessed(state.iterations() * mesh.face_count());
  state.counters["faces"] = mesh.face_count();
  state.counters["vertices"] = mesh.vertex_count();
}

void editor_setup(benchmark::State& state) {
  const Mesh* mesh = bunny_or_skip(state);
  if (mesh == nullptr) return;
  const harmonia::EditDescription edit = harmonia::bench::geometric_edit(*mesh);
  std::map<std::string, double> phase_seconds;  // Summed over the iterations.
  for (auto _ : state) {
    const harmonia::SurfaceEditor editor(*mesh, edit.regions, cpu_options());
    if (!succeeded(state, editor.setup_report())) return;
    for (const harmonia::PhaseTiming& timing : editor.setup_report().timings) {
      phase_seconds[timing.phase] += timing.seconds;
    }
  }
  report_size(state, *mesh);
  // The set-up's phases: validation, analysis, factorization, fields.
  const auto iterations = static_cast<double>(state.iterations());
  for (const auto& [phase, seconds] : phase_seconds) {
    state.counters[phase + "_ms"] = 1e3 * seconds / iterations;
  }
}

void editor_frame(benchmark::State& state) {
  const Mesh* mesh = bunny_or_skip(state);
  if (mesh == nullptr) return;
  const harmonia::EditDescription edit = harmonia::bench::geometric_edit(*mesh);
  harmonia::SurfaceEditor editor(*mesh, edit.regions, cpu_options());
  if (!succeeded(state, editor.setup_report())) return;
  harmonia::EditFrameTiming summed;
  int frame = 0;
  int flipped_triangles = 0;
  for (auto _ : state) {
    const harmonia::SurfaceEditResult result = editor.deform(harmonia::bench::frame_transforms(
        edit.transforms, frame % frames_per_edit + 1, frames_per_edit));
    ++frame;
    if (!succeeded(state, result.report)) return;
    benchmark::DoNotOptimize(result.positions.data());
    summed.blending += result.timing.blending;
    summed.assembly += result.timing.assembly;
    summed.solve += result.timing.solve;
    summed.check += result.timing.check;
    flipped_triangles = result.report.flipped_triangles;
  }
  report_size(state, *mesh);
  const auto iterations = static_cast<double>(state.iterations());
  state.counters["blend_ms"] = 1e3 * summed.blending / iterations;
  state.counters["assembly_ms"] = 1e3 * summed.assembly / iterations;
  state.counters["solve_ms"] = 1e3 * summed.solve / iterations;
  state.counters["check_ms"] = 1e3 * summed.check / iterations;
  state.counters["flipped"] = flipped_triangles;  // Of the last frame shown.
  // The editor's promise: one factorization, however many frames.
  state.counters["factorizations"] = editor.factorization_count();
}

void with_sizes(benchmark::internal::Benchmark* benchmark, int max_size) {
  for (const int factor : size_factors) {
    if (factor <= max_size) benchmark->Arg(factor);
  }
  benchmark->ArgName("size")->Unit(benchmark::kMillisecond)->UseRealTime();
}

}  // namespace

int main(int argc, char** argv) {
  // As the harmonia program: two halves of a large system may be factorized side by side, with
  // OpenBLAS held to one thread per call (harmonia/blas_threads.h).
  harmonia::set_blas_thread_policy(harmonia::BlasThreadPolicy::hold_during_split_factorizations);
  const int max_size = harmonia::bench::max_size_factor(&argc, argv);
  with_sizes(benchmark::RegisterBenchmark("surface_editor/setup", editor_setup), max_size);
  with_sizes(benchmark::RegisterBenchmark("surface_editor/frame", editor_frame), max_size);

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
