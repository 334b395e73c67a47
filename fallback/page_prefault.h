#pragma once
// Internal: a thread with nothing left to do maps in the pages of memory that another thread is
// about to fill, without touching its contents.
//
// Why: the first write to each fresh page of a large allocation stops the writing thread for the
// kernel to map and clear it. On the 2-core machine that costs 0.55 s per GB (up to 2.8 s per GB
// where the host has not backed the memory recently): in linear ABF's two-thread factorization the
// second half's factor (about 0.4 GB) spent 40-55 % of its time there while the first thread sat
// idle. MADV_POPULATE_WRITE (Linux 5.14) maps the pages as a write would, leaves their contents
// alone and is harmless on pages already mapped, so it can run beside the thread that writes
// them. Elsewhere (older kernels, other systems) prefault_backward() returns at once.
#include <atomic>
#include <cstddef>

namespace harmonia::detail {

//! Maps in the pages of [begin, begin + bytes) from the end backwards (the writer fills them from
//! the front), a few megabytes at a time, until all are mapped or `stop` becomes true.
void prefault_backward(void* begin, std::size_t bytes, const std::atomic<bool>& stop);

}  // namespace harmonia::detail
