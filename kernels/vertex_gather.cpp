// The embedded SPIR-V of shaders/vertex_gather.comp (its only translation unit).
#include <cstdint>

#include "kernels/triangle_calculus.h"
#include "vertex_gather.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram vertex_gather_program{
    "vertex_gather", vertex_gather_spv, sizeof(vertex_gather_spv),
    static_cast<std::uint32_t>(VertexGatherBinding::count), sizeof(VertexGatherPush)};

}  // namespace harmonia::vulkan::detail
