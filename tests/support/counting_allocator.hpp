#pragma once
// Counts heap allocations, to prove that World::step allocates nothing in
// steady state. tests/support/counting_allocator.cpp replaces the global
// operator new (every form, aligned included) with one that counts while a
// CountAllocations is alive; tests/CMakeLists.txt links that file into every
// test executable with a source that includes this header.
//
//   fulcrum::test::CountAllocations count;   // starts at 0
//   world.step(dt);
//   EXPECT_EQ(count.stop(), 0);              // stop() ends counting, returns the count
#include <cstddef>

namespace fulcrum::test {

// The raw switch and counter (prefer CountAllocations).
void setCountingAllocations(bool on);
long allocationCount();
void resetAllocationCount();

// Heap growth while a HeapBudget is alive: the bytes allocated minus the
// bytes freed since it started (malloc_usable_size of each block, so blocks
// from before it count when freed: growth, not use), and its peak. With a
// budget, an allocation that would take the growth past it throws
// std::bad_alloc, as a machine out of memory does (but promptly).
class HeapBudget {
public:
    explicit HeapBudget(long long budgetBytes = -1);  // -1: only measure
    ~HeapBudget();
    HeapBudget(const HeapBudget&) = delete;
    HeapBudget& operator=(const HeapBudget&) = delete;
    long long growth() const;      // bytes
    long long peakGrowth() const;  // bytes
};

class CountAllocations {
public:
    CountAllocations() {
        resetAllocationCount();
        setCountingAllocations(true);
    }
    ~CountAllocations() { setCountingAllocations(false); }
    CountAllocations(const CountAllocations&) = delete;
    CountAllocations& operator=(const CountAllocations&) = delete;
    long count() const { return allocationCount(); }
    long stop() {
        setCountingAllocations(false);
        return allocationCount();
    }
};

}  // namespace fulcrum::test
