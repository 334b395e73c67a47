// The embedded SPIR-V of shaders/linear_combination.comp (its only translation unit).
#include <cstdint>

#include "kernels/vector_ops.h"
#include "linear_combination.spv.h"
#include "linear_combination_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram linear_combination_fp64_program{
    "linear_combination_fp64", linear_combination_fp64_spv, sizeof(linear_combination_fp64_spv),
    static_cast<std::uint32_t>(LinearCombinationBinding::count), sizeof(LinearCombinationPush)};
}  // namespace

const KernelProgram linear_combination_program{
    "linear_combination",           linear_combination_spv,
    sizeof(linear_combination_spv), static_cast<std::uint32_t>(LinearCombinationBinding::count),
    sizeof(LinearCombinationPush),  &linear_combination_fp64_program};

}  // namespace harmonia::vulkan::detail
