#version 450
#extension GL_GOOGLE_include_directive : require
// Sums per-corner terms at the vertices, one invocation per vertex and one row of workgroups per
// column, through a map built once on the host: vertex v owns the corners
// corners[k] (= 3 f + corner) for k in [vertex_offsets[v], vertex_offsets[v + 1]), in face order,
// summed in that fixed order (no atomics, same bits every run). C++ side:
// kernels/triangle_calculus.h (VertexGatherPush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer VertexOffsets { uint vertex_offsets[]; };
layout(std430, binding = 1) readonly buffer Corners { uint corners[]; };
layout(std430, binding = 2) readonly buffer Terms { real terms[]; };  // 3F x columns
layout(std430, binding = 3) writeonly buffer Sums { real sums[]; };   // #V x columns

layout(push_constant) uniform Push {
  uint vertex_count;
  uint corner_count;  // 3F: the stride between columns of the terms
} push;

void main() {
  const uint term_base = block_column() * push.corner_count;
  const uint sum_base = block_column() * push.vertex_count;
  for (uint vertex = first_item(); vertex < push.vertex_count; vertex += grid_stride()) {
    real sum = 0.0;
    for (uint k = vertex_offsets[vertex]; k < vertex_offsets[vertex + 1]; ++k)
      sum += terms[term_base + corners[k]];
    sums[sum_base + vertex] = sum;
  }
}
