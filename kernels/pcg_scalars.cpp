// The embedded SPIR-V of shaders/pcg_scalars.comp (its only translation unit).
#include <cstdint>

#include "kernels/pcg.h"
#include "pcg_scalars.spv.h"
#include "pcg_scalars_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram pcg_scalars_fp64_program{
    "pcg_scalars_fp64", pcg_scalars_fp64_spv, sizeof(pcg_scalars_fp64_spv),
    static_cast<std::uint32_t>(PcgScalarsBinding::count), sizeof(PcgScalarsPush)};
}  // namespace

const KernelProgram pcg_scalars_program{
    "pcg_scalars",           pcg_scalars_spv,
    sizeof(pcg_scalars_spv), static_cast<std::uint32_t>(PcgScalarsBinding::count),
    sizeof(PcgScalarsPush),  &pcg_scalars_fp64_program};

}  // namespace harmonia::vulkan::detail
