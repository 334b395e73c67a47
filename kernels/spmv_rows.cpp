// The embedded SPIR-V of shaders/spmv_rows.comp (its only translation unit).
#include <cstdint>

#include "kernels/spmv.h"
#include "spmv_rows.spv.h"
#include "spmv_rows_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram spmv_rows_fp64_program{
    "spmv_rows_fp64", spmv_rows_fp64_spv, sizeof(spmv_rows_fp64_spv),
    static_cast<std::uint32_t>(SpmvBinding::count), sizeof(SpmvPush)};
}  // namespace

const KernelProgram spmv_rows_program{
    "spmv_rows",           spmv_rows_spv,
    sizeof(spmv_rows_spv), static_cast<std::uint32_t>(SpmvBinding::count),
    sizeof(SpmvPush),      &spmv_rows_fp64_program};

}  // namespace harmonia::vulkan::detail
