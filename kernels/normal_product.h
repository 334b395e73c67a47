#pragma once
// Internal: the weighted normal product M = B D B^T (D diagonal, B sparse) with a fixed pattern,
// refreshed on the device (shaders/normal_product.comp): the system matrix of the angle-based
// methods, whose B and D change every Newton step while their patterns do not.
//
// Once per pattern of B the host builds the pattern of B B^T (every (i, j) whose rows share a
// column; the diagonal of every non-empty row) and, per entry, the products b_ik b_jk over the
// shared columns k in increasing order. Each refresh is one invocation per entry of M summing
// its list in that order: same input, same bits, and M exactly symmetric.
// Eigen twin: host/backend/cpu_normal_product.h (B * D * B^T).

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "backend/backend.h"
#include "kernels/buffer.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

// Mirrors `Push` in shaders/normal_product.comp.
struct NormalProductPush {
  std::uint32_t entries;
};
static_assert(sizeof(NormalProductPush) == 4);

enum class NormalProductBinding : std::uint32_t {
  slot_offsets,
  products,
  b_values,
  diagonal,
  values,
  count
};

extern const KernelProgram normal_product_program;

// Error of an entry of M relative to sum_k |b_ik d_k b_jk| over its `terms` products: b and d
// rounded to the device type (3 u), two products rounded (2 u), the sum of `terms` values rounded
// terms - 1 times, plus one u of slack; u = 2^-24 in fp32, 2^-53 in fp64.
constexpr double normal_product_error_bound(int terms,
                                            DevicePrecision precision = DevicePrecision::float32) {
  return (terms + 5) * (precision == DevicePrecision::float64 ? 0x1p-53 : 0x1p-24);
}

// The pattern of B B^T and the products behind each of its entries.
struct NormalProductMap {
  harmonia::detail::RowMajorSparse pattern;  // rows(B) x rows(B), values zero.
  std::vector<std::uint32_t> slot_offsets;   // nnz(M) + 1.
  std::vector<std::uint32_t> products;       // (left, right, k) per product.
};

[[nodiscard]] NormalProductMap build_normal_product_map(const harmonia::detail::RowMajorSparse& b);

// The device side of one pattern of B.
class NormalProduct {
 public:
  // `b` gives the pattern (and the first values); B, D and M are device reals of `precision`.
  NormalProduct(CommandRecorder& recorder, const harmonia::detail::RowMajorSparse& b,
                DevicePrecision precision = DevicePrecision::float32);

  // New values of B (in the slot order of the pattern it was built with) and of D (one per
  // column of B), uploaded; then M refreshed (one submission, waited for).
  void update(const Eigen::Ref<const Eigen::VectorXd>& b_values,
              const Eigen::Ref<const Eigen::VectorXd>& diagonal);
  // Uploads new values of B and D without refreshing M.
  void upload(const Eigen::Ref<const Eigen::VectorXd>& b_values,
              const Eigen::Ref<const Eigen::VectorXd>& diagonal);
  // Records the refresh over the values already in b_values() and diagonal() (for a pipeline
  // that computes them on the device).
  void record(CommandRecorder& recorder);
  // The same, writing M's values (slot order of map().pattern) into `target` instead of values():
  // the value buffer of a VulkanMatrix with that pattern (kernels/normal_product_matrix.h).
  void record(CommandRecorder& recorder, const Buffer& target);

  [[nodiscard]] Buffer& b_values() { return b_values_; }
  [[nodiscard]] Buffer& diagonal() { return diagonal_; }
  [[nodiscard]] const Buffer& values() const { return values_; }  // M, slot order of the map.
  [[nodiscard]] const NormalProductMap& map() const { return map_; }
  [[nodiscard]] DevicePrecision precision() const { return precision_; }
  // M in double (the device values widened).
  [[nodiscard]] harmonia::detail::RowMajorSparse download() const;

 private:
  CommandRecorder& recorder_;
  DevicePrecision precision_;
  NormalProductMap map_;
  Eigen::Index b_entries_, b_columns_;
  Buffer slot_offsets_, products_, b_values_, diagonal_, values_;
};

}  // namespace harmonia::vulkan::detail
