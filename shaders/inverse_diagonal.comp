#version 450
#extension GL_GOOGLE_include_directive : require
// The Jacobi inverse diagonal of a CSR matrix whose values a kernel wrote (the normal product,
// kernels/normal_product.h), one invocation per row: 1 / A(row, row), or 1 where that entry is
// absent (diagonal_slots[row] = no_slot) or zero, as the host does for uploaded matrices.
// C++ side: kernels/device_arrays.h (VulkanMatrix::record_inverse_diagonal, InverseDiagonalPush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer DiagonalSlots { uint diagonal_slots[]; };
layout(std430, binding = 1) readonly buffer Values { real values[]; };
layout(std430, binding = 2) writeonly buffer InverseDiagonal { real inverse_diagonal[]; };

const uint no_slot = 0xffffffffu;

layout(push_constant) uniform Push {
  uint rows;
} push;

void main() {
  for (uint row = first_item(); row < push.rows; row += grid_stride()) {
    const uint slot = diagonal_slots[row];
    const real diagonal = slot == no_slot ? real(0.0) : values[slot];
    inverse_diagonal[row] = diagonal != 0.0 ? real(1.0) / diagonal : real(1.0);
  }
}
