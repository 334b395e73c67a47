#version 450
#extension GL_GOOGLE_include_directive : require
// Jacobi preconditioner z = r ./ diag(A), as z = inverse_diagonal .* r per column (the inverse
// is formed on the host in double; 1 where the diagonal is zero). C++ side: kernels/vector_ops.h.
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer InverseDiagonal { real inverse_diagonal[]; };
layout(std430, binding = 1) readonly buffer R { real r[]; };
layout(std430, binding = 2) writeonly buffer Z { real z[]; };

layout(push_constant) uniform Push {
  uint rows;
} push;

void main() {
  const uint base = block_column() * push.rows;
  for (uint row = first_item(); row < push.rows; row += grid_stride())
    z[base + row] = inverse_diagonal[row] * r[base + row];
}
