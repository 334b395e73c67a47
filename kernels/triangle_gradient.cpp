// The embedded SPIR-V of shaders/triangle_gradient.comp (its only translation unit).
#include <cstdint>

#include "kernels/triangle_calculus.h"
#include "triangle_gradient.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram triangle_gradient_program{
    "triangle_gradient", triangle_gradient_spv, sizeof(triangle_gradient_spv),
    static_cast<std::uint32_t>(TriangleGradientBinding::count), sizeof(TriangleGradientPush)};

}  // namespace harmonia::vulkan::detail
