#pragma once
// Internal: MINRES (Paige and Saunders) run on the device (fp32 or fp64), several iterations per
// submission (shaders/minres_scalars.comp, shaders/minres_update.comp with the SpMV, dot and
// vector kernels). The Lanczos vectors, the search directions, the rotation scalars and the
// convergence flags of every column live in device buffers; the host reads the flags back only
// every `check_every` iterations. Unpreconditioned, as the Eigen twin (Backend::minres in
// host/backend/krylov.cpp): a Jacobi preconditioner must be SPD, which the diagonal of an
// indefinite matrix need not be.
//
// One iteration, per column (v_k of unit norm, v_0 = 0):
//   q = A v_k - beta_k v_{k-1};  alpha_k = v_k . q;  q -= alpha_k v_k;  beta_{k+1} = |q|
//   rotate (alpha_k, beta_{k+1}) into the triangular factor; w_k, x += phi_k w_k
//   v_{k-1} <- v_k, v_k <- q / beta_{k+1}
// (the modified Gram-Schmidt form of the Lanczos step). |phibar_k| is the residual norm of x_k.

#include <cstddef>
#include <cstdint>

#include "backend/backend.h"
#include "kernels/device_arrays.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

// Mirrors `Push` in shaders/minres_scalars.comp.
struct MinresScalarsPush {
  std::uint32_t columns;
  std::uint32_t stage;  // A MinresStage.
};
static_assert(sizeof(MinresScalarsPush) == 8 && offsetof(MinresScalarsPush, stage) == 4);

// Mirrors `Push` in shaders/minres_update.comp.
struct MinresUpdatePush {
  std::uint32_t rows;
  std::uint32_t columns;
};
static_assert(sizeof(MinresUpdatePush) == 8 && offsetof(MinresUpdatePush, columns) == 4);

enum class MinresScalarsBinding : std::uint32_t { scalars, state, count };
enum class MinresUpdateBinding : std::uint32_t {
  scalars,
  x,
  previous_v,
  v,
  q,
  older_w,
  old_w,
  count
};

// Float fields of the scalars buffer (field f of column c at f * columns + c), as in the shaders.
enum class MinresField : std::uint32_t {
  vq,             // v_k . q (the Lanczos alpha_k).
  qq,             // q . q (beta_{k+1}^2; |r0|^2 at the start).
  beta,           // beta_k.
  inverse_beta,   // 1 / beta_{k+1} (0 when frozen).
  cs,             // The last Givens rotation.
  sn,
  dbar,           // Rotated tridiagonal entries carried to the next step.
  epsilon,
  phibar,         // Residual norm of the current iterate.
  old_epsilon,    // Weights of w_k = (v_k - old_epsilon w_{k-2} - delta w_{k-1}) / gamma.
  delta,
  inverse_gamma,
  phi,            // x += phi w_k.
  threshold,      // Converged when |phibar| <= threshold.
  count
};
// Unsigned fields of the state buffer.
enum class MinresState : std::uint32_t { active, iterations, failure, count };
enum class MinresStage : std::uint32_t { start, rotate };
enum class MinresFailure : std::uint32_t { none, not_finite };

extern const KernelProgram minres_scalars_program;
extern const KernelProgram minres_update_program;

struct DeviceMinresResult {
  int iterations = 0;      // Most iterations any column took.
  bool cancelled = false;  // The progress callback returned false.
  MinresFailure failure = MinresFailure::none;
  int failed_column = -1;
  Eigen::VectorXd residual_estimates;  // |phibar| per column at the end (absolute).
};

// Solves A x = b (A symmetric, possibly indefinite or singular) from the warm start in x, on the
// device in the blocks' precision. Column c stops when its residual estimate |phibar| is at most
// thresholds[c] (absolute) or its Krylov space is exhausted. At most max_iterations iterations;
// the flags are read back every check_every iterations, which is also when `progress` is called
// (steps offset by progress_offset, out of progress_total).
[[nodiscard]] DeviceMinresResult run_device_minres(Context::Impl& context, const VulkanMatrix& a,
                                                   const VulkanVectors& b, VulkanVectors& x,
                                                   const Eigen::VectorXd& thresholds,
                                                   int max_iterations, int check_every,
                                                   const ProgressCallback& progress,
                                                   int progress_offset, int progress_total);

}  // namespace harmonia::vulkan::detail
