#include "math/large_array.hpp"

#include <atomic>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace fulcrum::detail {

namespace {

std::atomic<bool> gHugePages{true};
std::atomic<std::size_t> gLargeAllocations{0};

}  // namespace

void setLargeArrayHugePages(bool on) { gHugePages.store(on, std::memory_order_relaxed); }
bool largeArrayHugePages() { return gHugePages.load(std::memory_order_relaxed); }
std::size_t largeArrayAllocationCount() { return gLargeAllocations.load(std::memory_order_relaxed); }

void* allocateArrayBytes(std::size_t bytes) {
    if (bytes < kLargeArrayBytes) return ::operator new(bytes);
    gLargeAllocations.fetch_add(1, std::memory_order_relaxed);
    if constexpr (!kLargeArraysAligned) {
        return ::operator new(bytes);
    } else {
        void* p = ::operator new(bytes, std::align_val_t{kHugePageBytes});
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        // The whole 2 MiB pieces. A kernel without transparent huge pages
        // refuses (EINVAL): the array keeps plain pages, all the advice changes.
        const std::size_t whole = bytes / kHugePageBytes * kHugePageBytes;
        if (largeArrayHugePages()) (void)madvise(p, whole, MADV_HUGEPAGE);
#endif
        return p;
    }
}

void releaseArrayBytes(void* p, std::size_t bytes) noexcept {
    if (!kLargeArraysAligned || bytes < kLargeArrayBytes) {
        ::operator delete(p);
    } else {
        ::operator delete(p, std::align_val_t{kHugePageBytes});
    }
}

}  // namespace fulcrum::detail
