// The embedded SPIR-V of shaders/minres_update.comp (its only translation unit).
#include <cstdint>

#include "kernels/minres.h"
#include "minres_update.spv.h"
#include "minres_update_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram minres_update_fp64_program{
    "minres_update_fp64", minres_update_fp64_spv, sizeof(minres_update_fp64_spv),
    static_cast<std::uint32_t>(MinresUpdateBinding::count), sizeof(MinresUpdatePush)};
}  // namespace

const KernelProgram minres_update_program{
    "minres_update",           minres_update_spv,
    sizeof(minres_update_spv), static_cast<std::uint32_t>(MinresUpdateBinding::count),
    sizeof(MinresUpdatePush),  &minres_update_fp64_program};

}  // namespace harmonia::vulkan::detail
