// The embedded SPIR-V of shaders/pcg_update.comp (its only translation unit).
#include <cstdint>

#include "kernels/pcg.h"
#include "pcg_update.spv.h"
#include "pcg_update_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram pcg_update_fp64_program{
    "pcg_update_fp64", pcg_update_fp64_spv, sizeof(pcg_update_fp64_spv),
    static_cast<std::uint32_t>(PcgUpdateBinding::count), sizeof(PcgUpdatePush)};
}  // namespace

const KernelProgram pcg_update_program{
    "pcg_update",           pcg_update_spv,
    sizeof(pcg_update_spv), static_cast<std::uint32_t>(PcgUpdateBinding::count),
    sizeof(PcgUpdatePush),  &pcg_update_fp64_program};

}  // namespace harmonia::vulkan::detail
