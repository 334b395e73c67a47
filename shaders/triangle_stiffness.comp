#version 450
#extension GL_GOOGLE_include_directive : require
// Per-triangle P1 stiffness of a mesh operator, one invocation per triangle. For each corner pair
// (a, b = a + 1 mod 3) it writes the off-diagonal stiffness entry S_ab (= -w_ab in the PSD
// convention of host/harmonia/laplacian.h) to contributions[3 f + a]; shaders/slot_gather.comp
// then sums these into a fixed CSR pattern. No atomics: every output has one writer.
//   cotangent (4.41): 3D positions, S_ab = -cot(theta_c) / 2 with c the third corner.
//   tensor (5.10): planar uv and a 2x2 tensor C per triangle,
//                  S_ab = (e_a^perp)^T sym(C) e_b^perp / (4 A), e_k the uv edge opposite corner k.
// A zero-area triangle contributes zeros. C++ side: kernels/triangle_assembly.h
// (TriangleStiffnessPush); Eigen twin: fallback/triangle_assembly.h.
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer Faces { uint faces[]; };     // 3 per triangle
layout(std430, binding = 1) readonly buffer Points { real points[]; };  // 3 (or 2) per vertex
layout(std430, binding = 2) readonly buffer Tensors { real tensors[]; };  // C00 C01 C10 C11
layout(std430, binding = 3) writeonly buffer Contributions { real contributions[]; };

const uint kind_cotangent = 0u;
const uint kind_tensor = 1u;

layout(push_constant) uniform Push {
  uint face_count;
  uint kind;  // kind_cotangent or kind_tensor
} push;

real3 position(uint vertex) {
  return real3(points[3 * vertex], points[3 * vertex + 1], points[3 * vertex + 2]);
}
real2 planar(uint vertex) { return real2(points[2 * vertex], points[2 * vertex + 1]); }

void cotangent_stiffness(uint face) {
  real3 p[3];
  for (uint k = 0; k < 3; ++k) p[k] = position(faces[3 * face + k]);
  // cot at corner c = (u . v) / |u x v| for the edges leaving c; |u x v| = 2 A at every corner.
  const real twice_area = length(cross(p[1] - p[0], p[2] - p[0]));
  const real scale = twice_area == 0.0 ? 0.0 : 0.5 / twice_area;
  for (uint a = 0; a < 3; ++a) {
    const uint b = (a + 1) % 3, c = (a + 2) % 3;
    contributions[3 * face + a] = -(dot(p[a] - p[c], p[b] - p[c]) * scale);
  }
}

void tensor_stiffness(uint face) {
  real2 rotated_edge[3];
  for (uint k = 0; k < 3; ++k) {
    const real2 edge = planar(faces[3 * face + (k + 2) % 3]) - planar(faces[3 * face + (k + 1) % 3]);
    rotated_edge[k] = real2(-edge.y, edge.x);
  }
  const real twice_area =
      abs(rotated_edge[2].x * rotated_edge[1].y - rotated_edge[2].y * rotated_edge[1].x);
  // Only the symmetric part of C enters the energy.
  const real off_diagonal = 0.5 * (tensors[4 * face + 1] + tensors[4 * face + 2]);
  const real2x2 tensor = real2x2(tensors[4 * face], off_diagonal, off_diagonal, tensors[4 * face + 3]);
  for (uint a = 0; a < 3; ++a) {
    const uint b = (a + 1) % 3;
    contributions[3 * face + a] = twice_area == 0.0
        ? 0.0
        : dot(rotated_edge[a], tensor * rotated_edge[b]) / (2.0 * twice_area);
  }
}

void main() {
  for (uint face = first_item(); face < push.face_count; face += grid_stride()) {
    if (push.kind == kind_tensor)
      tensor_stiffness(face);
    else
      cotangent_stiffness(face);
  }
}
