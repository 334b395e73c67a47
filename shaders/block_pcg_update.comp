#version 450
#extension GL_GOOGLE_include_directive : require
// One fused PCG step of a block-diagonal system, each row with the step length of its own
// system (block k of column c is system c * blocks + k): x += alpha p, r -= alpha q,
// z = inverse_diagonal .* r. Systems no longer active (converged or broken down) have alpha = 0
// (shaders/pcg_scalars.comp), and a zero step changes nothing, so their rows are skipped: they
// stay exactly as they were, and the NaN of a broken-down system's p cannot reach its x.
// Scalars are laid out as in shaders/pcg_scalars.comp with one "column" per system.
// C++ side: kernels/block_pcg.h (BlockPcgUpdatePush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer RowBlocks { uint row_blocks[]; };
layout(std430, binding = 1) readonly buffer Scalars { real scalars[]; };
layout(std430, binding = 2) readonly buffer InverseDiagonal { real inverse_diagonal[]; };
layout(std430, binding = 3) readonly buffer P { real p[]; };
layout(std430, binding = 4) readonly buffer Q { real q[]; };
layout(std430, binding = 5) buffer X { real x[]; };
layout(std430, binding = 6) buffer R { real r[]; };
layout(std430, binding = 7) writeonly buffer Z { real z[]; };

layout(push_constant) uniform Push {
  uint rows;
  uint blocks;
  uint alpha_index;  // alpha of system s is scalars[alpha_index + s].
} push;

void main() {
  const uint column = block_column();
  const uint base = column * push.rows;
  for (uint row = first_item(); row < push.rows; row += grid_stride()) {
    const real alpha = scalars[push.alpha_index + column * push.blocks + row_blocks[row]];
    if (alpha == 0.0) continue;
    const uint at = base + row;
    x[at] += alpha * p[at];
    const real residual = r[at] - alpha * q[at];
    r[at] = residual;
    z[at] = inverse_diagonal[row] * residual;
  }
}
