#version 450
#extension GL_GOOGLE_include_directive : require
// What each triangle hands to its three corners, one invocation per triangle and one row of
// workgroups per column; shaders/vertex_gather.comp sums them per vertex in a fixed order.
//   divergence: corner k of face f gets area_f (grad phi_k . F_f) for the per-triangle field F
//               (rows 3 f + axis): div = G^T diag(area) F (harmonia::divergence).
//   fragment:   corner a gets sum over the other corners b of cot(theta_c) / 2 (x_a - x_b), with
//               c the third corner and x the face's own target coordinates (rows 3 f + k): the
//               Poisson right-hand side of a fragmented target (6.2.2,
//               harmonia::fragment_poisson_rhs).
// A zero-area triangle hands out zeros. Output rows 3 f + k. C++ side: kernels/triangle_calculus.h
// (CornerTermsPush).
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer Faces { uint faces[]; };
layout(std430, binding = 1) readonly buffer Positions { real positions[]; };  // 3 per vertex
layout(std430, binding = 2) readonly buffer Input { real inputs[]; };  // 3F x columns
layout(std430, binding = 3) writeonly buffer Terms { real terms[]; };  // 3F x columns

const uint mode_divergence = 0u;
const uint mode_fragment = 1u;

layout(push_constant) uniform Push {
  uint face_count;
  uint mode;  // mode_divergence or mode_fragment
} push;

real3 position(uint vertex) {
  return real3(positions[3 * vertex], positions[3 * vertex + 1], positions[3 * vertex + 2]);
}

void main() {
  const uint base = block_column() * 3 * push.face_count;
  for (uint face = first_item(); face < push.face_count; face += grid_stride()) {
    real3 p[3];
    for (uint k = 0; k < 3; ++k) p[k] = position(faces[3 * face + k]);
    const real3 normal = cross(p[1] - p[0], p[2] - p[0]);
    const real normal_squared = dot(normal, normal);
    for (uint k = 0; k < 3; ++k) {
      real term = 0.0;
      if (normal_squared > 0.0) {
        if (push.mode == mode_divergence) {
          const real3 field = real3(inputs[base + 3 * face], inputs[base + 3 * face + 1],
                                  inputs[base + 3 * face + 2]);
          const real3 hat = cross(normal, p[(k + 2) % 3] - p[(k + 1) % 3]) / normal_squared;
          term = 0.5 * sqrt(normal_squared) * dot(hat, field);
        } else {
          const real scale = 0.5 / sqrt(normal_squared);
          for (uint step = 1; step < 3; ++step) {
            const uint other = (k + step) % 3, third = (k + 3 - step) % 3;
            const real half_cot = dot(p[k] - p[third], p[other] - p[third]) * scale;
            term += half_cot * (inputs[base + 3 * face + k] - inputs[base + 3 * face + other]);
          }
        }
      }
      terms[base + 3 * face + k] = term;
    }
  }
}
