#version 450
#extension GL_GOOGLE_include_directive : require
// The per-column scalar work of Jacobi-PCG, on the device so that a batch of iterations needs no
// host round trip: step lengths, direction weights, convergence and breakdown flags.
// Layout (kernels/pcg.h, PcgField / PcgState): field f of column c is scalars[f * columns + c],
// state s of column c is state[s * columns + c]. One invocation per column.
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) buffer Scalars { real scalars[]; };
layout(std430, binding = 1) buffer State { uint state[]; };

// Float fields.
const uint field_rz = 0u;         // r . z of the current iterate.
const uint field_pq = 1u;         // p . A p.
const uint field_rz_next = 2u;    // r . z after the update.
const uint field_rr = 3u;         // r . r after the update (the residual norm squared).
const uint field_alpha = 4u;
const uint field_beta = 5u;
const uint field_threshold = 6u;  // Converged when rr <= threshold (squared absolute tolerance).
// Unsigned fields.
const uint state_active = 0u;      // 1 while the column iterates.
const uint state_iterations = 1u;  // Iterations the column took.
const uint state_failure = 2u;  // 0 ok, 1 p.Ap <= 0 (not positive definite), 2 non-finite r.r.

// Stages.
const uint start = 0u;         // After rz, rr of the initial residual: set the flags.
const uint step_length = 1u;   // After pq: alpha.
const uint next_direction = 2u;  // After rz_next, rr: beta, convergence.

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

void main() {
  for (uint column = first_item(); column < push.columns; column += grid_stride()) {
    if (push.stage == start) {
      const real residual = get(field_rr, column);
      put_state(state_iterations, column, 0u);
      put_state(state_failure, column, (isnan(residual) || isinf(residual)) ? 2u : 0u);
      put_state(state_active, column, residual > get(field_threshold, column) ? 1u : 0u);
    } else if (push.stage == step_length) {
      real step = 0.0;
      if (get_state(state_active, column) == 1u) {
        const real curvature = get(field_pq, column);
        if (curvature > 0.0 && !isinf(curvature)) {
          step = get(field_rz, column) / curvature;
        } else {
          put_state(state_failure, column, 1u);
          put_state(state_active, column, 0u);
        }
      }
      put(field_alpha, column, step);
    } else if (push.stage == next_direction) {
      real weight = 0.0;
      if (get_state(state_active, column) == 1u) {
        put_state(state_iterations, column, get_state(state_iterations, column) + 1u);
        const real previous = get(field_rz, column);
        const real next = get(field_rz_next, column);
        weight = previous != 0.0 ? next / previous : 0.0;
        put(field_rz, column, next);
        const real residual = get(field_rr, column);
        if (isnan(residual) || isinf(residual)) {
          put_state(state_failure, column, 2u);
          put_state(state_active, column, 0u);
        } else if (residual <= get(field_threshold, column)) {
          put_state(state_active, column, 0u);
        }
      }
      put(field_beta, column, weight);
    }
  }
}
