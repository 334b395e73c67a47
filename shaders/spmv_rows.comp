#version 450
#extension GL_GOOGLE_include_directive : require
// y = A x for a CSR matrix, one invocation per row (short rows: mesh Laplacians have ~7 entries).
// Each row is summed left to right. C++ side: kernels/spmv.h (SpmvPush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer RowOffsets { uint row_offsets[]; };
layout(std430, binding = 1) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 2) readonly buffer Values { real values[]; };
layout(std430, binding = 3) readonly buffer X { real x[]; };
layout(std430, binding = 4) writeonly buffer Y { real y[]; };

layout(push_constant) uniform Push {
  uint rows;    // Rows of A (and of y).
  uint x_rows;  // Columns of A (rows of x): the stride between columns of the x block.
} push;

void main() {
  const uint x_base = block_column() * push.x_rows;
  const uint y_base = block_column() * push.rows;
  for (uint row = first_item(); row < push.rows; row += grid_stride()) {
    real sum = 0.0;
    for (uint entry = row_offsets[row]; entry < row_offsets[row + 1]; ++entry)
      sum += values[entry] * x[x_base + columns[entry]];
    y[y_base + row] = sum;
  }
}
