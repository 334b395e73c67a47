// The embedded SPIR-V of shaders/slot_gather.comp (its only translation unit).
#include <cstdint>

#include "kernels/triangle_assembly.h"
#include "slot_gather.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram slot_gather_program{"slot_gather", slot_gather_spv, sizeof(slot_gather_spv),
                                        static_cast<std::uint32_t>(SlotGatherBinding::count),
                                        sizeof(SlotGatherPush)};

}  // namespace harmonia::vulkan::detail
