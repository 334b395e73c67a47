// The embedded SPIR-V of shaders/block_pcg_direction.comp (its only translation unit).
#include <cstdint>

#include "block_pcg_direction.spv.h"
#include "block_pcg_direction_fp64.spv.h"
#include "kernels/block_pcg.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram block_pcg_direction_fp64_program{
    "block_pcg_direction_fp64", block_pcg_direction_fp64_spv, sizeof(block_pcg_direction_fp64_spv),
    static_cast<std::uint32_t>(BlockPcgDirectionBinding::count), sizeof(BlockPcgDirectionPush)};
}  // namespace

const KernelProgram block_pcg_direction_program{
    "block_pcg_direction",           block_pcg_direction_spv,
    sizeof(block_pcg_direction_spv), static_cast<std::uint32_t>(BlockPcgDirectionBinding::count),
    sizeof(BlockPcgDirectionPush),   &block_pcg_direction_fp64_program};

}  // namespace harmonia::vulkan::detail
