#include "kernels/transfers.h"

#include <cstring>
#include <stdexcept>
#include <vector>

#include "kernels/device_reals.h"

namespace harmonia::vulkan::detail {

void write_buffer(CommandRecorder& recorder, Buffer& target, const void* data, std::uint64_t bytes,
                  std::uint64_t offset) {
  if (bytes == 0) return;
  if (offset + bytes > target.bytes()) throw std::logic_error("write_buffer: out of range");
  if (target.mapped() != nullptr) {
    std::memcpy(static_cast<char*>(target.mapped()) + offset, data, bytes);
    return;
  }
  Buffer staging(recorder.context(), bytes, BufferRole::staging, "staging");
  std::memcpy(staging.mapped(), data, bytes);
  recorder.begin();
  recorder.copy(staging, 0, target, offset, bytes);
  recorder.end();
  recorder.submit_and_wait();
}

void read_buffer(CommandRecorder& recorder, const Buffer& source, void* data, std::uint64_t bytes,
                 std::uint64_t offset) {
  if (bytes == 0) return;
  if (offset + bytes > source.bytes()) throw std::logic_error("read_buffer: out of range");
  if (source.mapped() != nullptr) {
    std::memcpy(data, static_cast<const char*>(source.mapped()) + offset, bytes);
    return;
  }
  Buffer readback(recorder.context(), bytes, BufferRole::readback, "readback");
  recorder.begin();
  recorder.copy(source, offset, readback, 0, bytes);
  recorder.end();
  recorder.submit_and_wait();
  std::memcpy(data, readback.mapped(), bytes);
}

harmonia::detail::RowMajorSparse read_pattern_values(
    CommandRecorder& recorder, const Buffer& source,
    const harmonia::detail::RowMajorSparse& pattern, DevicePrecision precision) {
  const auto count = static_cast<std::size_t>(pattern.nonZeros());
  std::vector<std::byte> bytes(real_bytes(precision, count));
  read_buffer(recorder, source, bytes.data(), bytes.size());
  harmonia::detail::RowMajorSparse result = pattern;
  decode_reals(bytes.data(), count, precision, result.valuePtr());
  return result;
}

}  // namespace harmonia::vulkan::detail
