#version 450
#extension GL_GOOGLE_include_directive : require
// The next search direction of a block-diagonal system, each row with the direction weight of
// its own system (block k of column c is system c * blocks + k): p = z + beta p. Rows of systems
// no longer active (state, as in shaders/pcg_scalars.comp) are left alone, as in
// shaders/block_pcg_update.comp; here the flag is read, since beta = 0 is a legitimate weight.
// C++ side: kernels/block_pcg.h (BlockPcgDirectionPush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer RowBlocks { uint row_blocks[]; };
layout(std430, binding = 1) readonly buffer State { uint state[]; };
layout(std430, binding = 2) readonly buffer Scalars { real scalars[]; };
layout(std430, binding = 3) readonly buffer Z { real z[]; };
layout(std430, binding = 4) buffer P { real p[]; };

layout(push_constant) uniform Push {
  uint rows;
  uint blocks;
  uint beta_index;    // beta of system s is scalars[beta_index + s].
  uint active_index;  // 1 in state[active_index + s] while system s iterates.
} push;

void main() {
  const uint column = block_column();
  const uint base = column * push.rows;
  for (uint row = first_item(); row < push.rows; row += grid_stride()) {
    const uint system = column * push.blocks + row_blocks[row];
    if (state[push.active_index + system] != 1u) continue;
    const uint at = base + row;
    p[at] = z[at] + scalars[push.beta_index + system] * p[at];
  }
}
