#pragma once
// The error bound of every entry of a matrix assembled on the device in fp32
// (kernels/triangle_assembly.h), from the per-triangle bound declared next to the kernel: shared by
// the tests of the assembly and of the backends' per-triangle operators.

#include <Eigen/Core>
#include <cmath>
#include <cstddef>

#include "backend/backend.h"
#include "kernels/triangle_assembly.h"

namespace harmonia::testing {

// Per slot: the declared per-triangle bound summed over the slot's contributions, plus the
// rounding of the gather's sum; per diagonal: the row's off-diagonal bounds plus its sum's
// rounding. `conditioning`: triangle_stiffness_conditioning of every face; `expected`: the
// operator in the pattern of `map`.
inline Eigen::VectorXd entry_bounds(const vulkan::detail::AssemblySlotMap& map,
                                    const Eigen::VectorXd& conditioning,
                                    const detail::RowMajorSparse& expected) {
  constexpr double unit_roundoff = 0x1p-24;
  Eigen::VectorXd bounds = Eigen::VectorXd::Zero(expected.nonZeros());
  for (int row = 0; row < map.pattern.rows(); ++row) {
    const int begin = map.pattern.outerIndexPtr()[row], end = map.pattern.outerIndexPtr()[row + 1];
    double off_diagonal_bound = 0.0, off_diagonal_magnitude = 0.0;
    int diagonal = -1;
    for (int slot = begin; slot < end; ++slot) {
      if (map.pattern.innerIndexPtr()[slot] == row) {
        diagonal = slot;
        continue;
      }
      const auto first = map.slot_offsets[static_cast<std::size_t>(slot)];
      const auto last = map.slot_offsets[static_cast<std::size_t>(slot) + 1];
      double bound = 0.0, magnitude = 0.0;
      for (auto k = first; k < last; ++k) {
        const double triangle = conditioning[map.slot_contributions[k] / 3];
        bound += vulkan::detail::stiffness_error_bound(triangle);
        magnitude += triangle;  // Bounds |contribution| (kappa |C| / 2 <= kappa^2 s |C|).
      }
      bounds[slot] = bound + static_cast<double>(last - first) * unit_roundoff * magnitude;
      off_diagonal_bound += bounds[slot];
      off_diagonal_magnitude += std::abs(expected.valuePtr()[slot]) + bounds[slot];
    }
    if (diagonal >= 0)
      bounds[diagonal] =
          off_diagonal_bound + (end - begin) * unit_roundoff * off_diagonal_magnitude;
  }
  return bounds;
}

}  // namespace harmonia::testing
