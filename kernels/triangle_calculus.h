#pragma once
// Internal: per-triangle gradient and the divergence back to the vertices on the device, and the
// Poisson right-hand side of a fragmented target (thesis 4.38-4.39, 6.2.2):
//   shaders/triangle_gradient.comp: G u, per triangle (rows 3 f + axis).
//   shaders/corner_terms.comp: what each triangle hands its corners (divergence or fragment).
//   shaders/vertex_gather.comp: the corners' terms summed per vertex in face order (no atomics).
// Eigen twins: harmonia::gradient_operator, harmonia::divergence, harmonia::fragment_poisson_rhs
// (host/harmonia/gradient.h), on 3D positions (planar positions get z = 0). Every block may hold
// several columns (u and v at once).

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "kernels/buffer.h"
#include "kernels/device_arrays.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

// Mirrors `Push` in shaders/triangle_gradient.comp.
struct TriangleGradientPush {
  std::uint32_t face_count;
  std::uint32_t vertex_count;
};
static_assert(sizeof(TriangleGradientPush) == 8 &&
              offsetof(TriangleGradientPush, vertex_count) == 4);

enum class CornerTermsMode : std::uint32_t { divergence = 0, fragment = 1 };

// Mirrors `Push` in shaders/corner_terms.comp.
struct CornerTermsPush {
  std::uint32_t face_count;
  std::uint32_t mode;  // CornerTermsMode.
};
static_assert(sizeof(CornerTermsPush) == 8 && offsetof(CornerTermsPush, mode) == 4);

// Mirrors `Push` in shaders/vertex_gather.comp.
struct VertexGatherPush {
  std::uint32_t vertex_count;
  std::uint32_t corner_count;
};
static_assert(sizeof(VertexGatherPush) == 8 && offsetof(VertexGatherPush, corner_count) == 4);

enum class TriangleGradientBinding : std::uint32_t { faces, positions, values, gradients, count };
enum class CornerTermsBinding : std::uint32_t { faces, positions, inputs, terms, count };
enum class VertexGatherBinding : std::uint32_t { vertex_offsets, corners, terms, sums, count };

extern const KernelProgram triangle_gradient_program;
extern const KernelProgram corner_terms_program;
extern const KernelProgram vertex_gather_program;

// Absolute error of a per-triangle term computed in fp32: each product of a geometric factor
// (hat gradient, area, half cotangent) and an input value is off by at most 32 u kappa^2 s of its
// magnitude, with kappa^2 s the triangle's conditioning (triangle_stiffness_conditioning in
// kernels/triangle_assembly.h; the argument of stiffness_error_bound), and `magnitude` the sum of
// |factor| |value| over the products of the term (for a difference x_a - x_b: |x_a| + |x_b|).
// The vertex gather adds (terms summed) u times the sum of the terms' magnitudes.
constexpr double triangle_term_error_bound(double conditioning, double magnitude) {
  return 32.0 * 0x1p-24 * conditioning * magnitude;
}

// The device side of one mesh: faces, positions and the vertex -> corner map.
class TriangleCalculus {
 public:
  // positions: #V x 2 or #V x 3. Throws harmonia::Error(invalid_input) naming a face with an
  // index out of range.
  // The blocks given to it must hold reals of `precision`.
  TriangleCalculus(CommandRecorder& recorder, const Eigen::MatrixX3i& faces,
                   const Eigen::MatrixXd& positions,
                   DevicePrecision precision = DevicePrecision::float32);

  // New positions of the same vertices (#V x 2 or #V x 3): the geometry changed, the
  // connectivity did not.
  void set_positions(const Eigen::MatrixXd& positions);

  // gradients (3F x m) = G values (#V x m).
  void gradient(const VulkanVectors& values, VulkanVectors& gradients);
  // divergence (#V x m) = G^T diag(area) field (field 3F x m).
  void divergence(const VulkanVectors& field, VulkanVectors& result);
  // rhs (#V x m) from fragments (3F x m, row 3 f + k: the target of corner k of face f).
  void fragment_poisson_rhs(const VulkanVectors& fragments, VulkanVectors& rhs);

  // The same, recorded into a caller's recording (for pipelines chaining kernels).
  void record_gradient(CommandRecorder& recorder, const VulkanVectors& values,
                       VulkanVectors& gradients);
  void record_corner_sums(CommandRecorder& recorder, CornerTermsMode mode,
                          const VulkanVectors& inputs, VulkanVectors& result);

  [[nodiscard]] int face_count() const { return face_count_; }
  [[nodiscard]] int vertex_count() const { return vertex_count_; }
  // Vertex v owns corners()[vertex_offsets()[v] .. vertex_offsets()[v + 1]) (3 f + k, face order).
  [[nodiscard]] const std::vector<std::uint32_t>& vertex_offsets() const { return offsets_; }
  [[nodiscard]] const std::vector<std::uint32_t>& corners() const { return corners_; }

 private:
  void submit_corner_sums(CornerTermsMode mode, const VulkanVectors& inputs, VulkanVectors& result);

  CommandRecorder& recorder_;
  DevicePrecision precision_;
  int face_count_, vertex_count_;
  std::vector<std::uint32_t> offsets_, corners_;
  Buffer faces_, positions_, vertex_offsets_, corner_list_;
  std::unique_ptr<Buffer> terms_;  // 3F x columns, grown on demand.
};

}  // namespace harmonia::vulkan::detail
