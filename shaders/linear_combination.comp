#version 450
#extension GL_GOOGLE_include_directive : require
// y = a x + b y per column, where a and b are constants times (optionally) per-column
// coefficients kept in a device buffer: axpy, xpay, copy and scale, and the PCG direction update
// with beta computed on the device. C++ side: kernels/vector_ops.h (LinearCombinationPush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer Coefficients { real coefficients[]; };
layout(std430, binding = 1) readonly buffer X { real x[]; };
layout(std430, binding = 2) buffer Y { real y[]; };

const uint alpha_from_buffer = 1u;  // a = alpha_factor * coefficients[alpha_index + column]
const uint beta_from_buffer = 2u;   // b = beta_factor * coefficients[beta_index + column]
const uint read_y = 4u;             // Without it y = a x (y is not read: copy).

layout(push_constant) uniform Push {
  uint rows;
  uint alpha_index;
  uint beta_index;
  uint flags;
  float alpha_factor;
  float beta_factor;
} push;

void main() {
  const uint column = block_column();
  real alpha = push.alpha_factor;
  if ((push.flags & alpha_from_buffer) != 0u) alpha *= coefficients[push.alpha_index + column];
  real beta = push.beta_factor;
  if ((push.flags & beta_from_buffer) != 0u) beta *= coefficients[push.beta_index + column];
  const uint base = column * push.rows;
  if ((push.flags & read_y) != 0u) {
    for (uint row = first_item(); row < push.rows; row += grid_stride())
      y[base + row] = alpha * x[base + row] + beta * y[base + row];
  } else {
    for (uint row = first_item(); row < push.rows; row += grid_stride())
      y[base + row] = alpha * x[base + row];
  }
}
