// The embedded SPIR-V of shaders/spmv_rows.comp (its only translation unit).
#include <cstdint>

#include "kernels/spmv.h"
#include "spmv_rows.spv.h"

namespace harmonia::vulkan::detail {

const KernelProgram spmv_rows_program{"spmv_rows", spmv_rows_spv, sizeof(spmv_rows_spv),
                                      static_cast<std::uint32_t>(SpmvBinding::count),
                                      sizeof(SpmvPush)};

}  // namespace harmonia::vulkan::detail
