#version 450
#extension GL_GOOGLE_include_directive : require
// Per-triangle gradient of P1 functions (thesis 4.38-4.39), one invocation per triangle and one
// row of workgroups per column of the function block: grad u on face f = sum_k u_k grad phi_k,
// with the hat gradient grad phi_k = n x e_k / |n|^2 (n = (p1 - p0) x (p2 - p0), e_k the edge
// opposite corner k). Output rows 3 f + axis, like harmonia::gradient_operator on 3D positions
// (planar positions are passed with z = 0). A zero-area triangle has zero gradients.
// C++ side: kernels/triangle_calculus.h (TriangleGradientPush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer Faces { uint faces[]; };
layout(std430, binding = 1) readonly buffer Positions { real positions[]; };  // 3 per vertex
layout(std430, binding = 2) readonly buffer Values { real values[]; };  // #V x columns
layout(std430, binding = 3) writeonly buffer Gradients { real gradients[]; };  // 3F x columns

layout(push_constant) uniform Push {
  uint face_count;
  uint vertex_count;
} push;

real3 position(uint vertex) {
  return real3(positions[3 * vertex], positions[3 * vertex + 1], positions[3 * vertex + 2]);
}

void main() {
  const uint value_base = block_column() * push.vertex_count;
  const uint gradient_base = block_column() * 3 * push.face_count;
  for (uint face = first_item(); face < push.face_count; face += grid_stride()) {
    uint corner[3];
    real3 p[3];
    for (uint k = 0; k < 3; ++k) {
      corner[k] = faces[3 * face + k];
      p[k] = position(corner[k]);
    }
    const real3 normal = cross(p[1] - p[0], p[2] - p[0]);
    const real normal_squared = dot(normal, normal);
    real3 gradient = real3(0.0);
    if (normal_squared > 0.0) {
      for (uint k = 0; k < 3; ++k) {
        const real3 hat = cross(normal, p[(k + 2) % 3] - p[(k + 1) % 3]) / normal_squared;
        gradient += values[value_base + corner[k]] * hat;
      }
    }
    for (uint axis = 0; axis < 3; ++axis)
      gradients[gradient_base + 3 * face + axis] = gradient[axis];
  }
}
