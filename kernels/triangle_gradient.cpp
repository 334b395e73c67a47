// The embedded SPIR-V of shaders/triangle_gradient.comp (its only translation unit).
#include <cstdint>

#include "kernels/triangle_calculus.h"
#include "triangle_gradient.spv.h"
#include "triangle_gradient_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram triangle_gradient_fp64_program{
    "triangle_gradient_fp64", triangle_gradient_fp64_spv, sizeof(triangle_gradient_fp64_spv),
    static_cast<std::uint32_t>(TriangleGradientBinding::count), sizeof(TriangleGradientPush)};
}  // namespace

const KernelProgram triangle_gradient_program{
    "triangle_gradient",           triangle_gradient_spv,
    sizeof(triangle_gradient_spv), static_cast<std::uint32_t>(TriangleGradientBinding::count),
    sizeof(TriangleGradientPush),  &triangle_gradient_fp64_program};

}  // namespace harmonia::vulkan::detail
