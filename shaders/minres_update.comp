#version 450
#extension GL_GOOGLE_include_directive : require
// One fused MINRES vector step per column with the weights from the device
// (shaders/minres_scalars.comp): the new direction w_k = (v_k - old_epsilon w_{k-2} - delta
// w_{k-1}) / gamma, x += phi w_k, the directions shifted (w_{k-2} <- w_{k-1} <- w_k) and the
// Lanczos vectors shifted (v_{k-1} <- v_k <- q / beta_{k+1}). Everything is per element, so the
// shifts happen in place and a recorded batch never swaps buffers. C++ side: kernels/minres.h.
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer Scalars { real scalars[]; };
layout(std430, binding = 1) buffer X { real x[]; };
layout(std430, binding = 2) buffer PreviousV { real previous_v[]; };
layout(std430, binding = 3) buffer V { real v[]; };
layout(std430, binding = 4) readonly buffer Q { real q[]; };
layout(std430, binding = 5) buffer OlderW { real older_w[]; };  // w_{k-2}
layout(std430, binding = 6) buffer OldW { real old_w[]; };      // w_{k-1}

// The fields read here (kernels/minres.h, MinresField).
const uint field_inverse_beta = 3u;
const uint field_old_epsilon = 9u;
const uint field_delta = 10u;
const uint field_inverse_gamma = 11u;
const uint field_phi = 12u;

layout(push_constant) uniform Push {
  uint rows;
  uint columns;
} push;

void main() {
  const uint column = block_column();
  const real inverse_beta = scalars[field_inverse_beta * push.columns + column];
  const real old_epsilon = scalars[field_old_epsilon * push.columns + column];
  const real delta = scalars[field_delta * push.columns + column];
  const real inverse_gamma = scalars[field_inverse_gamma * push.columns + column];
  const real phi = scalars[field_phi * push.columns + column];
  const uint base = column * push.rows;
  for (uint row = first_item(); row < push.rows; row += grid_stride()) {
    const uint at = base + row;
    const real lanczos = v[at];
    const real previous_direction = old_w[at];
    const real direction =
        (lanczos - old_epsilon * older_w[at] - delta * previous_direction) * inverse_gamma;
    older_w[at] = previous_direction;
    old_w[at] = direction;
    x[at] += phi * direction;
    previous_v[at] = lanczos;
    v[at] = q[at] * inverse_beta;
  }
}
