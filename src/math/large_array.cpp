#include "math/large_array.hpp"

#include <atomic>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace fulcrum::detail {

namespace {

std::atomic<bool> gHugePages{true};
std::atomic<std::size_t> gLargeAllocations{0};

// Advises the whole 2 MiB pieces of [p, p + bytes); p is 2 MiB aligned. A
// kernel without transparent huge pages refuses (EINVAL): the array then
// keeps plain pages, which is all the advice could change.
void adviseHugePages(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const std::size_t whole = bytes / kHugePageBytes * kHugePageBytes;
    if (whole != 0) (void)madvise(p, whole, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

}  // namespace

void setLargeArrayHugePages(bool on) { gHugePages.store(on, std::memory_order_relaxed); }
bool largeArrayHugePages() { return gHugePages.load(std::memory_order_relaxed); }
std::size_t largeArrayAllocationCount() { return gLargeAllocations.load(std::memory_order_relaxed); }

void* allocateArrayBytes(std::size_t bytes) {
    if (bytes < kLargeArrayBytes) return ::operator new(bytes);
    void* p = ::operator new(bytes, std::align_val_t{kHugePageBytes});
    gLargeAllocations.fetch_add(1, std::memory_order_relaxed);
    if (largeArrayHugePages()) adviseHugePages(p, bytes);
    return p;
}

void releaseArrayBytes(void* p, std::size_t bytes) noexcept {
    if (bytes < kLargeArrayBytes) {
        ::operator delete(p);
    } else {
        ::operator delete(p, std::align_val_t{kHugePageBytes});
    }
}

}  // namespace fulcrum::detail
