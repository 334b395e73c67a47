#version 450
#extension GL_GOOGLE_include_directive : require
// The per-column scalar work of MINRES (Paige and Saunders), on the device so that a batch of
// iterations needs no host round trip: the Lanczos coefficients, the Givens rotation that keeps
// the tridiagonal least-squares problem triangular, the weights of the direction and solution
// updates, convergence and breakdown flags. Same recurrences as Backend::minres
// (host/backend/krylov.cpp). Layout (kernels/minres.h, MinresField / MinresState): field f of
// column c is scalars[f * columns + c], state s of column c is state[s * columns + c]. One
// invocation per column.
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) buffer Scalars { real scalars[]; };
layout(std430, binding = 1) buffer State { uint state[]; };

// Float fields.
const uint field_vq = 0u;           // v_k . q: the Lanczos alpha_k (from the dot kernel).
const uint field_qq = 1u;           // q . q: beta_{k+1}^2 (beta_1^2 = |r0|^2 at the start).
const uint field_beta = 2u;         // beta_k, weight of v_{k-1} in q = A v_k - beta_k v_{k-1}.
const uint field_inverse_beta = 3u; // 1 / beta_{k+1}: normalizes q into v_{k+1} (0 when frozen).
const uint field_cs = 4u;           // The last Givens rotation (cosine, sine).
const uint field_sn = 5u;
const uint field_dbar = 6u;         // Entries of the rotated tridiagonal carried to the next step.
const uint field_epsilon = 7u;
const uint field_phibar = 8u;       // |phibar| = residual norm of the current iterate.
const uint field_old_epsilon = 9u;  // w_k = (v_k - old_epsilon w_{k-2} - delta w_{k-1}) / gamma.
const uint field_delta = 10u;
const uint field_inverse_gamma = 11u;
const uint field_phi = 12u;         // x += phi w_k.
const uint field_threshold = 13u;   // Converged when |phibar| <= threshold (absolute).
// Unsigned fields.
const uint state_active = 0u;      // 1 while the column iterates.
const uint state_iterations = 1u;  // Iterations the column took.
const uint state_failure = 2u;     // 0 ok, 1 a non-finite scalar.

// Stages.
const uint start = 0u;   // After qq = |b - A x0|^2: initial rotation and flags.
const uint rotate = 1u;  // After vq and qq of an iteration: rotation, update weights, flags.

#ifdef HARMONIA_FP64
const real smallest_normal = 2.2250738585072014e-308lf;
#else
const real smallest_normal = 1.17549435e-38;
#endif

layout(push_constant) uniform Push {
  uint columns;
  uint stage;
} push;

real get(uint field, uint column) { return scalars[field * push.columns + column]; }
void put(uint field, uint column, real value) { scalars[field * push.columns + column] = value; }
uint get_state(uint field, uint column) { return state[field * push.columns + column]; }
void put_state(uint field, uint column, uint value) {
  state[field * push.columns + column] = value;
}
bool finite(real value) { return !isnan(value) && !isinf(value); }

// sqrt(a^2 + b^2) without overflow or underflow of the squares.
real hypotenuse(real a, real b) {
  const real largest = max(abs(a), abs(b));
  if (largest == 0.0) return real(0.0);
  const real s = a / largest, t = b / largest;
  return largest * sqrt(s * s + t * t);
}

// A frozen column: every weight zero, so the vector kernels leave its x bit for bit and its
// Lanczos vectors at zero.
void freeze_weights(uint column) {
  put(field_beta, column, 0.0);
  put(field_inverse_beta, column, 0.0);
  put(field_old_epsilon, column, 0.0);
  put(field_delta, column, 0.0);
  put(field_inverse_gamma, column, 0.0);
  put(field_phi, column, 0.0);
}

void start_column(uint column) {
  const real beta = sqrt(max(get(field_qq, column), real(0.0)));
  put(field_beta, column, beta);
  put(field_phibar, column, beta);
  put(field_cs, column, -1.0);
  put(field_sn, column, 0.0);
  put(field_dbar, column, 0.0);
  put(field_epsilon, column, 0.0);
  put(field_old_epsilon, column, 0.0);
  put(field_delta, column, 0.0);
  put(field_inverse_gamma, column, 0.0);
  put(field_phi, column, 0.0);
  put_state(state_iterations, column, 0u);
  put_state(state_failure, column, finite(beta) ? 0u : 1u);
  const bool iterating = finite(beta) && beta > get(field_threshold, column);
  put_state(state_active, column, iterating ? 1u : 0u);
  put(field_inverse_beta, column, iterating ? real(1.0) / beta : real(0.0));
  if (!iterating) freeze_weights(column);
}

void rotate_column(uint column) {
  if (get_state(state_active, column) != 1u) {
    freeze_weights(column);
    return;
  }
  put_state(state_iterations, column, get_state(state_iterations, column) + 1u);
  const real alpha = get(field_vq, column);
  const real beta = sqrt(max(get(field_qq, column), real(0.0)));  // beta_{k+1}
  const real cs = get(field_cs, column), sn = get(field_sn, column);
  const real dbar = get(field_dbar, column);
  // Apply the previous rotation to the new column (beta_k, alpha_k, beta_{k+1}) of T_k.
  const real delta = cs * dbar + sn * alpha;
  const real gbar = sn * dbar - cs * alpha;
  put(field_old_epsilon, column, get(field_epsilon, column));
  put(field_delta, column, delta);
  put(field_epsilon, column, sn * beta);
  put(field_dbar, column, -cs * beta);
  // The new rotation annihilates beta_{k+1} below gbar.
  const real gamma = max(hypotenuse(gbar, beta), smallest_normal);
  const real next_cs = gbar / gamma, next_sn = beta / gamma;
  put(field_cs, column, next_cs);
  put(field_sn, column, next_sn);
  const real phibar = get(field_phibar, column);
  put(field_phi, column, next_cs * phibar);
  const real next_phibar = next_sn * phibar;
  put(field_phibar, column, next_phibar);
  put(field_inverse_gamma, column, real(1.0) / gamma);
  put(field_beta, column, beta);
  put(field_inverse_beta, column, beta > 0.0 ? real(1.0) / beta : real(0.0));

  if (!finite(next_phibar) || !finite(beta) || !finite(gamma) || !finite(delta)) {
    put_state(state_failure, column, 1u);
    put_state(state_active, column, 0u);
    freeze_weights(column);  // x keeps its last finite value.
  } else if (abs(next_phibar) <= get(field_threshold, column) || !(beta > 0.0)) {
    // Converged, or the Krylov space is exhausted (beta_{k+1} = 0): this step's update still
    // applies; the next iterations leave the column alone.
    put_state(state_active, column, 0u);
    put(field_beta, column, 0.0);
    put(field_inverse_beta, column, 0.0);
  }
}

void main() {
  for (uint column = first_item(); column < push.columns; column += grid_stride()) {
    if (push.stage == start)
      start_column(column);
    else if (push.stage == rotate)
      rotate_column(column);
  }
}
