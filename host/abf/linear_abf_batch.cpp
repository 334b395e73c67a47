// The first round of linear ABF of many meshes, their reduced angle systems solved as the
// diagonal blocks of one matrix by one Backend::block_pcg (abf/linear_abf_batch.h). Everything
// but the solve is linear_abf()'s own code: the linearized round and the finishing of a result
// (abf/linear_abf_round.h), the reduced system's assembly and back-substitution
// (abf/reduced_angle_system.h), the estimate and the validated reconstruction.

#include "abf/linear_abf_batch.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <utility>

#include "abf/angle_constraints.h"
#include "abf/linear_abf_estimate.h"
#include "abf/linear_abf_round.h"
#include "abf/reduced_angle_system.h"
#include "abf/validated_angles_to_uv.h"
#include "fallback/cpu_backend.h"
#include "fallback/single_threaded_blas.h"
#include "mesh/for_each_index.h"
#include "mesh/power_of_two_scale.h"
#include "planar/map_pipeline.h"

namespace harmonia::detail {
namespace {

// One mesh of the batch, from its validation to its result.
struct MeshRound {
  ScaledMesh unit;
  AngleMapResult result;
  bool in_batch = false;  // Validated and assembled: its system is a block of the batch.
  std::vector<int> loop;
  AngleTopology topology;
  Eigen::VectorXd spatial, estimate;
  LinearizedRound linearized;
  std::unique_ptr<ReducedAngleSystem> system;  // Assembled on the host (a CPU backend).
  RowMajorSparse matrix;                       // Its reduced matrix, until the batch is formed.
  Eigen::VectorXd rhs;
  bool final = false;
};

// Validation, estimate and the assembled reduced system of one mesh, as linear_abf() does them
// before its first round's solve (linear_abf.cpp).
void prepare(const Mesh& input, const LinearAbfOptions& options, Backend& assembly_backend,
             const IterativeSettings& settings, MeshRound& round) {
  round.unit = unit_scaled(input);
  const Mesh& mesh = round.unit.mesh;
  SolveReport& report = round.result.report;
  PhaseClock clock(report, {});
  (void)clock.start("validation");
  if (!validate_linear_abf_options(options, report)) return;
  if (!validate_mesh_arrays(mesh, report)) return;
  round.loop = validate_disk_topology(mesh, report);
  if (!report.ok()) return;
  (void)clock.start("estimate");
  round.topology = build_angle_topology(mesh, round.loop);
  round.spatial = corner_angles(mesh);
  round.estimate =
      linear_abf_estimate(mesh, round.topology, round.spatial, options.exponential_map_deficit);
  (void)clock.start("assembly");
  // The first round: centred at its own estimate, no boundary rows.
  round.linearized = linearize_round(round.topology, round.estimate, round.estimate);
  round.system =
      std::make_unique<ReducedAngleSystem>(assembly_backend, round.topology, settings, nullptr);
  round.system->assemble(round.linearized.constraints.jacobian, round.linearized.weights);
  round.matrix = round.system->reduced_matrix();
  round.rhs = round.system->reduced_right_hand_side(round.linearized.pull,
                                                    -round.linearized.constraints.values);
  round.in_batch = true;
}

// The diagonal blocks of the batch in one CSR matrix (every block's pattern as it is), and the
// right-hand sides one after the other. Each mesh's matrix is released once copied.
struct BlockSystem {
  RowMajorSparse matrix;
  Eigen::VectorXd rhs;
  BlockRows blocks;
};

BlockSystem block_system(std::vector<MeshRound>& rounds) {
  BlockSystem system;
  system.blocks.offsets.push_back(0);
  Eigen::Index entries = 0;
  for (const MeshRound& round : rounds) {
    if (!round.in_batch) continue;
    system.blocks.offsets.push_back(system.blocks.offsets.back() +
                                    static_cast<int>(round.matrix.rows()));
    entries += round.matrix.nonZeros();
  }
  const int rows = system.blocks.offsets.back();
  system.matrix.resize(rows, rows);
  system.matrix.resizeNonZeros(entries);
  system.rhs.resize(rows);
  int* outer = system.matrix.outerIndexPtr();
  int* inner = system.matrix.innerIndexPtr();
  double* values = system.matrix.valuePtr();
  outer[0] = 0;
  int row = 0, entry = 0;
  for (MeshRound& round : rounds) {
    if (!round.in_batch) continue;
    RowMajorSparse& block = round.matrix;
    block.makeCompressed();
    const int first = row;
    for (Eigen::Index r = 0; r < block.rows(); ++r, ++row) {
      for (int e = block.outerIndexPtr()[r]; e < block.outerIndexPtr()[r + 1]; ++e, ++entry) {
        inner[entry] = first + block.innerIndexPtr()[e];
        values[entry] = block.valuePtr()[e];
      }
      outer[row + 1] = entry;
    }
    system.rhs.segment(first, block.rows()) = round.rhs;
    block = RowMajorSparse();
  }
  return system;
}

// What every result of the batch says of the solve (read once, not from the workers).
struct BatchSolve {
  BackendKind backend = BackendKind::cpu;
  std::string device, solver;
  double cross_check_error = 0.0;
  double seconds = 0.0;
  int block_count = 0;
};

// From the block's solution nu to the angles and, where they are valid, the layout; `final`
// where linear_abf() would stop after this round (see the header).
void finish(const LinearAbfOptions& options, const BatchSolve& batch, const BlockSystemStats& solve,
            const Eigen::VectorXd& nu, MeshRound& round) {
  AngleMapResult& result = round.result;
  SolveReport& report = result.report;
  report.rounds = 1;
  report.iterations = solve.iterations;
  report.residual = solve.relative_residual;
  report.solver = batch.solver;
  report.backend = batch.backend;
  report.device = batch.device;
  if (batch.backend == BackendKind::vulkan) report.precision = "float (refined in double)";
  report.timings.push_back(PhaseTiming{
      "block_pcg (shared by " + std::to_string(batch.block_count) + ")", batch.seconds});
  if (!linear_abf_solve_accepted(solve.status, solve.relative_residual)) return;
  PhaseClock clock(report, {});
  (void)clock.start("back-substitution");
  const LinearizedRound& linearized = round.linearized;
  Eigen::VectorXd error, multipliers;
  // e = W (r - A^T x) with (A W A^T) x = A W r - b; for r = 0, (3.12-3.13).
  round.system->back_substitute(linearized.pull, -linearized.constraints.values, nu, error,
                                multipliers);
  round.system.reset();
  const Eigen::VectorXd angles = round.estimate + error;  // (3.1)
  if (first_invalid_corner(angles) >= 0) return;
  (void)clock.start("reconstruction");
  // The layout's least-squares system is small: factorized directly on the CPU.
  AnglesToUvOptions reconstruction = options.reconstruction;
  reconstruction.solver = options.solver_options;
  reconstruction.solver.backend = BackendChoice::cpu;
  reconstruction.solver.progress = nullptr;
  const std::vector<int> no_ordering;  // The layout's solver orders its unknowns itself.
  MapResult layout = angles_to_uv_validated(round.unit.mesh, corner_rows(angles), reconstruction,
                                            {round.loop, no_ordering, nullptr});
  clock.stop();
  const bool good = layout.report.ok() && (!options.avoid_boundary_crossings ||
                                           layout.report.boundary_self_intersections == 0);
  if (!good) return;
  finish_linear_abf_result(angles, std::move(layout),
                           summarize_linear_abf_angles(round.topology, round.spatial, angles), -1,
                           batch.cross_check_error, result);
  to_model_units(result.uv, round.unit.scale, options.reconstruction.normalization, true);
  round.final = result.report.ok();
}

int thread_count(int requested) {
  if (requested > 0) return requested;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

}  // namespace

std::vector<std::optional<AngleMapResult>> linear_abf_first_rounds(
    const std::vector<const Mesh*>& meshes, const LinearAbfOptions& options, Backend& backend,
    int threads) {
  const auto count = static_cast<int>(meshes.size());
  std::vector<std::optional<AngleMapResult>> results(meshes.size());
  if (options.rounds > 1) return results;  // Several rounds asked for: linear_abf()'s own.
  threads = thread_count(threads);
  // CHOLMOD's calls on several threads at once would queue for OpenBLAS's one pool
  // (fallback/single_threaded_blas.h).
  std::optional<SingleThreadedBlas> single_threaded_blas;
  if (threads > 1 && SingleThreadedBlas::allowed()) single_threaded_blas.emplace();

  IterativeSettings settings;
  settings.relative_tolerance = options.solver_options.tolerance;
  settings.max_iterations = options.solver_options.max_iterations;
  CpuBackend assembly_backend;  // The reduced matrices are assembled on the host.
  std::vector<MeshRound> rounds(meshes.size());
  for_each_index(count, threads, [&](int i) {
    prepare(*meshes[static_cast<std::size_t>(i)], options, assembly_backend, settings,
            rounds[static_cast<std::size_t>(i)]);
  });

  BlockSystem system = block_system(rounds);
  const int block_count = system.blocks.count();
  BlockSolveStats stats;
  Eigen::VectorXd solution = Eigen::VectorXd::Zero(system.matrix.rows());
  double solve_seconds = 0.0;
  stats.block_count = block_count;
  stats.systems.resize(static_cast<std::size_t>(block_count));  // Empty blocks: nothing to solve.
  if (system.matrix.rows() > 0) {
    const auto started = std::chrono::steady_clock::now();
    const std::unique_ptr<DeviceMatrix> matrix = backend.upload(system.matrix);
    system.matrix = RowMajorSparse();  // The backend keeps its own copy on the host.
    const std::unique_ptr<DeviceVectors> rhs = backend.upload(system.rhs);
    const std::unique_ptr<DeviceVectors> x =
        backend.allocate(static_cast<int>(system.rhs.size()), 1);
    stats = backend.block_pcg(*matrix, system.blocks, *rhs, *x, settings,
                              options.solver_options.progress);
    solution = x->download().col(0);
    solve_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  }
  BatchSolve batch;
  batch.backend = backend.kind();
  batch.device = backend.description();
  batch.cross_check_error = backend.cross_check_error();
  batch.seconds = solve_seconds;
  batch.block_count = block_count;
  batch.solver = "block-pcg-jacobi (reduced, " + std::to_string(block_count) +
                 (block_count == 1 ? " mesh" : " meshes") + " in one solve)";
  const bool cancelled = stats.status == Status::cancelled;
  const bool refused = stats.status == Status::invalid_input;  // Not block diagonal: a bug.

  std::vector<int> block_of(meshes.size(), -1);
  for (int i = 0, block = 0; i < count; ++i)
    if (rounds[static_cast<std::size_t>(i)].in_batch)
      block_of[static_cast<std::size_t>(i)] = block++;
  for_each_index(count, threads, [&](int i) {
    MeshRound& round = rounds[static_cast<std::size_t>(i)];
    const int block = block_of[static_cast<std::size_t>(i)];
    if (block < 0 || cancelled || refused) return;
    finish(options, batch, stats.system(block),
           solution.segment(system.blocks.begin(block), system.blocks.size(block)), round);
  });

  for (int i = 0; i < count; ++i) {
    MeshRound& round = rounds[static_cast<std::size_t>(i)];
    if (!round.in_batch) {
      results[static_cast<std::size_t>(i)] = std::move(round.result);  // Refused, as linear_abf.
    } else if (cancelled) {
      AngleMapResult& result = results[static_cast<std::size_t>(i)].emplace();
      result.report.status = Status::cancelled;
      result.report.message = "linear_abf: " + stats.message;
    } else if (round.final) {
      results[static_cast<std::size_t>(i)] = std::move(round.result);
    }
  }
  return results;
}

std::vector<AngleMapResult> linear_abf_batch(const std::vector<const Mesh*>& meshes,
                                             const LinearAbfOptions& options, Backend& backend,
                                             int threads) {
  std::vector<std::optional<AngleMapResult>> first =
      linear_abf_first_rounds(meshes, options, backend, threads);
  std::vector<AngleMapResult> results(meshes.size());
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    if (first[i]) {
      results[i] = std::move(*first[i]);
    } else {
      results[i] = linear_abf(*meshes[i], options);
    }
  }
  return results;
}

}  // namespace harmonia::detail
