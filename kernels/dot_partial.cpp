// The embedded SPIR-V of shaders/dot_partial.comp (its only translation unit).
#include <cstdint>

#include "dot_partial.spv.h"
#include "kernels/reduction.h"

namespace harmonia::vulkan::detail {

const KernelProgram dot_partial_program{"dot_partial", dot_partial_spv, sizeof(dot_partial_spv),
                                        static_cast<std::uint32_t>(DotPartialBinding::count),
                                        sizeof(DotPartialPush)};

}  // namespace harmonia::vulkan::detail
