#version 450
#extension GL_GOOGLE_include_directive : require
// One fused PCG step per column with alpha from the device: x += alpha p, r -= alpha q,
// z = inverse_diagonal .* r. C++ side: kernels/pcg.h (PcgUpdatePush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer Scalars { real scalars[]; };
layout(std430, binding = 1) readonly buffer InverseDiagonal { real inverse_diagonal[]; };
layout(std430, binding = 2) readonly buffer P { real p[]; };
layout(std430, binding = 3) readonly buffer Q { real q[]; };
layout(std430, binding = 4) buffer X { real x[]; };
layout(std430, binding = 5) buffer R { real r[]; };
layout(std430, binding = 6) writeonly buffer Z { real z[]; };

layout(push_constant) uniform Push {
  uint rows;
  uint alpha_index;  // alpha of column c is scalars[alpha_index + c].
} push;

void main() {
  const uint column = block_column();
  const real alpha = scalars[push.alpha_index + column];
  const uint base = column * push.rows;
  for (uint row = first_item(); row < push.rows; row += grid_stride()) {
    const uint at = base + row;
    x[at] += alpha * p[at];
    const real residual = r[at] - alpha * q[at];
    r[at] = residual;
    z[at] = inverse_diagonal[row] * residual;
  }
}
