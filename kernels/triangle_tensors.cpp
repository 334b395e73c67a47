// The embedded SPIR-V of shaders/triangle_tensors.comp (its only translation unit), its recording
// and its declared error bound.
#include "kernels/triangle_tensors.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "triangle_tensors.spv.h"
#include "triangle_tensors_fp64.spv.h"

namespace harmonia::vulkan::detail {
namespace {

// s = 1 + |p|_max / L_min of a triangle's corners: how coordinate rounding grows on its edges.
template <int Dimension>
double coordinate_amplification(const Eigen::Matrix<double, 3, Dimension>& corners) {
  double shortest = std::numeric_limits<double>::infinity(), farthest = 0.0;
  for (int k = 0; k < 3; ++k) {
    shortest = std::min(shortest, (corners.row((k + 1) % 3) - corners.row(k)).norm());
    farthest = std::max(farthest, corners.row(k).norm());
  }
  return 1.0 + farthest / shortest;
}

}  // namespace

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram triangle_tensors_fp64_program{
    "triangle_tensors_fp64", triangle_tensors_fp64_spv, sizeof(triangle_tensors_fp64_spv),
    static_cast<std::uint32_t>(TriangleTensorsBinding::count), sizeof(TriangleTensorsPush)};
}  // namespace

const KernelProgram triangle_tensors_program{
    "triangle_tensors",           triangle_tensors_spv,
    sizeof(triangle_tensors_spv), static_cast<std::uint32_t>(TriangleTensorsBinding::count),
    sizeof(TriangleTensorsPush),  &triangle_tensors_fp64_program};

double triangle_tensor_conditioning(const Eigen::Matrix3d& corners,
                                    const Eigen::Matrix<double, 3, 2>& corners_uv,
                                    const Eigen::Vector4d& form, const Eigen::Vector4d& tensor) {
  const Eigen::Vector2d edge_j = (corners_uv.row(1) - corners_uv.row(0)).transpose();
  const Eigen::Vector2d edge_k = (corners_uv.row(2) - corners_uv.row(0)).transpose();
  const double twice_area = std::abs(edge_j.x() * edge_k.y() - edge_j.y() * edge_k.x());
  if (twice_area == 0.0) return std::numeric_limits<double>::infinity();
  double longest = 0.0;
  for (int k = 0; k < 3; ++k)
    longest = std::max(longest, (corners_uv.row((k + 1) % 3) - corners_uv.row(k)).norm());
  const double kappa = longest * longest / twice_area;
  // Eigenvalues of the symmetric 2x2 form.
  const double mean = 0.5 * (form[0] + form[3]);
  const double radius = std::hypot(0.5 * (form[0] - form[3]), 0.5 * (form[1] + form[2]));
  const double condition = (mean + radius) / (mean - radius);
  return tensor.norm() * condition *
         (kappa * coordinate_amplification<2>(corners_uv) + coordinate_amplification<3>(corners));
}

void record_triangle_tensors(CommandRecorder& recorder, const Buffer& faces,
                             const Buffer& positions, const Buffer& uv, Buffer& tensors,
                             std::uint32_t face_count, DevicePrecision precision) {
  recorder.dispatch(in_precision(triangle_tensors_program, precision),
                    {&faces, &positions, &uv, &tensors}, TriangleTensorsPush{face_count},
                    recorder.groups_for(face_count));
}

}  // namespace harmonia::vulkan::detail
