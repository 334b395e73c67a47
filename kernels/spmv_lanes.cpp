// The embedded SPIR-V of shaders/spmv_lanes.comp (its only translation unit).
#include <cstdint>

#include "kernels/spmv.h"
#include "spmv_lanes.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram spmv_lanes_program{"spmv_lanes", spmv_lanes_spv, sizeof(spmv_lanes_spv),
                                       static_cast<std::uint32_t>(SpmvBinding::count),
                                       sizeof(SpmvPush)};

}  // namespace harmonia::vulkan::detail
