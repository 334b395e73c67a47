#include "kernels/buffer.h"

#include <cstdio>
#include <utility>

#include "harmonia/types.h"

namespace harmonia::vulkan::detail {
namespace {

// The first memory type allowed by `type_bits` with all of `required` (and, if any such type has
// them, all of `preferred` too); -1 when none.
int find_memory_type(const VkPhysicalDeviceMemoryProperties& memory, std::uint32_t type_bits,
                     VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) {
  int fallback = -1;
  for (std::uint32_t type = 0; type < memory.memoryTypeCount; ++type) {
    if ((type_bits & (1u << type)) == 0) continue;
    const VkMemoryPropertyFlags flags = memory.memoryTypes[type].propertyFlags;
    if ((flags & required) != required) continue;
    if ((flags & preferred) == preferred) return static_cast<int>(type);
    if (fallback < 0) fallback = static_cast<int>(type);
  }
  return fallback;
}

}  // namespace

std::string mebibytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
  return text;
}

Buffer::Buffer(Context::Impl& context, std::uint64_t bytes, BufferRole role,
               const std::string& what)
    : context_(&context), bytes_(bytes) {
  const VulkanFunctions& vk = context.vk;
  if (role == BufferRole::device && bytes > context.info.max_storage_buffer_range)
    throw Error(Status::device_failure,
                "the " + what + " buffer needs " + mebibytes(bytes) + " but the device (" +
                    context.info.name + ") binds at most " +
                    mebibytes(context.info.max_storage_buffer_range) +
                    " per storage buffer (maxStorageBufferRange); use the CPU backend for a "
                    "problem this large");
  if (role == BufferRole::device && context.info.device_local_bytes > 0 &&
      bytes > context.info.device_local_bytes)
    throw Error(Status::device_failure,
                "the " + what + " buffer needs " + mebibytes(bytes) + " but the device has " +
                    mebibytes(context.info.device_local_bytes) + " of device-local memory");

  auto info = vk_info<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = std::max<std::uint64_t>(bytes, 16);
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  switch (role) {
    case BufferRole::device:
      info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                   VK_BUFFER_USAGE_TRANSFER_DST_BIT;
      break;
    case BufferRole::staging:
      info.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
      break;
    case BufferRole::readback:
      info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
      break;
  }
  const std::string action = "allocating the " + what + " buffer (" + mebibytes(bytes) + ")";
  check(vk.vkCreateBuffer(context.device, &info, context.allocator, &buffer_), action.c_str());

  VkMemoryRequirements requirements{};
  vk.vkGetBufferMemoryRequirements(context.device, buffer_, &requirements);
  const VkMemoryPropertyFlags host =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  int type = -1;
  switch (role) {
    case BufferRole::device:
      type = context.info.unified_memory
                 ? find_memory_type(context.memory, requirements.memoryTypeBits,
                                    VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | host, 0)
                 : -1;
      if (type < 0)
        type = find_memory_type(context.memory, requirements.memoryTypeBits,
                                VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0);
      break;
    case BufferRole::staging:
      type = find_memory_type(context.memory, requirements.memoryTypeBits, host, 0);
      break;
    case BufferRole::readback:
      type = find_memory_type(context.memory, requirements.memoryTypeBits, host,
                              VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
      break;
  }
  if (type < 0) {
    release();
    throw Error(Status::device_failure, action + ": the device offers no suitable memory type");
  }
  auto allocate = vk_info<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex = static_cast<std::uint32_t>(type);
  // An injected failure (kernels/fault_injection.h) stands in for the driver's out-of-memory.
  const VkResult allocated =
      context.faults.next_allocation_fails()
          ? VK_ERROR_OUT_OF_DEVICE_MEMORY
          : vk.vkAllocateMemory(context.device, &allocate, context.allocator, &memory_);
  if (allocated != VK_SUCCESS) {
    release();
    check(allocated, action.c_str());
  }
  try {
    check(vk.vkBindBufferMemory(context.device, buffer_, memory_, 0), action.c_str());
    if (context.memory.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
      check(vk.vkMapMemory(context.device, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), action.c_str());
  } catch (...) {
    release();
    throw;
  }
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& other) noexcept
    : context_(other.context_),
      buffer_(std::exchange(other.buffer_, VK_NULL_HANDLE)),
      memory_(std::exchange(other.memory_, VK_NULL_HANDLE)),
      bytes_(other.bytes_),
      mapped_(std::exchange(other.mapped_, nullptr)) {}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    context_ = other.context_;
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    bytes_ = other.bytes_;
    mapped_ = std::exchange(other.mapped_, nullptr);
  }
  return *this;
}

void Buffer::release() noexcept {
  if (context_ == nullptr) return;
  const VulkanFunctions& vk = context_->vk;
  if (mapped_ != nullptr) vk.vkUnmapMemory(context_->device, memory_);
  if (buffer_ != VK_NULL_HANDLE) vk.vkDestroyBuffer(context_->device, buffer_, context_->allocator);
  if (memory_ != VK_NULL_HANDLE) vk.vkFreeMemory(context_->device, memory_, context_->allocator);
  mapped_ = nullptr;
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

}  // namespace harmonia::vulkan::detail
