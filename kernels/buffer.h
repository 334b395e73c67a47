#pragma once
// Internal: a Vulkan buffer with its own memory allocation. Move-only RAII; the Context must
// outlive it.
//
// Device buffers live in device-local memory. On unified-memory devices (integrated GPUs,
// lavapipe) that memory is also host-visible and coherent: the buffer is mapped and written in
// place. Elsewhere data goes through a host-visible staging buffer (kernels/transfers.h).

#include <cstdint>
#include <string>

#include "kernels/context_impl.h"

namespace harmonia::vulkan::detail {

enum class BufferRole {
  device,    // Storage buffer read and written by kernels (mapped only on unified memory).
  staging,   // Host-visible source of uploads.
  readback,  // Host-visible (cached where possible) destination of downloads.
};

class Buffer {
 public:
  // `what` names the buffer in error messages (e.g. "matrix values"). Before allocating, checks
  // the size against maxStorageBufferRange and the device-local heap; throws
  // harmonia::Error(Status::device_failure) with the sizes when it cannot fit, or when the driver
  // reports out of memory (or the context's fault injection makes it do so). A size of 0 is
  // rounded up (Vulkan has no empty buffers).
  Buffer(Context::Impl& context, std::uint64_t bytes, BufferRole role, const std::string& what);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  [[nodiscard]] VkBuffer handle() const { return buffer_; }
  [[nodiscard]] std::uint64_t bytes() const { return bytes_; }  // The requested size.
  // Host address of the contents, or null when the memory is not host-visible.
  [[nodiscard]] void* mapped() const { return mapped_; }

 private:
  void release() noexcept;
  Context::Impl* context_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  std::uint64_t bytes_ = 0;
  void* mapped_ = nullptr;
};

// "12.5 MiB" style text for messages.
[[nodiscard]] std::string mebibytes(std::uint64_t bytes);

}  // namespace harmonia::vulkan::detail
