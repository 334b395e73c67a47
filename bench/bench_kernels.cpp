// Kernel benchmarks on both backends, over the cotangent Dirichlet system of the face scan
// (bench_support.h: interior block of the cotangent Laplacian, boundary on the unit circle) at
// 1x, 4x and 16x its size (51,712 / 206,848 / 827,392 faces), with two right-hand sides (u, v):
//   copy    - a plain buffer copy on the backend: the memory bandwidth SpMV can hope for.
//   spmv    - effective bandwidth, counting each matrix byte once per column and x, y once.
//   dot     - the fixed-order reduction.
//   pcg     - Jacobi-PCG to --pcg_tolerance (default 1e-10, what the maps ask for): wall time,
//             iterations and the final residual (the CPU runs the Krylov loop of
//             host/backend/krylov.cpp over CpuBackend; Vulkan its fused device PCG, which in fp32
//             refines in double on the host).
//   cholmod - the reference: one supernodal CHOLMOD analyze + factorize + solve (the "floor").
// Vulkan runs in fp32 and, where the device has shaderFloat64, in fp64 (one context with
// ContextOptions::enable_float64). Vulkan kernel times are GPU times from timestamps
// (UseManualTime) where the queue has them. The device is the best one Vulkan offers, or the one
// whose name contains $HARMONIA_BENCH_VULKAN_DEVICE. On a software device (lavapipe) a PCG run
// whose estimated time exceeds --max_software_seconds (default 20) is skipped, saying why.
// Compare timings only on the same device.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "backend/backend.h"
#include "bench/bench_support.h"
#include "fallback/cpu_backend.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"

#ifdef HARMONIA_HAVE_VULKAN
#include "harmonia/vulkan_context.h"
#include "kernels/vulkan_backend.h"
#endif

