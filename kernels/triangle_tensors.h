#pragma once
// Internal: the per-triangle conductance tensor C = (sqrt(I))^-1 of a quasi-harmonic map (thesis
// 5.1-5.7) on the device (shaders/triangle_tensors.comp), from the 3D positions and the current
// uv. Eigen twin: harmonia::quasi_harmonic_tensors (fallback/triangle_assembly.h).
// TriangleAssembly (kernels/triangle_assembly.h) runs it into the tensors its tensor-cotangent
// assembly reads, so a quasi-harmonic round refreshes C and the operator in one submission.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "kernels/buffer.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

// Mirrors `Push` in shaders/triangle_tensors.comp.
struct TriangleTensorsPush {
  std::uint32_t face_count;
};
static_assert(sizeof(TriangleTensorsPush) == 4);

enum class TriangleTensorsBinding : std::uint32_t { faces, positions, uv, tensors, count };

extern const KernelProgram triangle_tensors_program;

// Absolute error of each fp32 entry of C, in units of its conditioning
// (triangle_tensor_conditioning). Rounding the coordinates perturbs the uv edges by
// 2 sqrt(3) u s_uv and the 3D edges by 2 sqrt(3) u s_3d relative (s = 1 + |p|_max / L_min);
// inverting the uv edge matrix amplifies the former by kappa_uv = L_max^2 / (2 A_uv), so J is off
// by about 4 u (kappa_uv s_uv + s_3d) relative, I = J^T J by twice that; the square root and the
// inverse amplify a relative error of I by at most cond(I) (each by sqrt(cond(I))). With the
// arithmetic of the closed forms, rounded up to 64 u |C| cond(I) (kappa_uv s_uv + s_3d).
constexpr double triangle_tensor_error_bound(double conditioning) {
  return 64.0 * 0x1p-24 * conditioning;
}

// |C| cond(I) (kappa_uv s_uv + s_3d) for a triangle with these 3D and uv corners (rows), its first
// fundamental form I and tensor C (row-wise 2x2); infinite for a zero-area uv triangle.
[[nodiscard]] double triangle_tensor_conditioning(const Eigen::Matrix3d& corners,
                                                  const Eigen::Matrix<double, 3, 2>& corners_uv,
                                                  const Eigen::Vector4d& form,
                                                  const Eigen::Vector4d& tensor);

// Records C for `face_count` triangles: faces 3 uints, positions 3 floats and uv 2 floats per
// vertex, tensors 4 floats per triangle (row-wise).
void record_triangle_tensors(CommandRecorder& recorder, const Buffer& faces,
                             const Buffer& positions, const Buffer& uv, Buffer& tensors,
                             std::uint32_t face_count,
                             DevicePrecision precision = DevicePrecision::float32);

}  // namespace harmonia::vulkan::detail
