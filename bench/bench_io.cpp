// Reading OBJ files of growing size: face.obj from the corpus at 1x, 4x and 16x its face count
// (51712, 206848 and 827392 faces). The larger copies are made once with subdivide.py into the
// benchmark mesh cache (bench_support.h). Reports faces per second; the target is 1M faces in at most 1 s.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <optional>
#include <string>

#include "bench/bench_support.h"
#include "harmonia/io.h"
#include "harmonia/types.h"

namespace {

namespace fs = std::filesystem;

void read_face_obj(benchmark::State& state) {
  std::string reason;
  const std::optional<fs::path> found = harmonia::bench::scaled_mesh(
      harmonia::bench::shared_data_dir() / "disk" / "face.obj",
      static_cast<int>(state.range(0)), &reason);
  if (!found) {
    state.SkipWithError(reason.c_str());
    return;
  }
  const fs::path& path = *found;
  std::int64_t faces = 0;
  for (auto _ : state) {
    const harmonia::Mesh mesh = harmonia::read_obj(path);
    faces = mesh.face_count();
    benchmark::DoNotOptimize(mesh.vertices.data());
  }
  state.SetItemsProcessed(state.iterations() * faces);
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["MB"] = static_cast<double>(fs::file_size(path)) / 1e6;
}

}  // namespace

BENCHMARK(read_face_obj)->Arg(1)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
