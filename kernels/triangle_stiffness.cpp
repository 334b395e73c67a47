// The embedded SPIR-V of shaders/triangle_stiffness.comp (its only translation unit).
#include <cstdint>

#include "kernels/triangle_assembly.h"
#include "triangle_stiffness.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram triangle_stiffness_program{
    "triangle_stiffness", triangle_stiffness_spv, sizeof(triangle_stiffness_spv),
    static_cast<std::uint32_t>(TriangleStiffnessBinding::count), sizeof(TriangleStiffnessPush)};

}  // namespace harmonia::vulkan::detail
