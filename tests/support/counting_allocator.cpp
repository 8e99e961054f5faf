// The counting global operator new of counting_allocator.hpp. Every form of
// operator new, the nothrow ones included, is replaced here and ends in the
// counting functions below, so an allocation by any container, aligned (SIMD)
// types and std::stable_sort's nothrow temporary buffer included, is counted
// while counting is on. The nothrow forms are replaced too, not left to
// libstdc++ (whose versions would call ours): AddressSanitizer intercepts
// them itself, and its operator new paired with our free is a reported
// alloc-dealloc mismatch. The replacements pair malloc / aligned_alloc with
// free on purpose.
#include "support/counting_allocator.hpp"

#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<bool> gCounting{false};
std::atomic<long> gAllocations{0};
// HeapBudget: growth, its peak and the budget (-1: none) while gMeasuring.
std::atomic<bool> gMeasuring{false};
std::atomic<long long> gGrowth{0}, gPeak{0}, gBudget{-1};

void* allocate(std::size_t size, std::size_t alignment) {
    if (gCounting.load(std::memory_order_relaxed)) gAllocations.fetch_add(1, std::memory_order_relaxed);
    if (size == 0) size = 1;
    const bool measuring = gMeasuring.load(std::memory_order_relaxed);
    if (measuring) {
        const long long budget = gBudget.load(std::memory_order_relaxed);
        if (budget >= 0 && gGrowth.load(std::memory_order_relaxed) + static_cast<long long>(size) > budget) {
            throw std::bad_alloc();
        }
    }
    void* p = nullptr;
    if (alignment <= alignof(std::max_align_t)) {
        p = std::malloc(size);
    } else {
        size = (size + alignment - 1) / alignment * alignment;  // aligned_alloc wants a multiple
        p = std::aligned_alloc(alignment, size);
    }
    if (p == nullptr) throw std::bad_alloc();
    if (measuring) {
        const long long now =
            gGrowth.fetch_add(static_cast<long long>(malloc_usable_size(p)), std::memory_order_relaxed) +
            static_cast<long long>(malloc_usable_size(p));
        long long peak = gPeak.load(std::memory_order_relaxed);
        while (now > peak && !gPeak.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {
        }
    }
    return p;
}

void release(void* p) {
    if (p != nullptr && gMeasuring.load(std::memory_order_relaxed)) {
        gGrowth.fetch_sub(static_cast<long long>(malloc_usable_size(p)), std::memory_order_relaxed);
    }
    std::free(p);
}
}  // namespace

namespace fulcrum::test {
void setCountingAllocations(bool on) { gCounting.store(on, std::memory_order_relaxed); }
long allocationCount() { return gAllocations.load(std::memory_order_relaxed); }
void resetAllocationCount() { gAllocations.store(0, std::memory_order_relaxed); }

HeapBudget::HeapBudget(long long budgetBytes) {
    gGrowth.store(0, std::memory_order_relaxed);
    gPeak.store(0, std::memory_order_relaxed);
    gBudget.store(budgetBytes, std::memory_order_relaxed);
    gMeasuring.store(true, std::memory_order_relaxed);
}
HeapBudget::~HeapBudget() {
    gMeasuring.store(false, std::memory_order_relaxed);
    gBudget.store(-1, std::memory_order_relaxed);
}
long long HeapBudget::growth() const { return gGrowth.load(std::memory_order_relaxed); }
long long HeapBudget::peakGrowth() const { return gPeak.load(std::memory_order_relaxed); }
}  // namespace fulcrum::test

// GCC's sanitizer build inlines these into callers and flags the intended
// malloc/free pairing.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t size) { return allocate(size, 0); }
void* operator new[](std::size_t size) { return allocate(size, 0); }
void* operator new(std::size_t size, std::align_val_t a) { return allocate(size, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t size, std::align_val_t a) { return allocate(size, static_cast<std::size_t>(a)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return allocate(size, 0);
    } catch (const std::bad_alloc&) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return allocate(size, 0);
    } catch (const std::bad_alloc&) {
        return nullptr;
    }
}
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
    try {
        return allocate(size, static_cast<std::size_t>(a));
    } catch (const std::bad_alloc&) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
    try {
        return allocate(size, static_cast<std::size_t>(a));
    } catch (const std::bad_alloc&) {
        return nullptr;
    }
}
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release(p); }
