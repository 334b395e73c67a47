#include "kernels/device_reals.h"

#include <cstring>

#include "kernels/device_arrays.h"

namespace harmonia::vulkan::detail {

const char* precision_name(DevicePrecision precision) {
  return precision == DevicePrecision::float64 ? "fp64" : "fp32";
}

std::vector<std::byte> encode_reals(const double* values, std::size_t count,
                                    DevicePrecision precision, const char* what) {
  std::vector<std::byte> bytes(real_bytes(precision, count));
  if (count == 0) return bytes;
  if (precision == DevicePrecision::float64) {
    std::memcpy(bytes.data(), values, bytes.size());
  } else {
    const std::vector<float> rounded = to_float(values, count, what);
    std::memcpy(bytes.data(), rounded.data(), bytes.size());
  }
  return bytes;
}

void decode_reals(const std::byte* bytes, std::size_t count, DevicePrecision precision,
                  double* values) {
  if (precision == DevicePrecision::float64) {
    if (count > 0) std::memcpy(values, bytes, count * sizeof(double));
    return;
  }
  for (std::size_t k = 0; k < count; ++k) {
    float value = 0.0f;
    std::memcpy(&value, bytes + k * sizeof(float), sizeof(float));
    values[k] = value;
  }
}

}  // namespace harmonia::vulkan::detail
