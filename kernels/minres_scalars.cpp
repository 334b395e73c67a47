// The embedded SPIR-V of shaders/minres_scalars.comp (its only translation unit).
#include <cstdint>

#include "kernels/minres.h"
#include "minres_scalars.spv.h"
#include "minres_scalars_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram minres_scalars_fp64_program{
    "minres_scalars_fp64", minres_scalars_fp64_spv, sizeof(minres_scalars_fp64_spv),
    static_cast<std::uint32_t>(MinresScalarsBinding::count), sizeof(MinresScalarsPush)};
}  // namespace

const KernelProgram minres_scalars_program{
    "minres_scalars",           minres_scalars_spv,
    sizeof(minres_scalars_spv), static_cast<std::uint32_t>(MinresScalarsBinding::count),
    sizeof(MinresScalarsPush),  &minres_scalars_fp64_program};

}  // namespace harmonia::vulkan::detail
