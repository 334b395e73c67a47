// The embedded SPIR-V of shaders/block_dot.comp (its only translation unit).
#include <cstdint>

#include "block_dot.spv.h"
#include "block_dot_fp64.spv.h"
#include "kernels/block_pcg.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram block_dot_fp64_program{
    "block_dot_fp64", block_dot_fp64_spv, sizeof(block_dot_fp64_spv),
    static_cast<std::uint32_t>(BlockDotBinding::count), sizeof(BlockDotPush)};
}  // namespace

const KernelProgram block_dot_program{
    "block_dot",           block_dot_spv,
    sizeof(block_dot_spv), static_cast<std::uint32_t>(BlockDotBinding::count),
    sizeof(BlockDotPush),  &block_dot_fp64_program};

}  // namespace harmonia::vulkan::detail
