// The embedded SPIR-V of shaders/pcg_update.comp (its only translation unit).
#include <cstdint>

#include "kernels/pcg.h"
#include "pcg_update.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram pcg_update_program{"pcg_update", pcg_update_spv, sizeof(pcg_update_spv),
                                       static_cast<std::uint32_t>(PcgUpdateBinding::count),
                                       sizeof(PcgUpdatePush)};

}  // namespace harmonia::vulkan::detail