namespace {

using harmonia::detail::Backend;
using harmonia::detail::RowMajorSparse;
namespace bench = harmonia::bench;

constexpr int block_columns = 2;
constexpr int size_factors[] = {1, 4, 16};

// Settings from the command line (see main).
double pcg_tolerance = 1e-10;
double max_software_seconds = 20.0;

// The cotangent Dirichlet system of the face scan at `factor` times its size.
struct KernelSystem {
  bench::DirichletSystem dirichlet;  // Column-major, as CHOLMOD takes it.
  RowMajorSparse matrix;             // The same, in the backends' CSR layout.
  int faces = 0;
};

// The system at `factor`, built once; null (with `message`) when the corpus is absent.
const KernelSystem* face_system(int factor, std::string* message) {
  static std::map<int, std::unique_ptr<KernelSystem>> cache;
  if (auto found = cache.find(factor); found != cache.end()) return found->second.get();
  const auto path =
      bench::scaled_mesh(bench::shared_data_dir() / "disk" / "face.obj", factor, message);
  if (!path) return nullptr;
  const harmonia::Mesh mesh = harmonia::read_mesh(*path);
  auto system = std::make_unique<KernelSystem>();
  system->dirichlet =
      bench::dirichlet_system(mesh, harmonia::laplacian(mesh, harmonia::WeightScheme::cotangent));
  system->matrix = system->dirichlet.interior_matrix;
  system->matrix.makeCompressed();
  system->faces = mesh.face_count();
  return cache.emplace(factor, std::move(system)).first->second.get();
}

// The system of the benchmark's size argument, or null after skipping the benchmark.
const KernelSystem* system_for(benchmark::State& state) {
  std::string message;
  const KernelSystem* system = face_system(static_cast<int>(state.range(0)), &message);
  if (system == nullptr) state.SkipWithError(message.c_str());
  return system;
}

void size_counters(benchmark::State& state, const KernelSystem& system) {
  state.counters["faces"] = system.faces;
  state.counters["rows"] = static_cast<double>(system.matrix.rows());
  state.counters["nonzeros"] = static_cast<double>(system.matrix.nonZeros());
}

Eigen::MatrixXd ones_block(Eigen::Index rows) { return Eigen::MatrixXd::Ones(rows, block_columns); }

// Bytes a CSR product y = A x over the block moves at least: values and column indices once per
// column of the block (the kernels walk the matrix per column), row offsets likewise, x and y once.
std::int64_t spmv_bytes(const RowMajorSparse& a, int value_bytes, int block_walks) {
  return block_walks * (a.nonZeros() * (value_bytes + 4) + (a.rows() + 1) * 4) +
         std::int64_t{block_columns} * (a.rows() + a.cols()) * value_bytes;
}

// Iterations of the CPU PCG per size factor, once measured (used to estimate device runs).
std::map<int, int>& cpu_pcg_iterations() {
  static std::map<int, int> iterations;
  return iterations;
}

harmonia::detail::IterativeSettings pcg_settings() {
  harmonia::detail::IterativeSettings settings;
  settings.relative_tolerance = pcg_tolerance;
  return settings;
}

// One PCG from x = 0 per benchmark iteration; wall time.
void run_pcg(benchmark::State& state, Backend& backend, const KernelSystem& system) {
  const auto matrix = backend.upload(system.matrix);
  const auto b = backend.upload(system.dirichlet.right_hand_sides);
  harmonia::detail::SolveStats stats;
  for (auto _ : state) {
    const auto x = backend.allocate(static_cast<int>(system.matrix.rows()), block_columns);
    stats = backend.pcg(*matrix, *b, *x, pcg_settings(), {});
    if (stats.status != harmonia::Status::ok) return state.SkipWithError(stats.message.c_str());
  }
  size_counters(state, system);
  state.counters["pcg_iterations"] = stats.iterations;
  state.counters["residual"] = stats.relative_residual;
  state.counters["tolerance"] = pcg_tolerance;
}

// ---------------------------------------------------------------------------------------------
// CPU (double)

void cpu_copy(benchmark::State& state) {
  const KernelSystem* system = system_for(state);
  if (system == nullptr) return;
  harmonia::detail::CpuBackend cpu;
  const Eigen::Index rows = system->matrix.rows();
  const auto x = cpu.upload(ones_block(rows));
  const auto y = cpu.allocate(static_cast<int>(rows), block_columns);
  for (auto _ : state) cpu.copy(*x, *y);
  state.SetBytesProcessed(state.iterations() * 2 * rows * block_columns * 8);
  size_counters(state, *system);
}

void cpu_spmv(benchmark::State& state) {
  const KernelSystem* system = system_for(state);
  if (system == nullptr) return;
  harmonia::detail::CpuBackend cpu;
  const auto matrix = cpu.upload(system->matrix);
  const auto x = cpu.upload(ones_block(system->matrix.cols()));
  const auto y = cpu.allocate(static_cast<int>(system->matrix.rows()), block_columns);
  for (auto _ : state) cpu.spmv(*matrix, *x, *y);
  // Eigen walks the matrix once for the whole block.
  state.SetBytesProcessed(state.iterations() * spmv_bytes(system->matrix, 8, 1));
  size_counters(state, *system);
}

void cpu_dot(benchmark::State& state) {
  const KernelSystem* system = system_for(state);
  if (system == nullptr) return;
  harmonia::detail::CpuBackend cpu;
  const Eigen::Index rows = system->matrix.rows();
  const auto x = cpu.upload(ones_block(rows));
  for (auto _ : state) benchmark::DoNotOptimize(cpu.dot(*x, *x));
  state.SetBytesProcessed(state.iterations() * 2 * rows * block_columns * 8);
  size_counters(state, *system);
}

void cpu_pcg(benchmark::State& state) {
  const KernelSystem* system = system_for(state);
  if (system == nullptr) return;
  harmonia::detail::CpuBackend cpu;
  run_pcg(state, cpu, *system);
  cpu_pcg_iterations()[static_cast<int>(state.range(0))] =
      static_cast<int>(state.counters["pcg_iterations"].value);
}

// The reference: CHOLMOD supernodal analyze + factorize + solve (manual time, nothing else).
void cholmod_reference(benchmark::State& state) {
  const KernelSystem* system = system_for(state);
  if (system == nullptr) return;
  bench::FloorMeasurement floor;
  for (auto _ : state) {
    floor = bench::measure_floor(system->dirichlet);
    if (!floor.available) return state.SkipWithError(floor.message.c_str());
    state.SetIterationTime(floor.total_seconds());
  }
  size_counters(state, *system);
  state.counters["factorize_ms"] = floor.factorize_seconds * 1e3;
  state.counters["residual"] = floor.relative_residual;
}

// ---------------------------------------------------------------------------------------------
// Vulkan (fp32 and fp64)

#ifdef HARMONIA_HAVE_VULKAN
using harmonia::DevicePrecision;
using harmonia::vulkan::detail::VulkanBackend;

// The benchmark context: created once, with shaderFloat64 where the device has it; null (with
// a note) when Vulkan has no device.
std::shared_ptr<harmonia::vulkan::Context> vulkan_context() {
  static std::shared_ptr<harmonia::vulkan::Context> context = [] {
    harmonia::vulkan::ContextOptions options;
    options.enable_float64 = true;
    if (const char* name = std::getenv("HARMONIA_BENCH_VULKAN_DEVICE")) options.device_name = name;
    try {
      auto created =
          std::make_shared<harmonia::vulkan::Context>(harmonia::vulkan::Context::create(options));
      const auto& device = created->device();
      std::cerr << "vulkan device: " << device.name << " ("
                << harmonia::vulkan::to_string(device.type) << ", subgroup " << device.subgroup_size
                << ", fp64 " << (device.float64_enabled ? "yes" : "no") << ")\n";
      return created;
    } catch (const harmonia::Error& error) {
      std::cerr << "no Vulkan device for the benchmarks: " << error.what() << '\n';
      return std::shared_ptr<harmonia::vulkan::Context>();
    }
  }();
  return context;
}

// The backend of `precision` on the benchmark context, or null after skipping the benchmark.
VulkanBackend* vulkan_backend(benchmark::State& state, DevicePrecision precision) {
  static std::map<DevicePrecision, std::unique_ptr<VulkanBackend>> backends;
  const auto context = vulkan_context();
  if (!context) {
    state.SkipWithError("no Vulkan device");
    return nullptr;
  }
  if (precision == DevicePrecision::float64 && !context->device().float64_enabled) {
    state.SkipWithError("the Vulkan device has no shaderFloat64");
    return nullptr;
  }
  auto& backend = backends[precision];
  if (!backend) backend = std::make_unique<VulkanBackend>(context, precision);
  return backend.get();
}

int value_bytes(DevicePrecision precision) { return precision == DevicePrecision::float64 ? 8 : 4; }

// GPU time of the last submission, or the wall time when the queue has no timestamps.
void set_time(benchmark::State& state, double gpu_seconds,
              std::chrono::steady_clock::time_point started) {
  const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - started;
  state.SetIterationTime(gpu_seconds > 0.0 ? gpu_seconds : wall.count());
}

void vulkan_copy(benchmark::State& state, DevicePrecision precision) {
  const KernelSystem* system = system_for(state);
  VulkanBackend* gpu = system == nullptr ? nullptr : vulkan_backend(state, precision);
  if (gpu == nullptr) return;
  const Eigen::Index rows = system->matrix.rows();
  const auto x = gpu->upload(ones_block(rows));
  const auto y = gpu->allocate(static_cast<int>(rows), block_columns);
  for (auto _ : state) {
    const auto started = std::chrono::steady_clock::now();
    gpu->copy(*x, *y);
    set_time(state, gpu->last_gpu_seconds(), started);
  }
  state.SetBytesProcessed(state.iterations() * 2 * rows * block_columns * value_bytes(precision));
  size_counters(state, *system);
}

void vulkan_spmv(benchmark::State& state, DevicePrecision precision) {
  const KernelSystem* system = system_for(state);
  VulkanBackend* gpu = system == nullptr ? nullptr : vulkan_backend(state, precision);
  if (gpu == nullptr) return;
  const auto matrix = gpu->upload(system->matrix);
  const auto x = gpu->upload(ones_block(system->matrix.cols()));
  const auto y = gpu->allocate(static_cast<int>(system->matrix.rows()), block_columns);
  for (auto _ : state) {
    const auto started = std::chrono::steady_clock::now();
    gpu->spmv(*matrix, *x, *y);
    set_time(state, gpu->last_gpu_seconds(), started);
  }
  state.SetBytesProcessed(state.iterations() *
                          spmv_bytes(system->matrix, value_bytes(precision), block_columns));
  size_counters(state, *system);
}

void vulkan_dot(benchmark::State& state, DevicePrecision precision) {
  const KernelSystem* system = system_for(state);
  VulkanBackend* gpu = system == nullptr ? nullptr : vulkan_backend(state, precision);
  if (gpu == nullptr) return;
  const Eigen::Index rows = system->matrix.rows();
  const auto x = gpu->upload(ones_block(rows));
  for (auto _ : state) {
    const auto started = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(gpu->dot(*x, *x));
    set_time(state, gpu->last_gpu_seconds(), started);
  }
  state.SetBytesProcessed(state.iterations() * 2 * rows * block_columns * value_bytes(precision));
  size_counters(state, *system);
}

// On a software device the 16x PCG takes minutes. Estimate the run from a short probe (a few
// iterations) times the iterations the CPU needed for the same system (the same Krylov method),
// or 4 sqrt(rows) when the CPU run was filtered out (Jacobi-PCG on a mesh Laplacian needs
// O(sqrt(rows)) iterations). Returns why to skip, or an empty string.
std::string software_device_skip_reason(VulkanBackend& gpu, const KernelSystem& system,
                                        int factor) {
  const auto& device = vulkan_context()->device();
  if (device.type != harmonia::vulkan::DeviceType::cpu) return {};
  const auto matrix = gpu.upload(system.matrix);
  const auto b = gpu.upload(system.dirichlet.right_hand_sides);
  const auto x = gpu.allocate(static_cast<int>(system.matrix.rows()), block_columns);
  harmonia::detail::IterativeSettings probe = pcg_settings();
  probe.max_iterations = 16;
  const auto started = std::chrono::steady_clock::now();
  const auto stats = gpu.pcg(*matrix, *b, *x, probe, {});
  const double probe_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double per_iteration = probe_seconds / std::max(stats.iterations, 1);
  const auto known = cpu_pcg_iterations().find(factor);
  const double iterations = known != cpu_pcg_iterations().end()
                                ? known->second
                                : 4.0 * std::sqrt(static_cast<double>(system.matrix.rows()));
  const double estimate = per_iteration * iterations;
  if (estimate <= max_software_seconds) return {};
  char text[256];
  std::snprintf(text, sizeof text,
                "skipped: software device %s, estimated %.0f s (%.0f iterations x %.1f ms) > "
                "--max_software_seconds=%.0f",
                device.name.c_str(), estimate, iterations, per_iteration * 1e3,
                max_software_seconds);
  return text;
}

void vulkan_pcg(benchmark::State& state, DevicePrecision precision) {
  const KernelSystem* system = system_for(state);
  VulkanBackend* gpu = system == nullptr ? nullptr : vulkan_backend(state, precision);
  if (gpu == nullptr) return;
  const std::string skip =
      software_device_skip_reason(*gpu, *system, static_cast<int>(state.range(0)));
  if (!skip.empty()) {
    std::cerr << "vulkan pcg x" << state.range(0) << ": " << skip << '\n';
    return state.SkipWithError(skip.c_str());
  }
  run_pcg(state, *gpu, *system);
}
#endif

// ---------------------------------------------------------------------------------------------

// Removes "--NAME=VALUE" from argv and returns VALUE, or null.
const char* take_flag(int* argc, char** argv, const char* name) {
  const std::string prefix = std::string("--") + name + "=";
  const char* value = nullptr;
  int kept = 1;
  for (int index = 1; index < *argc; ++index) {
    if (std::strncmp(argv[index], prefix.c_str(), prefix.size()) == 0) {
      value = argv[index] + prefix.size();
    } else {
      argv[kept++] = argv[index];
    }
  }
  *argc = kept;
  return value;
}

template <typename Function>
void register_sizes(const std::string& name, Function function, int max_size, bool manual_time,
                    benchmark::TimeUnit unit) {
  auto* registered = benchmark::RegisterBenchmark(name.c_str(), function);
  for (const int factor : size_factors) {
    if (factor <= max_size) registered->Arg(factor);
  }
  registered->ArgName("size")->Unit(unit);
  if (manual_time) registered->UseManualTime();
}

}  // namespace

