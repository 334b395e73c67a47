// The embedded SPIR-V of shaders/pcg_scalars.comp (its only translation unit).
#include <cstdint>

#include "kernels/pcg.h"
#include "pcg_scalars.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram pcg_scalars_program{"pcg_scalars", pcg_scalars_spv, sizeof(pcg_scalars_spv),
                                        static_cast<std::uint32_t>(PcgScalarsBinding::count),
                                        sizeof(PcgScalarsPush)};

}  // namespace harmonia::vulkan::detail
