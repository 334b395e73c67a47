#pragma once
// Internal: the arithmetic type of the device kernels (DevicePrecision) on the host side: how
// many bytes a real takes in a buffer and how doubles become device reals and back. Every shader
// exists in both precisions (shaders/common/real.glsl); the buffers of one backend all hold the
// same type, chosen when the backend is created.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "harmonia/solver_options.h"

namespace harmonia::vulkan::detail {

//! Bytes of one real in a device buffer: 4 (fp32) or 8 (fp64).
[[nodiscard]] constexpr std::uint64_t real_bytes(DevicePrecision precision) {
  return precision == DevicePrecision::float64 ? 8 : 4;
}
//! Bytes of `count` reals.
[[nodiscard]] constexpr std::uint64_t real_bytes(DevicePrecision precision, std::uint64_t count) {
  return real_bytes(precision) * count;
}

//! "fp32" or "fp64", for descriptions and messages.
[[nodiscard]] const char* precision_name(DevicePrecision precision);

//! `count` doubles as device reals (raw bytes, ready to copy into a buffer). In fp32 a finite
//! value beyond float's range is refused (harmonia::Error, Status::unsupported; `what` names
//! the data); in fp64 the values are copied unchanged.
[[nodiscard]] std::vector<std::byte> encode_reals(const double* values, std::size_t count,
                                                  DevicePrecision precision, const char* what);

//! `count` device reals (as read from a buffer) widened to double.
void decode_reals(const std::byte* bytes, std::size_t count, DevicePrecision precision,
                  double* values);

}  // namespace harmonia::vulkan::detail
