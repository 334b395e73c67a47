// prefault_backward: the pages of a fresh allocation are mapped in without a change to what was
// written in them, and a raised stop flag leaves them alone.
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "fallback/page_prefault.h"

namespace harmonia {
namespace {

// A fresh anonymous mapping of `pages` pages (nothing mapped in yet).
struct FreshPages {
  explicit FreshPages(std::size_t pages)
      : page(static_cast<std::size_t>(sysconf(_SC_PAGESIZE))), bytes(pages * page) {
    memory = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  }
  ~FreshPages() {
    if (memory != MAP_FAILED) munmap(memory, bytes);
  }
  // How many of the pages are resident.
  [[nodiscard]] std::size_t resident() const {
    std::vector<unsigned char> status(bytes / page);
    if (mincore(memory, bytes, status.data()) != 0) return 0;
    std::size_t count = 0;
    for (const unsigned char s : status) count += s & 1U;
    return count;
  }
  std::size_t page, bytes;
  void* memory = MAP_FAILED;
};

TEST(PagePrefault, MapsInEveryPageAndKeepsTheirContents) {
  FreshPages pages(64);
  ASSERT_NE(pages.memory, MAP_FAILED);
  auto* bytes = static_cast<unsigned char*>(pages.memory);
  std::memset(bytes, 0x5a, pages.page);  // The writer has filled the first page.
  EXPECT_EQ(pages.resident(), 1U);
  const std::atomic<bool> stop = false;
  detail::prefault_backward(pages.memory, pages.bytes, stop);
#ifdef MADV_POPULATE_WRITE
  FreshPages probe(1);
  if (madvise(probe.memory, probe.bytes, MADV_POPULATE_WRITE) != 0)
    GTEST_SKIP() << "the kernel has no MADV_POPULATE_WRITE";
  EXPECT_EQ(pages.resident(), 64U);
#endif
  for (std::size_t k = 0; k < pages.page; ++k) ASSERT_EQ(bytes[k], 0x5a) << k;
  for (std::size_t k = pages.page; k < pages.bytes; ++k) ASSERT_EQ(bytes[k], 0) << k;
}

TEST(PagePrefault, ARaisedStopLeavesThePagesAlone) {
  FreshPages pages(64);
  ASSERT_NE(pages.memory, MAP_FAILED);
  const std::atomic<bool> stop = true;
  detail::prefault_backward(pages.memory, pages.bytes, stop);
  EXPECT_EQ(pages.resident(), 0U);
}

}  // namespace
}  // namespace harmonia
