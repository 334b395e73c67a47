#version 450
#extension GL_GOOGLE_include_directive : require
// Sums per-element contributions into the values of a CSR matrix with a fixed pattern, one
// invocation per row, through a slot map built once on the host: the contributions of slot s are
// contributions[slot_contributions[k]] for k in [slot_offsets[s], slot_offsets[s + 1]), summed in
// that (fixed) order. The diagonal entry of each row is minus the sum of its off-diagonal entries
// (left to right), so rows sum to zero exactly as in host/mesh/adjacency_pattern.h.
// Deterministic: no atomics. C++ side: kernels/triangle_assembly.h (SlotGatherPush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer RowOffsets { uint row_offsets[]; };
layout(std430, binding = 1) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 2) readonly buffer SlotOffsets { uint slot_offsets[]; };
layout(std430, binding = 3) readonly buffer SlotContributions { uint slot_contributions[]; };
layout(std430, binding = 4) readonly buffer Contributions { real contributions[]; };
layout(std430, binding = 5) writeonly buffer Values { real values[]; };

const uint no_slot = 0xffffffffu;

layout(push_constant) uniform Push {
  uint rows;
} push;

void main() {
  for (uint row = first_item(); row < push.rows; row += grid_stride()) {
    real off_diagonal_sum = 0.0;
    uint diagonal_slot = no_slot;
    for (uint slot = row_offsets[row]; slot < row_offsets[row + 1]; ++slot) {
      if (columns[slot] == row) {
        diagonal_slot = slot;
        continue;
      }
      real value = 0.0;
      for (uint k = slot_offsets[slot]; k < slot_offsets[slot + 1]; ++k)
        value += contributions[slot_contributions[k]];
      values[slot] = value;
      off_diagonal_sum += value;
    }
    if (diagonal_slot != no_slot) values[diagonal_slot] = -off_diagonal_sum;
  }
}
