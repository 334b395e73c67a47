// The embedded SPIR-V of shaders/jacobi.comp (its only translation unit).
#include <cstdint>

#include "jacobi.spv.h"
#include "jacobi_fp64.spv.h"
#include "kernels/vector_ops.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram jacobi_fp64_program{"jacobi_fp64", jacobi_fp64_spv, sizeof(jacobi_fp64_spv),
                                        static_cast<std::uint32_t>(JacobiBinding::count),
                                        sizeof(JacobiPush)};
}  // namespace

const KernelProgram jacobi_program{
    "jacobi",           jacobi_spv,
    sizeof(jacobi_spv), static_cast<std::uint32_t>(JacobiBinding::count),
    sizeof(JacobiPush), &jacobi_fp64_program};

}  // namespace harmonia::vulkan::detail
