// Reading OBJ files of growing size: face.obj from the corpus at 1x, 4x and 16x its face count
// (51712, 206848 and 827392 faces). The larger copies are made once with subdivide.py into a
// temporary folder. Reports faces per second; the target is 1M faces in at most 1 s.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "harmonia/io.h"
#include "harmonia/types.h"

namespace {

namespace fs = std::filesystem;

// The OBJ with 4^times the faces of face.obj, or an empty path (and a reason) if it cannot be had.
fs::path face_mesh(int times, std::string& reason) {
  const fs::path source = fs::path(HARMONIA_SHARED_DATA_DIR) / "disk" / "face.obj";
  if (!fs::exists(source)) {
    reason = "corpus not found: " + source.string();
    return {};
  }
  if (times == 0) return source;
  const fs::path folder = fs::temp_directory_path() / "harmonia_bench_io";
  const fs::path target = folder / ("face-x" + std::to_string(1 << (2 * times)) + ".obj");
  if (fs::exists(target)) return target;
  fs::create_directories(folder);
  const fs::path script = fs::path(HARMONIA_SHARED_TOOLS_DIR) / "subdivide.py";
  // Write under another name first so that an interrupted run leaves no partial target behind.
  const fs::path partial = target.string() + ".partial";
  const std::string command = "python3 '" + script.string() + "' '" + source.string() + "' '" +
                              partial.string() + "' --times " + std::to_string(times) +
                              " > /dev/null";
  if (std::system(command.c_str()) != 0 || !fs::exists(partial)) {
    reason = "could not run " + script.string();
    return {};
  }
  fs::rename(partial, target);
  return target;
}

void read_face_obj(benchmark::State& state) {
  std::string reason;
  const fs::path path = face_mesh(static_cast<int>(state.range(0)), reason);
  if (path.empty()) {
    state.SkipWithError(reason.c_str());
    return;
  }
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

BENCHMARK(read_face_obj)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
