#pragma once
// Internal: Jacobi-preconditioned conjugate gradients run on the device (fp32 or fp64), several
// iterations per submission (shaders/pcg_update.comp, shaders/pcg_scalars.comp with the SpMV,
// dot and vector kernels). The step lengths, direction weights, residual norms and convergence
// flags of every column live in device buffers; the host reads them back only every
// `check_every` iterations. Eigen twin: the PCG loop of host/backend/krylov.cpp.

#include <cstddef>
#include <cstdint>

#include "backend/backend.h"
#include "kernels/device_arrays.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

// Mirrors `Push` in shaders/pcg_update.comp.
struct PcgUpdatePush {
  std::uint32_t rows;
  std::uint32_t alpha_index;
};
static_assert(sizeof(PcgUpdatePush) == 8 && offsetof(PcgUpdatePush, alpha_index) == 4);

// Mirrors `Push` in shaders/pcg_scalars.comp.
struct PcgScalarsPush {
  std::uint32_t columns;
  std::uint32_t stage;  // A PcgStage.
};
static_assert(sizeof(PcgScalarsPush) == 8 && offsetof(PcgScalarsPush, stage) == 4);

enum class PcgUpdateBinding : std::uint32_t { scalars, inverse_diagonal, p, q, x, r, z, count };
enum class PcgScalarsBinding : std::uint32_t { scalars, state, count };

// Float fields of the scalars buffer (field f of column c at f * columns + c), as in the shader.
enum PcgField : std::uint32_t { rz, pq, rz_next, rr, alpha, beta, threshold, field_count };
// Unsigned fields of the state buffer.
enum PcgState : std::uint32_t { active, iterations, failure, state_count };
enum class PcgStage : std::uint32_t { start, step_length, next_direction };
enum class PcgFailure : std::uint32_t { none, not_positive_definite, not_finite };

extern const KernelProgram pcg_update_program;
extern const KernelProgram pcg_scalars_program;

struct DevicePcgResult {
  int iterations = 0;      // Most iterations any column took.
  bool cancelled = false;  // The progress callback returned false.
  PcgFailure failure = PcgFailure::none;
  int failed_column = -1;
};

// Solves A x = b from the warm start in x, on the device in the blocks' precision. Column c
// stops when its recursive residual norm is at most thresholds[c] (absolute). At most
// max_iterations iterations; residuals are read back every check_every iterations, which is also
// when `progress` is called (steps offset by progress_offset, out of progress_total).
[[nodiscard]] DevicePcgResult run_device_pcg(Context::Impl& context, const VulkanMatrix& a,
                                             const VulkanVectors& b, VulkanVectors& x,
                                             const Eigen::VectorXd& thresholds, int max_iterations,
                                             int check_every, const ProgressCallback& progress,
                                             int progress_offset, int progress_total);

}  // namespace harmonia::vulkan::detail
