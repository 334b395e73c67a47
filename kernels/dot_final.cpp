// The embedded SPIR-V of shaders/dot_final.comp (its only translation unit).
#include <cstdint>

#include "dot_final.spv.h"
#include "kernels/reduction.h"

namespace harmonia::vulkan::detail {

const KernelProgram dot_final_program{"dot_final", dot_final_spv, sizeof(dot_final_spv),
                                      static_cast<std::uint32_t>(DotFinalBinding::count),
                                      sizeof(DotFinalPush)};

}  // namespace harmonia::vulkan::detail
