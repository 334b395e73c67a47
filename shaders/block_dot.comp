#version 450
#extension GL_GOOGLE_include_directive : require
// Segmented dot products of a block-diagonal system: one sum per diagonal block per column,
// results[result_offset + column * blocks + block] = sum of a[i] b[i] over the block's rows. One
// workgroup per block (striding over the blocks when they outnumber the grid): each invocation sums
// its rows in order, then a tree, so the order is fixed and the result the same on every run.
// Blocks are meant to be small (texture-atlas charts); a block far larger than the others
// serializes on its one workgroup. C++ side: kernels/block_pcg.h (BlockDotPush).
#include "common/real.glsl"
#include "common/grid.glsl"
#include "common/tree_sum.glsl"

layout(std430, binding = 0) readonly buffer BlockOffsets { uint block_offsets[]; };
layout(std430, binding = 1) readonly buffer A { real a[]; };
layout(std430, binding = 2) readonly buffer B { real b[]; };
layout(std430, binding = 3) buffer Results { real results[]; };

layout(push_constant) uniform Push {
  uint rows;           // Rows of the whole system: the stride between columns.
  uint blocks;         // Diagonal blocks; block k owns rows block_offsets[k] .. [k + 1] - 1.
  uint result_offset;  // Where the result of block 0, column 0 goes in `results`.
} push;

void main() {
  const uint column = block_column();
  const uint base = column * push.rows;
  // The loop bound depends on the workgroup only, so every invocation reaches the barriers.
  for (uint block = gl_WorkGroupID.x; block < push.blocks; block += gl_NumWorkGroups.x) {
    real sum = 0.0;
    for (uint row = block_offsets[block] + gl_LocalInvocationID.x; row < block_offsets[block + 1];
         row += gl_WorkGroupSize.x)
      sum += a[base + row] * b[base + row];
    tree_sum(sum, gl_WorkGroupSize.x);
    if (gl_LocalInvocationID.x == 0)
      results[push.result_offset + column * push.blocks + block] = partial_sums[0];
    barrier();  // partial_sums[0] is read before the next block's sums overwrite it.
  }
}
