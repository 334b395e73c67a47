// The embedded SPIR-V of shaders/vertex_gather.comp (its only translation unit).
#include <cstdint>

#include "kernels/triangle_calculus.h"
#include "vertex_gather.spv.h"
#include "vertex_gather_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram vertex_gather_fp64_program{
    "vertex_gather_fp64", vertex_gather_fp64_spv, sizeof(vertex_gather_fp64_spv),
    static_cast<std::uint32_t>(VertexGatherBinding::count), sizeof(VertexGatherPush)};
}  // namespace

const KernelProgram vertex_gather_program{
    "vertex_gather",           vertex_gather_spv,
    sizeof(vertex_gather_spv), static_cast<std::uint32_t>(VertexGatherBinding::count),
    sizeof(VertexGatherPush),  &vertex_gather_fp64_program};

}  // namespace harmonia::vulkan::detail
