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
