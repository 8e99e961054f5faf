// Determinism of the parallel patterns (src/threads/deterministic_parallel.hpp):
// a float sum is bit-identical for every thread count and scheduler, and
// per-worker outputs merge into exactly the single-threaded order.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "threads/reverse_scheduler.hpp"
#include "threads/deterministic_parallel.hpp"
#include "threads/thread_pool.hpp"

using namespace fulcrum;

namespace {

// Values over twelve orders of magnitude, both signs: float addition is far
// from associative on them, so any change in summation order shows in the bits.
std::vector<float> wildValues(std::size_t n) {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> mantissa(-1.0f, 1.0f);
    std::uniform_int_distribution<int> exponent(-20, 20);
    std::vector<float> v(n);
    for (float& x : v) {
        const int e = exponent(rng);  // drawn last argument first, as GCC evaluated the call: the same cases with every compiler
        x = std::ldexp(mantissa(rng), e);
    }
    return v;
}

std::vector<std::unique_ptr<TaskSystem>> allSchedulers() {
    std::vector<std::unique_ptr<TaskSystem>> s;
    s.push_back(std::make_unique<InlineTaskSystem>());
    s.push_back(std::make_unique<test::ReverseScheduler>());
    for (std::uint32_t threads : {1u, 2u, 3u, 4u, 8u}) s.push_back(makeThreadPool(ThreadPoolDef{threads, 2000, 4}));
    return s;
}

}  // namespace

TEST(BlockReduction, FloatSumIsBitIdenticalForEveryThreadCount) {
    const std::vector<float> values = wildValues(100003);
    constexpr std::uint32_t kBlock = 256;
    const auto count = static_cast<std::uint32_t>(values.size());

    // The reference: the same order of additions, written out sequentially.
    float reference = 0.0f;
    for (std::uint32_t begin = 0; begin < count; begin += kBlock) {
        float block = 0.0f;
        for (std::uint32_t i = begin; i < std::min(count, begin + kBlock); ++i) block += values[i];
        reference += block;
    }
    // Sanity against double precision: |error| <= n * eps * sum|x| (Higham, eq. 4.4).
    double exact = 0, magnitude = 0;
    for (float x : values) exact += x, magnitude += std::fabs(x);
    EXPECT_LE(std::fabs(reference - exact), double(count) * 0x1p-24 * magnitude);

    for (auto& tasks : allSchedulers()) {
        detail::BlockReduction<float> reduction;
        for (int repeat = 0; repeat < 3; ++repeat) {
            const float sum = reduction.run(
                *tasks, count, kBlock, 0.0f,
                [&](std::uint32_t begin, std::uint32_t end) {
                    float s = 0.0f;
                    for (std::uint32_t i = begin; i < end; ++i) s += values[i];
                    return s;
                },
                [](float a, float b) { return a + b; });
            EXPECT_EQ(std::bit_cast<std::uint32_t>(sum), std::bit_cast<std::uint32_t>(reference))
                << "workers " << tasks->workerCount() << ": " << sum << " vs " << reference;
        }
    }
}

TEST(BlockReduction, PlainPerRangeSumsWouldNotBeDeterministic) {
    // Why the blocks are needed: summing each scheduler range and adding the
    // range sums gives different bits for different cuts of the same data. (If
    // this ever passes trivially, the data above is too tame to test anything.)
    const std::vector<float> values = wildValues(100003);
    const auto count = static_cast<std::uint32_t>(values.size());
    auto perRangeSum = [&](std::uint32_t rangeSize) {
        float total = 0.0f;
        for (std::uint32_t begin = 0; begin < count; begin += rangeSize) {
            float s = 0.0f;
            for (std::uint32_t i = begin; i < std::min(count, begin + rangeSize); ++i) s += values[i];
            total += s;
        }
        return total;
    };
    EXPECT_NE(std::bit_cast<std::uint32_t>(perRangeSum(6251)), std::bit_cast<std::uint32_t>(perRangeSum(25001)));
}

TEST(WorkerBuffers, MergeGivesTheSingleThreadedOrder) {
    // Index i emits i % 4 items (i, 0), (i, 1), ...: variable output per index,
    // some indices none.
    struct Item {
        std::uint32_t index, k;
        bool operator==(const Item&) const = default;
    };
    constexpr std::uint32_t kCount = 5000;
    std::vector<Item> expected;
    for (std::uint32_t i = 0; i < kCount; ++i)
        for (std::uint32_t k = 0; k < i % 4; ++k) expected.push_back({i, k});

    for (auto& tasks : allSchedulers()) {
        detail::WorkerBuffers<Item> buffers;
        std::vector<Item> merged;
        for (int repeat = 0; repeat < 3; ++repeat) {
            buffers.reset(tasks->workerCount());
            tasks->parallelFor(kCount, 16, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
                std::vector<Item>& out = buffers.beginRange(worker, begin);
                for (std::uint32_t i = begin; i < end; ++i)
                    for (std::uint32_t k = 0; k < i % 4; ++k) out.push_back({i, k});
            });
            buffers.mergeInIndexOrder(merged);
            EXPECT_TRUE(merged == expected) << "workers " << tasks->workerCount();
        }
    }
}
