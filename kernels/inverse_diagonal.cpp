// The embedded SPIR-V of shaders/inverse_diagonal.comp (its only translation unit) and its
// dispatch for matrices whose values a kernel wrote.
#include <cstdint>
#include <limits>
#include <vector>

#include "inverse_diagonal.spv.h"
#include "inverse_diagonal_fp64.spv.h"
#include "kernels/device_arrays.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"
#include "kernels/transfers.h"

namespace harmonia::vulkan::detail {
namespace {

// Mirrors `Push` in shaders/inverse_diagonal.comp.
struct InverseDiagonalPush {
  std::uint32_t rows;
};
static_assert(sizeof(InverseDiagonalPush) == 4);

enum class InverseDiagonalBinding : std::uint32_t { diagonal_slots, values, inverse, count };

const KernelProgram inverse_diagonal_fp64_program{
    "inverse_diagonal_fp64", inverse_diagonal_fp64_spv, sizeof(inverse_diagonal_fp64_spv),
    static_cast<std::uint32_t>(InverseDiagonalBinding::count), sizeof(InverseDiagonalPush)};

const KernelProgram inverse_diagonal_program{
    "inverse_diagonal",           inverse_diagonal_spv,
    sizeof(inverse_diagonal_spv), static_cast<std::uint32_t>(InverseDiagonalBinding::count),
    sizeof(InverseDiagonalPush),  &inverse_diagonal_fp64_program};

constexpr std::uint32_t no_slot = std::numeric_limits<std::uint32_t>::max();

}  // namespace

void VulkanMatrix::record_inverse_diagonal(CommandRecorder& recorder) {
  const auto row_count = static_cast<std::size_t>(host_.rows());
  if (!diagonal_slots_) {
    std::vector<std::uint32_t> slots(row_count, no_slot);
    for (std::size_t row = 0; row < row_count; ++row) {
      for (int slot = host_.outerIndexPtr()[row]; slot < host_.outerIndexPtr()[row + 1]; ++slot)
        if (host_.innerIndexPtr()[slot] == static_cast<int>(row))
          slots[row] = static_cast<std::uint32_t>(slot);
    }
    diagonal_slots_ = std::make_unique<Buffer>(transfers_.context(), row_count * 4,
                                               BufferRole::device, "matrix diagonal slots");
    write_buffer(transfers_, *diagonal_slots_, slots.data(), slots.size() * 4);
  }
  recorder.dispatch(in_precision(inverse_diagonal_program, precision_),
                    {diagonal_slots_.get(), &values_, &inverse_diagonal_},
                    InverseDiagonalPush{static_cast<std::uint32_t>(row_count)},
                    recorder.groups_for(row_count));
}

}  // namespace harmonia::vulkan::detail
