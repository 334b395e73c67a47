// The embedded SPIR-V of shaders/corner_terms.comp (its only translation unit).
#include <cstdint>

#include "kernels/triangle_calculus.h"
#include "corner_terms.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram corner_terms_program{"corner_terms", corner_terms_spv, sizeof(corner_terms_spv),
                                         static_cast<std::uint32_t>(CornerTermsBinding::count),
                                         sizeof(CornerTermsPush)};

}  // namespace harmonia::vulkan::detail
