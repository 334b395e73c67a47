// The embedded SPIR-V of shaders/block_pcg_update.comp (its only translation unit).
#include <cstdint>

#include "block_pcg_update.spv.h"
#include "block_pcg_update_fp64.spv.h"
#include "kernels/block_pcg.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram block_pcg_update_fp64_program{
    "block_pcg_update_fp64", block_pcg_update_fp64_spv, sizeof(block_pcg_update_fp64_spv),
    static_cast<std::uint32_t>(BlockPcgUpdateBinding::count), sizeof(BlockPcgUpdatePush)};
}  // namespace

const KernelProgram block_pcg_update_program{
    "block_pcg_update",           block_pcg_update_spv,
    sizeof(block_pcg_update_spv), static_cast<std::uint32_t>(BlockPcgUpdateBinding::count),
    sizeof(BlockPcgUpdatePush),   &block_pcg_update_fp64_program};

}  // namespace harmonia::vulkan::detail
