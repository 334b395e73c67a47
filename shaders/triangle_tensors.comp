#version 450
#extension GL_GOOGLE_include_directive : require
// Per-triangle conductance tensor of the quasi-harmonic map (thesis 5.1-5.7), one invocation per
// triangle: the Jacobian J = E3 E2^-1 of uv -> 3D (E3, E2: the 3D and uv edges from corner 0),
// the first fundamental form I = J^T J (5.2), its square root K = (I + sqrt(det I) Id) /
// sqrt(trace I + 2 sqrt(det I)) (closed form, 5.5) and C = K^-1 (5.7), stored row-wise
// (C00, C01, C10, C11). A zero-area uv triangle gets +infinity in all four entries, the marker
// harmonia::first_fundamental_forms uses. C++ side: kernels/triangle_assembly.h
// (TriangleTensorsPush); Eigen twin: harmonia::quasi_harmonic_tensors.
#include "common/real.glsl"
#include "common/grid.glsl"

layout(std430, binding = 0) readonly buffer Faces { uint faces[]; };
layout(std430, binding = 1) readonly buffer Positions { real positions[]; };  // 3 per vertex
layout(std430, binding = 2) readonly buffer Uv { real uv[]; };                // 2 per vertex
layout(std430, binding = 3) writeonly buffer Tensors { real tensors[]; };

layout(push_constant) uniform Push {
  uint face_count;
} push;

real3 position(uint vertex) {
  return real3(positions[3 * vertex], positions[3 * vertex + 1], positions[3 * vertex + 2]);
}
real2 planar(uint vertex) { return real2(uv[2 * vertex], uv[2 * vertex + 1]); }

void main() {
  for (uint face = first_item(); face < push.face_count; face += grid_stride()) {
    const uint i = faces[3 * face], j = faces[3 * face + 1], k = faces[3 * face + 2];
    const real3 edge3_j = position(j) - position(i), edge3_k = position(k) - position(i);
    const real2 edge2_j = planar(j) - planar(i), edge2_k = planar(k) - planar(i);
    const real det = edge2_j.x * edge2_k.y - edge2_k.x * edge2_j.y;
    if (det == 0.0) {
      const real infinity = real_infinity();
      for (uint entry = 0; entry < 4; ++entry) tensors[4 * face + entry] = infinity;
      continue;
    }
    // Columns of E2^-1 = (1/det) [[e2k.y, -e2k.x], [-e2j.y, e2j.x]]: J's columns are E3 times them.
    const real3 jacobian_u = (edge2_k.y * edge3_j - edge2_j.y * edge3_k) / det;
    const real3 jacobian_v = (edge2_j.x * edge3_k - edge2_k.x * edge3_j) / det;
    const real form_uu = dot(jacobian_u, jacobian_u);
    const real form_uv = dot(jacobian_u, jacobian_v);
    const real form_vv = dot(jacobian_v, jacobian_v);
    // K = sqrt(I) by Cayley-Hamilton; C = K^-1 = adj(K) / det(K). det I is clamped at 0 so that
    // rounding cannot turn the form of a (near) zero-area 3D triangle into NaN.
    const real root_det = sqrt(max(form_uu * form_vv - form_uv * form_uv, 0.0));
    const real root_trace = sqrt(form_uu + form_vv + 2.0 * root_det);
    const real k_uu = (form_uu + root_det) / root_trace;
    const real k_vv = (form_vv + root_det) / root_trace;
    const real k_uv = form_uv / root_trace;
    const real inverse_det = 1.0 / (k_uu * k_vv - k_uv * k_uv);
    tensors[4 * face] = k_vv * inverse_det;
    tensors[4 * face + 1] = -k_uv * inverse_det;
    tensors[4 * face + 2] = -k_uv * inverse_det;
    tensors[4 * face + 3] = k_uu * inverse_det;
  }
}
