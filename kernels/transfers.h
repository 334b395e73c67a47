#pragma once
// Internal: moving data between the host and device buffers. On unified memory the buffer is
// mapped and the copy is a memcpy; otherwise it goes through a staging (or readback) buffer and
// one submission on `recorder`, which waits for it.

#include <cstdint>

#include "backend/backend.h"
#include "kernels/buffer.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

void write_buffer(CommandRecorder& recorder, Buffer& target, const void* data, std::uint64_t bytes,
                  std::uint64_t offset = 0);
void read_buffer(CommandRecorder& recorder, const Buffer& source, void* data, std::uint64_t bytes,
                 std::uint64_t offset = 0);

//! `pattern` with its values replaced by the device reals in `source` (fp32 or fp64), one per
//! stored entry in CSR order (how the fixed-pattern assembly kernels leave their result).
[[nodiscard]] harmonia::detail::RowMajorSparse read_pattern_values(
    CommandRecorder& recorder, const Buffer& source,
    const harmonia::detail::RowMajorSparse& pattern,
    DevicePrecision precision = DevicePrecision::float32);

}  // namespace harmonia::vulkan::detail
