// Kernel benchmarks on both backends, over mesh Laplacians at 1x, 4x and 16x (hemisphere(50),
// (100), (200): 7.6k, 30k, 121k rows; with two right-hand sides, u and v):
//   Copy    - a plain buffer copy kernel on the device: the memory bandwidth SpMV can hope for.
//   Spmv    - effective bandwidth counting each matrix byte once and x, y once.
//   Dot     - the two-pass tree reduction.
//   Pcg     - Jacobi-PCG to 1e-6 (fp32's reach): time and iterations.
// Vulkan kernel times are GPU times from timestamps (UseManualTime) where the queue has them;
// PCG is wall time. The device is the best one Vulkan offers, or the one whose name contains
// $HARMONIA_BENCH_VULKAN_DEVICE (the harness chooses; the library never reads the environment).
// Compare timings only on the same device.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <map>
#include <memory>

#include "detail/backend.h"
#include "fallback/cpu_backend.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"

#ifdef HARMONIA_HAVE_VULKAN
#include "harmonia/vulkan_context.h"
#include "kernels/vulkan_backend.h"
#endif

namespace {

using harmonia::detail::Backend;
using harmonia::detail::RowMajorSparse;

constexpr int block_columns = 2;

// L + 1e-3 I of the hemisphere with `rings` rings (SPD), cached per size.
const RowMajorSparse& mesh_matrix(int rings) {
  static std::map<int, RowMajorSparse> cache;
  auto found = cache.find(rings);
  if (found == cache.end()) {
    Eigen::SparseMatrix<double> l =
        harmonia::laplacian(harmonia::hemisphere(rings), harmonia::WeightScheme::cotangent);
    Eigen::SparseMatrix<double> identity(l.rows(), l.cols());
    identity.setIdentity();
    RowMajorSparse matrix = l + 1e-3 * identity;
    matrix.makeCompressed();
    found = cache.emplace(rings, std::move(matrix)).first;
  }
  return found->second;
}

Eigen::MatrixXd ones_block(Eigen::Index rows) { return Eigen::MatrixXd::Ones(rows, block_columns); }

#ifdef HARMONIA_HAVE_VULKAN
// The benchmark device: created once; null (with a note) when Vulkan has none.
harmonia::vulkan::detail::VulkanBackend* vulkan_backend() {
  static std::unique_ptr<harmonia::vulkan::detail::VulkanBackend> backend = [] {
    harmonia::vulkan::ContextOptions options;
    if (const char* name = std::getenv("HARMONIA_BENCH_VULKAN_DEVICE")) options.device_name = name;
    try {
      auto context =
          std::make_shared<harmonia::vulkan::Context>(harmonia::vulkan::Context::create(options));
      std::cerr << "vulkan device: " << context->device().name << " ("
                << harmonia::vulkan::to_string(context->device().type) << ", subgroup "
                << context->device().subgroup_size << ")\n";
      return std::make_unique<harmonia::vulkan::detail::VulkanBackend>(std::move(context));
    } catch (const harmonia::Error& error) {
      std::cerr << "no Vulkan device for the benchmarks: " << error.what() << '\n';
      return std::unique_ptr<harmonia::vulkan::detail::VulkanBackend>();
    }
  }();
  return backend.get();
}

// GPU time of the last submission, or the wall time when the queue has no timestamps.
void set_time(benchmark::State& state, double gpu_seconds,
              std::chrono::steady_clock::time_point started) {
  const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - started;
  state.SetIterationTime(gpu_seconds > 0.0 ? gpu_seconds : wall.count());
}

void BM_VulkanCopy(benchmark::State& state) {
  auto* gpu = vulkan_backend();
  if (gpu == nullptr) return state.SkipWithError("no Vulkan device");
  const Eigen::Index rows = mesh_matrix(static_cast<int>(state.range(0))).rows();
  const auto x = gpu->upload(ones_block(rows));
  const auto y = gpu->allocate(static_cast<int>(rows), block_columns);
  for (auto _ : state) {
    const auto started = std::chrono::steady_clock::now();
    gpu->copy(*x, *y);
    set_time(state, gpu->last_gpu_seconds(), started);
  }
  state.SetBytesProcessed(state.iterations() * 2 * rows * block_columns * 4);
}

void BM_VulkanSpmv(benchmark::State& state) {
  auto* gpu = vulkan_backend();
  if (gpu == nullptr) return state.SkipWithError("no Vulkan device");
  const RowMajorSparse& a = mesh_matrix(static_cast<int>(state.range(0)));
  const auto matrix = gpu->upload(a);
  const auto x = gpu->upload(ones_block(a.cols()));
  const auto y = gpu->allocate(static_cast<int>(a.rows()), block_columns);
  for (auto _ : state) {
    const auto started = std::chrono::steady_clock::now();
    gpu->spmv(*matrix, *x, *y);
    set_time(state, gpu->last_gpu_seconds(), started);
  }
  // Values and column indices (4 + 4 bytes) and row offsets once per column of the block, x and
  // y once: the least traffic a CSR product can have.
  const std::int64_t bytes = block_columns * (a.nonZeros() * 8 + (a.rows() + 1) * 4) +
                             block_columns * (a.rows() + a.cols()) * 4;
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["rows"] = static_cast<double>(a.rows());
}

void BM_VulkanDot(benchmark::State& state) {
  auto* gpu = vulkan_backend();
  if (gpu == nullptr) return state.SkipWithError("no Vulkan device");
  const Eigen::Index rows = mesh_matrix(static_cast<int>(state.range(0))).rows();
  const auto x = gpu->upload(ones_block(rows));
  for (auto _ : state) {
    const auto started = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(gpu->dot(*x, *x));
    set_time(state, gpu->last_gpu_seconds(), started);
  }
  state.SetBytesProcessed(state.iterations() * 2 * rows * block_columns * 4);
}
#endif

void run_pcg(benchmark::State& state, Backend& backend) {
  const RowMajorSparse& a = mesh_matrix(static_cast<int>(state.range(0)));
  const auto matrix = backend.upload(a);
  const Eigen::MatrixXd rhs = a * ones_block(a.cols());
  const auto b = backend.upload(rhs);
  harmonia::detail::IterativeSettings settings;
  settings.relative_tolerance = 1e-6;
  int iterations = 0;
  for (auto _ : state) {
    const auto x = backend.allocate(static_cast<int>(a.rows()), block_columns);
    const auto stats = backend.pcg(*matrix, *b, *x, settings, {});
    if (stats.status != harmonia::Status::ok) return state.SkipWithError(stats.message.c_str());
    iterations = stats.iterations;
  }
  state.counters["rows"] = static_cast<double>(a.rows());
  state.counters["pcg_iterations"] = iterations;
}

#ifdef HARMONIA_HAVE_VULKAN
void BM_VulkanPcg(benchmark::State& state) {
  auto* gpu = vulkan_backend();
  if (gpu == nullptr) return state.SkipWithError("no Vulkan device");
  run_pcg(state, *gpu);
}
#endif

void BM_CpuSpmv(benchmark::State& state) {
  harmonia::detail::CpuBackend cpu;
  const RowMajorSparse& a = mesh_matrix(static_cast<int>(state.range(0)));
  const auto matrix = cpu.upload(a);
  const auto x = cpu.upload(ones_block(a.cols()));
  const auto y = cpu.allocate(static_cast<int>(a.rows()), block_columns);
  for (auto _ : state) cpu.spmv(*matrix, *x, *y);
  // Double values (8) and int indices (4); Eigen walks the matrix once for the whole block.
  const std::int64_t bytes =
      a.nonZeros() * 12 + (a.rows() + 1) * 4 + block_columns * (a.rows() + a.cols()) * 8;
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["rows"] = static_cast<double>(a.rows());
}

void BM_CpuCopy(benchmark::State& state) {
  harmonia::detail::CpuBackend cpu;
  const Eigen::Index rows = mesh_matrix(static_cast<int>(state.range(0))).rows();
  const auto x = cpu.upload(ones_block(rows));
  const auto y = cpu.allocate(static_cast<int>(rows), block_columns);
  for (auto _ : state) cpu.copy(*x, *y);
  state.SetBytesProcessed(state.iterations() * 2 * rows * block_columns * 8);
}

void BM_CpuDot(benchmark::State& state) {
  harmonia::detail::CpuBackend cpu;
  const Eigen::Index rows = mesh_matrix(static_cast<int>(state.range(0))).rows();
  const auto x = cpu.upload(ones_block(rows));
  for (auto _ : state) benchmark::DoNotOptimize(cpu.dot(*x, *x));
  state.SetBytesProcessed(state.iterations() * 2 * rows * block_columns * 8);
}

void BM_CpuPcg(benchmark::State& state) {
  harmonia::detail::CpuBackend cpu;
  run_pcg(state, cpu);
}

}  // namespace

// 1x, 4x, 16x rows.
#define HARMONIA_MESH_SIZES ->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMicrosecond)

#ifdef HARMONIA_HAVE_VULKAN
BENCHMARK(BM_VulkanCopy) HARMONIA_MESH_SIZES->UseManualTime();
BENCHMARK(BM_VulkanSpmv) HARMONIA_MESH_SIZES->UseManualTime();
BENCHMARK(BM_VulkanDot) HARMONIA_MESH_SIZES->UseManualTime();
BENCHMARK(BM_VulkanPcg) HARMONIA_MESH_SIZES->Unit(benchmark::kMillisecond)->Iterations(1);
#endif
BENCHMARK(BM_CpuCopy) HARMONIA_MESH_SIZES;
BENCHMARK(BM_CpuSpmv) HARMONIA_MESH_SIZES;
BENCHMARK(BM_CpuDot) HARMONIA_MESH_SIZES;
BENCHMARK(BM_CpuPcg) HARMONIA_MESH_SIZES->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
