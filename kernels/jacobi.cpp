// The embedded SPIR-V of shaders/jacobi.comp (its only translation unit).
#include <cstdint>

#include "jacobi.spv.h"
#include "kernels/vector_ops.h"

namespace harmonia::vulkan::detail {

const KernelProgram jacobi_program{"jacobi", jacobi_spv, sizeof(jacobi_spv),
                                   static_cast<std::uint32_t>(JacobiBinding::count),
                                   sizeof(JacobiPush)};

}  // namespace harmonia::vulkan::detail