// Flags of our own (removed before Google Benchmark sees argv): --max_size=N (or
// $HARMONIA_BENCH_MAX_SIZE; default 16), --pcg_tolerance=T (1e-10), --max_software_seconds=S (20).
int main(int argc, char** argv) {
  int max_size = 16;
  if (const char* from_environment = std::getenv("HARMONIA_BENCH_MAX_SIZE")) {
    max_size = std::atoi(from_environment);
  }
  if (const char* value = take_flag(&argc, argv, "max_size")) max_size = std::atoi(value);
  if (const char* value = take_flag(&argc, argv, "pcg_tolerance")) pcg_tolerance = std::atof(value);
  if (const char* value = take_flag(&argc, argv, "max_software_seconds")) {
    max_software_seconds = std::atof(value);
  }
  const auto micro = benchmark::kMicrosecond;
  const auto milli = benchmark::kMillisecond;
  register_sizes("cpu/copy", cpu_copy, max_size, false, micro);
  register_sizes("cpu/spmv", cpu_spmv, max_size, false, micro);
  register_sizes("cpu/dot", cpu_dot, max_size, false, micro);
  register_sizes("cpu/pcg", cpu_pcg, max_size, false, milli);
  register_sizes("cpu/cholmod", cholmod_reference, max_size, true, milli);
#ifdef HARMONIA_HAVE_VULKAN
  for (const auto& [suffix, precision] :
       {std::pair{"fp32", DevicePrecision::float32}, std::pair{"fp64", DevicePrecision::float64}}) {
    const std::string prefix = std::string("vulkan-") + suffix + "/";
    const DevicePrecision chosen = precision;
    register_sizes(
        prefix + "copy", [chosen](benchmark::State& s) { vulkan_copy(s, chosen); }, max_size, true,
        micro);
    register_sizes(
        prefix + "spmv", [chosen](benchmark::State& s) { vulkan_spmv(s, chosen); }, max_size, true,
        micro);
    register_sizes(
        prefix + "dot", [chosen](benchmark::State& s) { vulkan_dot(s, chosen); }, max_size, true,
        micro);
    register_sizes(
        prefix + "pcg", [chosen](benchmark::State& s) { vulkan_pcg(s, chosen); }, max_size, false,
        milli);
  }
#endif
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
