// The embedded SPIR-V of shaders/slot_gather.comp (its only translation unit).
#include <cstdint>

#include "kernels/triangle_assembly.h"
#include "slot_gather.spv.h"
#include "slot_gather_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram slot_gather_fp64_program{
    "slot_gather_fp64", slot_gather_fp64_spv, sizeof(slot_gather_fp64_spv),
    static_cast<std::uint32_t>(SlotGatherBinding::count), sizeof(SlotGatherPush)};
}  // namespace

const KernelProgram slot_gather_program{
    "slot_gather",           slot_gather_spv,
    sizeof(slot_gather_spv), static_cast<std::uint32_t>(SlotGatherBinding::count),
    sizeof(SlotGatherPush),  &slot_gather_fp64_program};

}  // namespace harmonia::vulkan::detail
