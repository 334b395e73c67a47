// The embedded SPIR-V of shaders/dot_partial.comp (its only translation unit).
#include <cstdint>

#include "dot_partial.spv.h"
#include "dot_partial_fp64.spv.h"
#include "kernels/reduction.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram dot_partial_fp64_program{
    "dot_partial_fp64", dot_partial_fp64_spv, sizeof(dot_partial_fp64_spv),
    static_cast<std::uint32_t>(DotPartialBinding::count), sizeof(DotPartialPush)};
}  // namespace

const KernelProgram dot_partial_program{
    "dot_partial",           dot_partial_spv,
    sizeof(dot_partial_spv), static_cast<std::uint32_t>(DotPartialBinding::count),
    sizeof(DotPartialPush),  &dot_partial_fp64_program};

}  // namespace harmonia::vulkan::detail
