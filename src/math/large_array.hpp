#pragma once
// LargeArrayAllocator<T> and LargeArray<T>: the allocator of the per-body and
// per-node arrays that grow with the world (the body store's records, the
// trees' nodes and build items, the broad phase's proxy records, the contact
// manager's per-slot arrays and its contact pool), and a std::vector that
// uses it.
//
// Why: a world of a million static bodies (Box3D's large_world) touches
// ~650 MB of fresh memory while it is built, and on a virtual machine every
// 4 KiB page of it costs a guest fault and a host fault. On the issue 21
// benchmark machine (an AMD EPYC guest, transparent huge pages in `madvise`
// mode) touching 650 MB took 2.3-2.4 s of CPU in 4 KiB pages and 1.2-1.4 s
// in 2 MiB pages, and large_world's whole process ~2.7 s against ~1.1-1.8 s
// with glibc's huge-page tunable (docs/benchmarks.md, branch `hs13`).
//
// How: an array of at least kLargeArrayBytes (2 MiB) is allocated aligned to
// 2 MiB (the aligned operator new, so the allocation counters and budgets of
// the tests see it like any other) and, on Linux, advised MADV_HUGEPAGE over
// its whole 2 MiB pieces, so the kernel backs those with huge pages when it
// can. Smaller arrays, and every array elsewhere than on Linux, are a plain
// operator new's. Nothing depends on where an array lives: the values and
// the results are the same with and without the advice (tests/math/
// large_array_test.cpp steps a world both ways, bit for bit).
//
// For users: where transparent huge pages are `never` (or not built into the
// kernel) the advice does nothing and the arrays are plain pages; where they
// are `madvise` or `always` a large array's resident size is rounded up to
// whole 2 MiB pages once its pieces are touched (at most 2 MiB per array over
// its capacity in bytes). setLargeArrayHugePages(false) turns the advice off
// for arrays allocated after the call (tests; the results do not change).
#include <cstddef>
#include <limits>
#include <new>
#include <vector>

namespace fulcrum::detail {

// Arrays of this many bytes or more are aligned to kHugePageBytes and advised.
inline constexpr std::size_t kLargeArrayBytes = std::size_t{2} << 20;
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;
// Only where the advice exists: elsewhere (WebAssembly's linear memory, say)
// the alignment would waste real memory for nothing.
#if defined(__linux__)
inline constexpr bool kLargeArraysAligned = true;
#else
inline constexpr bool kLargeArraysAligned = false;
#endif

// Whether large arrays allocated from now on are advised to use huge pages
// (default true). Process-wide; the same results either way.
void setLargeArrayHugePages(bool on);
bool largeArrayHugePages();
// How many large arrays have been allocated in this process (a test's check
// that a steady step allocates none).
std::size_t largeArrayAllocationCount();

// `bytes` from the plain or the large path (by size); throws std::bad_alloc
// when the memory is not there. Release with the same byte count.
void* allocateArrayBytes(std::size_t bytes);
void releaseArrayBytes(void* p, std::size_t bytes) noexcept;

template <class T>
struct LargeArrayAllocator {
    static_assert(alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__, "the plain path is operator new's default alignment");
    using value_type = T;

    LargeArrayAllocator() noexcept = default;
    template <class U>
    LargeArrayAllocator(const LargeArrayAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > std::numeric_limits<std::size_t>::max() / sizeof(T)) throw std::bad_array_new_length();
        return static_cast<T*>(allocateArrayBytes(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { releaseArrayBytes(p, n * sizeof(T)); }

    template <class U>
    bool operator==(const LargeArrayAllocator<U>&) const noexcept {
        return true;
    }
};

template <class T>
using LargeArray = std::vector<T, LargeArrayAllocator<T>>;

}  // namespace fulcrum::detail
