#version 450
#extension GL_GOOGLE_include_directive : require
// Values of the weighted normal product M = B D B^T (D diagonal) in a fixed pattern, one
// invocation per entry of M, through a map built once on the host: entry s of M is the sum over
// p in [slot_offsets[s], slot_offsets[s + 1]) of d[k] (b[left] b[right]) with
// (left, right, k) = products[3 p .. 3 p + 2] (left, right: entry indices into B's values, k the
// shared column), in increasing k. b[left] b[right] is computed before the weight so that M(i, j)
// and M(j, i) are the same bits. Deterministic: no atomics. C++ side: kernels/normal_product.h
// (NormalProductPush); Eigen twin: host/backend/cpu_normal_product.h.
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer SlotOffsets { uint slot_offsets[]; };
layout(std430, binding = 1) readonly buffer Products { uint products[]; };
layout(std430, binding = 2) readonly buffer BValues { real b[]; };
layout(std430, binding = 3) readonly buffer Diagonal { real d[]; };
layout(std430, binding = 4) writeonly buffer Values { real values[]; };

layout(push_constant) uniform Push {
  uint entries;  // Stored entries of M.
} push;

void main() {
  for (uint slot = first_item(); slot < push.entries; slot += grid_stride()) {
    real sum = 0.0;
    for (uint p = slot_offsets[slot]; p < slot_offsets[slot + 1]; ++p)
      sum += d[products[3 * p + 2]] * (b[products[3 * p]] * b[products[3 * p + 1]]);
    values[slot] = sum;
  }
}
