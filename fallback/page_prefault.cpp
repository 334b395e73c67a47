#include "fallback/page_prefault.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace harmonia::detail {

void prefault_backward(void* begin, std::size_t bytes, const std::atomic<bool>& stop) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  constexpr std::uintptr_t kChunk = std::uintptr_t{4} << 20;
  // The whole pages inside the range.
  const std::uintptr_t first = (reinterpret_cast<std::uintptr_t>(begin) + page - 1) / page * page;
  std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(begin) + bytes) / page * page;
  while (end > first && !stop.load(std::memory_order_relaxed)) {
    const std::uintptr_t start = end - first > kChunk ? end - kChunk : first;
    if (madvise(reinterpret_cast<void*>(start), end - start, MADV_POPULATE_WRITE) != 0) return;
    end = start;
  }
#else
  (void)begin;
  (void)bytes;
  (void)stop;
#endif
}

}  // namespace harmonia::detail
