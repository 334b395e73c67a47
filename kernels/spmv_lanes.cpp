// The embedded SPIR-V of shaders/spmv_lanes.comp (its only translation unit).
#include <cstdint>

#include "kernels/spmv.h"
#include "spmv_lanes.spv.h"
#include "spmv_lanes_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram spmv_lanes_fp64_program{
    "spmv_lanes_fp64", spmv_lanes_fp64_spv, sizeof(spmv_lanes_fp64_spv),
    static_cast<std::uint32_t>(SpmvBinding::count), sizeof(SpmvPush)};
}  // namespace

const KernelProgram spmv_lanes_program{
    "spmv_lanes",           spmv_lanes_spv,
    sizeof(spmv_lanes_spv), static_cast<std::uint32_t>(SpmvBinding::count),
    sizeof(SpmvPush),       &spmv_lanes_fp64_program};

}  // namespace harmonia::vulkan::detail
