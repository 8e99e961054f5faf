#include "math/large_array.hpp"

#include <atomic>
#include <cstdint>
#include <new>

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

// No user address space holds 2^48 bytes (x86-64's and AArch64's hold at
// most that; wasm32's 2^32): a request beyond it is refused here with
// bad_alloc, before any allocator sees it. AddressSanitizer's allocator
// aborts the process on such a request instead of throwing.
constexpr std::uint64_t kMaxArrayBytes = std::uint64_t{1} << 48;

void* allocateArrayBytes(std::size_t bytes) {
    if (static_cast<std::uint64_t>(bytes) > kMaxArrayBytes) throw std::bad_alloc();
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
