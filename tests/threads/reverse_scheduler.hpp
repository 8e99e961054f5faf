#pragma once
// A user-supplied TaskSystem for tests: every range on the calling thread, in
// reverse order, under made-up worker indices. Results that depend on range
// order or worker assignment differ between it and the thread pool.
#include <algorithm>
#include <cstdint>

#include "fulcrum/task_system.hpp"

namespace fulcrum::test {

// Cuts [0, count) into ranges of minRange (the last one longer) and runs them
// in reverse order as "worker" (range index % 3).
class ReverseScheduler final : public TaskSystem {
public:
    std::uint32_t calls = 0;
    std::uint32_t workerCount() const noexcept override { return 3; }
    void parallelFor(std::uint32_t count, std::uint32_t minRange, RangeFn fn) override {
        ++calls;
        if (count == 0) return;
        const std::uint32_t size = std::min(std::max(minRange, 1u), count);
        const std::uint32_t ranges = count / size;  // the last range takes the remainder
        for (std::uint32_t r = ranges; r-- > 0;) fn(r * size, r + 1 == ranges ? count : (r + 1) * size, r % 3);
    }
};

}  // namespace fulcrum::test
