#pragma once
// Internal: per-triangle assembly of a mesh operator into a CSR matrix with a fixed pattern, on
// the device and without float atomics (shaders/triangle_stiffness.comp, shaders/slot_gather.comp).
//
// Once per connectivity the host builds an AssemblySlotMap: the row-major pattern (diagonal plus
// the vertices sharing a face, sorted) and, for each CSR slot, the list of per-triangle
// contributions that land in it, in face order. Each assembly then runs two kernels: one
// invocation per triangle writes its three off-diagonal stiffness entries (contribution 3 f + a
// belongs to corners a and a + 1 of face f, in both orders), and one invocation per row sums each
// slot's list in that fixed order and sets the diagonal to minus the row's off-diagonal sum. Same
// input, same bits; the summation order is the one of the host assembly.
//
// Eigen twins (fallback/triangle_assembly.h): harmonia::laplacian(mesh, cotangent) and
// harmonia::tensor_cotangent_laplacian. One thread at a time, like the backend that made it.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "backend/backend.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "kernels/buffer.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

enum class StiffnessKind : std::uint32_t {
  cotangent = 0,  // Cotangent weights (4.41) of 3D positions.
  tensor = 1,     // Tensor-cotangent weights (5.10) of planar uv with a 2x2 tensor per triangle.
};

// Mirrors `Push` in shaders/triangle_stiffness.comp.
struct TriangleStiffnessPush {
  std::uint32_t face_count;
  std::uint32_t kind;  // StiffnessKind.
};
static_assert(sizeof(TriangleStiffnessPush) == 8 && offsetof(TriangleStiffnessPush, kind) == 4);

// Mirrors `Push` in shaders/slot_gather.comp.
struct SlotGatherPush {
  std::uint32_t rows;
};
static_assert(sizeof(SlotGatherPush) == 4);

enum class TriangleStiffnessBinding : std::uint32_t {
  faces,
  points,
  tensors,
  contributions,
  count
};
enum class SlotGatherBinding : std::uint32_t {
  row_offsets,
  columns,
  slot_offsets,
  slot_contributions,
  contributions,
  values,
  count
};

extern const KernelProgram triangle_stiffness_program;
extern const KernelProgram slot_gather_program;

// Absolute error of one triangle's fp32 stiffness entry, in units of its conditioning
// (triangle_stiffness_conditioning). With kappa = L_max^2 / (2 A), the entry is at most
// kappa |C| / 2; rounding the coordinates to float perturbs each edge by 2 sqrt(3) u s relative
// (s = 1 + |p|_max / L_min) and the entry by about 4 kappa^2 |C| times that; the edge differences,
// the dot and cross products, the length and the division add about 10 u kappa^2 |C|, and the
// tensor rounding u |C|. Rounded up to 32 u kappa^2 s |C|, u = 2^-24.
constexpr double stiffness_error_bound(double conditioning) {
  return 32.0 * 0x1p-24 * conditioning;
}

// kappa^2 s |C| of the triangle with these corners (rows; 2 or 3 columns) and tensor norm |C|
// (1 for cotangent weights); infinite for a zero-area triangle.
[[nodiscard]] double triangle_stiffness_conditioning(const Eigen::MatrixXd& corners,
                                                     double tensor_norm);

// The fixed pattern of a connectivity and the contributions gathered into each of its slots.
struct AssemblySlotMap {
  harmonia::detail::RowMajorSparse pattern;       // #V x #V, values zero.
  std::vector<std::uint32_t> slot_offsets;        // nnz + 1.
  std::vector<std::uint32_t> slot_contributions;  // Indices 3 f + a, face order within a slot.
  int face_count = 0;
};

// Throws harmonia::Error(invalid_input) naming the face when an index is outside
// [0, vertex_count). A corner pair of a face with a repeated vertex lands on the diagonal, which
// the gather recomputes, so it is not listed.
[[nodiscard]] AssemblySlotMap build_assembly_slot_map(const Eigen::MatrixX3i& faces,
                                                      int vertex_count);

// The device side of one connectivity: its slot map, the per-triangle scratch and the values.
class TriangleAssembly {
 public:
  TriangleAssembly(CommandRecorder& recorder, const Eigen::MatrixX3i& faces, int vertex_count,
                   DevicePrecision precision = DevicePrecision::float32);

  // Uploads the inputs and assembles (one submission, waited for).
  void assemble_cotangent(const Eigen::MatrixX3d& positions);
  void assemble_tensor(const Eigen::MatrixX2d& uv, const TriangleTensors& tensors);

  // The quasi-harmonic tensors C (5.7) of the map uv -> positions into tensors(), then the
  // tensor-cotangent operator (5.10) of uv under them: one quasi-harmonic round, one submission.
  // positions: #V x 3; uv: #V x 2. A zero-area uv triangle gets infinite tensors (as on the host)
  // and contributes nothing to the operator.
  void assemble_quasi_harmonic(const Eigen::MatrixX3d& positions, const Eigen::MatrixX2d& uv);
  // The tensors last computed or uploaded (#F x 4 row-wise, fp32 widened).
  [[nodiscard]] TriangleTensors download_tensors() const;

  // Records both kernels over the points and tensors already in points() and tensors() (for a
  // pipeline that produced them on the device; the tensors are not read for cotangent weights).
  void record(CommandRecorder& recorder, StiffnessKind kind);

  // Points as 3 (cotangent) or 2 (tensor) floats per vertex; tensors as 4 floats per triangle.
  [[nodiscard]] Buffer& points() { return points_; }
  [[nodiscard]] Buffer& tensors() { return tensors_; }
  // The 3D positions the tensor kernel reads (3 floats per vertex).
  [[nodiscard]] Buffer& positions() { return positions_; }
  // The CSR pattern on the device and the assembled values (fp32, slot order of pattern()).
  [[nodiscard]] const Buffer& row_offsets() const { return row_offsets_; }
  [[nodiscard]] const Buffer& columns() const { return columns_; }
  [[nodiscard]] const Buffer& values() const { return values_; }
  [[nodiscard]] const AssemblySlotMap& slot_map() const { return map_; }
  // The assembled matrix in double (the fp32 values widened).
  [[nodiscard]] harmonia::detail::RowMajorSparse download() const;

 private:
  void upload_points(Buffer& target, const double* data, std::size_t count);
  void submit(StiffnessKind kind);

  CommandRecorder& recorder_;
  DevicePrecision precision_;
  AssemblySlotMap map_;
  int vertex_count_;
  Buffer faces_, row_offsets_, columns_, slot_offsets_, slot_contributions_, contributions_,
      values_, tensors_, positions_;
  Buffer points_;  // Sized for 3 floats per vertex (cotangent) or used as 2 (uv).
};

}  // namespace harmonia::vulkan::detail
