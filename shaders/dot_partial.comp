#version 450
#extension GL_GOOGLE_include_directive : require
// First pass of dot(a, b) per column: workgroup g sums the items g*W + t, stepping by the grid,
// each invocation in order, then a tree; partials[column * groups + g] gets the group's sum. The
// number of groups depends only on the length and the device, so the order is fixed.
// C++ side: kernels/reduction.h (DotPartialPush).
#include "common/real.glsl"
#include "common/grid.glsl"
#include "common/tree_sum.glsl"

layout(std430, binding = 0) readonly buffer A { real a[]; };
layout(std430, binding = 1) readonly buffer B { real b[]; };
layout(std430, binding = 2) writeonly buffer Partials { real partials[]; };

layout(push_constant) uniform Push {
  uint rows;
} push;

void main() {
  const uint base = block_column() * push.rows;
  real sum = 0.0;
  for (uint item = first_item(); item < push.rows; item += grid_stride())
    sum += a[base + item] * b[base + item];
  tree_sum(sum, gl_WorkGroupSize.x);
  if (gl_LocalInvocationID.x == 0)
    partials[block_column() * gl_NumWorkGroups.x + gl_WorkGroupID.x] = partial_sums[0];
}
