#version 450
#extension GL_GOOGLE_include_directive : require
// Second pass of dot(a, b): one workgroup per column sums that column's partials (in order per
// invocation, then a tree) into results[result_offset + column]. C++ side: kernels/reduction.h.
#include "common/real.glsl"
#include "common/grid.glsl"
#include "common/tree_sum.glsl"

layout(std430, binding = 0) readonly buffer Partials { real partials[]; };
layout(std430, binding = 1) buffer Results { real results[]; };

layout(push_constant) uniform Push {
  uint groups;         // Partials per column (the first pass's workgroup count).
  uint result_offset;  // Where column 0's result goes in `results`.
} push;

void main() {
  const uint base = block_column() * push.groups;
  real sum = 0.0;
  for (uint item = gl_LocalInvocationID.x; item < push.groups; item += gl_WorkGroupSize.x)
    sum += partials[base + item];
  tree_sum(sum, gl_WorkGroupSize.x);
  if (gl_LocalInvocationID.x == 0) results[push.result_offset + block_column()] = partial_sums[0];
}
