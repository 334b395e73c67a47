// The embedded SPIR-V of shaders/corner_terms.comp (its only translation unit).
#include <cstdint>

#include "corner_terms.spv.h"
#include "corner_terms_fp64.spv.h"
#include "kernels/triangle_calculus.h"

namespace harmonia::vulkan::detail {

namespace {
// The same shader compiled with double arithmetic (shaders/common/real.glsl).
const KernelProgram corner_terms_fp64_program{
    "corner_terms_fp64", corner_terms_fp64_spv, sizeof(corner_terms_fp64_spv),
    static_cast<std::uint32_t>(CornerTermsBinding::count), sizeof(CornerTermsPush)};
}  // namespace

const KernelProgram corner_terms_program{
    "corner_terms",           corner_terms_spv,
    sizeof(corner_terms_spv), static_cast<std::uint32_t>(CornerTermsBinding::count),
    sizeof(CornerTermsPush),  &corner_terms_fp64_program};

}  // namespace harmonia::vulkan::detail
