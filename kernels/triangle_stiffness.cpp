// The embedded SPIR-V of shaders/triangle_stiffness.comp (its only translation unit).
#include <cstdint>

#include "kernels/triangle_assembly.h"
#include "triangle_stiffness.spv.h"
#include "triangle_stiffness_fp64.spv.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram triangle_stiffness_fp64_program{
    "triangle_stiffness_fp64", triangle_stiffness_fp64_spv, sizeof(triangle_stiffness_fp64_spv),
    static_cast<std::uint32_t>(TriangleStiffnessBinding::count), sizeof(TriangleStiffnessPush)};
}  // namespace

const KernelProgram triangle_stiffness_program{
    "triangle_stiffness",           triangle_stiffness_spv,
    sizeof(triangle_stiffness_spv), static_cast<std::uint32_t>(TriangleStiffnessBinding::count),
    sizeof(TriangleStiffnessPush),  &triangle_stiffness_fp64_program};

}  // namespace harmonia::vulkan::detail
