// Topology analysis on growing meshes: check_disk, boundary_loops and analyze_topology on the
// corpus disk face.obj at 1x, 4x and 16x its face count (51712, 206848, 827392 faces), and
// cut_to_disk on the closed homer.obj at 1x and 16x (12000, 192000 faces). The larger copies are
// made once with subdivide.py into the benchmark mesh cache (bench_support.h). Every planar map
// runs check_disk and boundary_loops first, so together they should stay well under a quarter
// second at 827K faces.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "bench/bench_support.h"
#include "harmonia/cut.h"
#include "harmonia/io.h"
#include "harmonia/topology.h"

namespace {

namespace fs = std::filesystem;

//! Meshes are read once per process (reading is not what is measured).
const harmonia::Mesh* load(const std::string& folder, const std::string& name, int factor,
                           std::string& reason) {
  static std::map<std::string, harmonia::Mesh> loaded;
  const std::string key = name + "-" + std::to_string(factor);
  if (const auto it = loaded.find(key); it != loaded.end()) return &it->second;
  const std::optional<fs::path> path = harmonia::bench::scaled_mesh(
      harmonia::bench::shared_data_dir() / folder / (name + ".obj"), factor, &reason);
  if (!path) return nullptr;
  return &loaded.emplace(key, harmonia::read_mesh(*path)).first->second;
}

template <typename Work>
void run_on(benchmark::State& state, const std::string& folder, const std::string& name,
            Work work) {
  std::string reason;
  const harmonia::Mesh* mesh = load(folder, name, static_cast<int>(state.range(0)), reason);
  if (mesh == nullptr) {
    state.SkipWithError(reason.c_str());
    return;
  }
  for (auto _ : state) work(*mesh);
  state.SetItemsProcessed(state.iterations() * mesh->face_count());
  state.counters["faces"] = static_cast<double>(mesh->face_count());
}

void check_disk_face(benchmark::State& state) {
  run_on(state, "disk", "face", [](const harmonia::Mesh& mesh) {
    std::string message;
    benchmark::DoNotOptimize(harmonia::check_disk(mesh, &message));
  });
}

void boundary_loops_face(benchmark::State& state) {
  run_on(state, "disk", "face", [](const harmonia::Mesh& mesh) {
    benchmark::DoNotOptimize(harmonia::boundary_loops(mesh).size());
  });
}

void analyze_topology_face(benchmark::State& state) {
  run_on(state, "disk", "face", [](const harmonia::Mesh& mesh) {
    benchmark::DoNotOptimize(harmonia::analyze_topology(mesh).edges);
  });
}

void cut_to_disk_homer(benchmark::State& state) {
  run_on(state, "closed", "homer", [](const harmonia::Mesh& mesh) {
    benchmark::DoNotOptimize(harmonia::cut_to_disk(mesh).seam_edges);
  });
}

}  // namespace

BENCHMARK(check_disk_face)->Arg(1)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(boundary_loops_face)->Arg(1)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(analyze_topology_face)->Arg(1)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(cut_to_disk_homer)->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
