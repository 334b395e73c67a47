// The embedded SPIR-V of shaders/linear_combination.comp (its only translation unit).
#include <cstdint>

#include "kernels/vector_ops.h"
#include "linear_combination.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram linear_combination_program{
    "linear_combination", linear_combination_spv, sizeof(linear_combination_spv),
    static_cast<std::uint32_t>(LinearCombinationBinding::count), sizeof(LinearCombinationPush)};

}  // namespace harmonia::vulkan::detail
