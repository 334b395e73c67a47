// The embedded SPIR-V of shaders/dot_final.comp (its only translation unit).
#include <cstdint>

#include "dot_final.spv.h"
#include "dot_final_fp64.spv.h"
#include "kernels/reduction.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram dot_final_fp64_program{
    "dot_final_fp64", dot_final_fp64_spv, sizeof(dot_final_fp64_spv),
    static_cast<std::uint32_t>(DotFinalBinding::count), sizeof(DotFinalPush)};
}  // namespace

const KernelProgram dot_final_program{
    "dot_final",           dot_final_spv,
    sizeof(dot_final_spv), static_cast<std::uint32_t>(DotFinalBinding::count),
    sizeof(DotFinalPush),  &dot_final_fp64_program};

}  // namespace harmonia::vulkan::detail
