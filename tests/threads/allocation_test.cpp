// No heap allocation per parallelFor call in steady state
// (support/counting_allocator.hpp counts global operator new). The lambdas capture more
// than std::function's small buffer holds, so a std::function in the path
// would allocate on every call.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <vector>

#include "fulcrum/world.hpp"
#include "reverse_scheduler.hpp"
#include "support/counting_allocator.hpp"
#include "threads/deterministic_parallel.hpp"
#include "threads/thread_pool.hpp"

using namespace fulcrum;
using fulcrum::test::CountAllocations;

TEST(Allocation, ParallelForAllocatesNothingPerCall) {
    for (std::uint32_t threads : {1u, 2u, 4u}) {
        for (std::uint32_t spin : {0u, 2000u}) {
            detail::ThreadPool pool(ThreadPoolDef{threads, spin, 4});
            std::vector<std::atomic<std::uint32_t>> hits(1000);
            double a = 1, b = 2, c = 3, d = 4;  // a fat capture
            auto body = [&, a, b, c, d](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
                for (std::uint32_t i = begin; i < end; ++i) hits[i].fetch_add(a + b + c + d > 0 ? 1u : 0u);
            };
            pool.parallelFor(1000, 1, body);  // warm-up (first wake-ups)
            long allocations = 0;
            {
                CountAllocations counter;
                for (int call = 0; call < 500; ++call) pool.parallelFor(1000, 1 + call % 50, body);
                allocations = counter.count();
            }
            EXPECT_EQ(allocations, 0) << "threads " << threads << " spin " << spin;
            for (auto& h : hits) ASSERT_EQ(h.load(), 501u);
        }
    }
}

TEST(Allocation, DeterministicPatternsReuseTheirStorage) {
    detail::ThreadPool pool(ThreadPoolDef{3, 2000, 4});
    std::vector<float> values(20000, 0.5f);
    detail::BlockReduction<float> reduction;
    detail::WorkerBuffers<std::uint32_t> buffers;
    std::vector<std::uint32_t> merged;
    auto runBoth = [&] {
        const float sum = reduction.run(
            pool, 20000, 128, 0.0f,
            [&](std::uint32_t begin, std::uint32_t end) {
                float s = 0;
                for (std::uint32_t i = begin; i < end; ++i) s += values[i];
                return s;
            },
            [](float x, float y) { return x + y; });
        buffers.reset(pool.workerCount());
        pool.parallelFor(20000, 64, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
            auto& out = buffers.beginRange(worker, begin);
            for (std::uint32_t i = begin; i < end; ++i)
                if (i % 7 == 0) out.push_back(i);
        });
        buffers.mergeInIndexOrder(merged);
        return sum;
    };
    buffers.reset(pool.workerCount());
    buffers.reserve(20000 / 7 + 1, 20000 / 64);  // the worst case: one worker gets everything
    runBoth();  // the reduction's partials, merged's capacity
    long allocations = 0;
    float sum = 0;
    {
        CountAllocations counter;
        for (int i = 0; i < 50; ++i) sum = runBoth();
        allocations = counter.count();
    }
    EXPECT_EQ(allocations, 0);
    EXPECT_EQ(sum, 10000.0f);  // 20000 x 0.5, exact in float
    EXPECT_EQ(merged.size(), 2858u);  // multiples of 7 below 20000
}

// The multithreaded step allocates nothing in steady state either: per-worker
// broad- and narrow-phase buffers are sized once, on the first step with a
// given worker count. A 5 x 8 x 5 stack of boxes settling on the ground (contacts
// begin and end throughout), stepped on the pool at 2 and 4 threads and on a
// user scheduler; momentum check: the pile's centre of mass stays above the
// ground (the boxes' half height, 1 cm tolerance for resting overlap).
TEST(Allocation, ThreadedStepDoesNotAllocateInSteadyState) {
    test::ReverseScheduler reverse;
    for (int config = 0; config < 3; ++config) {
        WorldDef def;
        def.parallelMinBodies = 0;  // 200 boxes: below the default, which would step them inline
        World world(def);
        world.setThreadCount(config == 0 ? 2 : 4);
        if (config == 2) world.setTaskSystem(&reverse);
        BodyDef ground;
        ground.type = BodyType::Static;
        ground.shape = Shape::box({20, 1, 20});
        ground.position = {0, -1, 0};
        world.createBody(ground);
        for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 5; ++z)
                for (int x = 0; x < 5; ++x) {
                    BodyDef d;
                    d.shape = Shape::box({Real(0.5), Real(0.5), Real(0.5)});
                    d.mass = 1;
                    d.position = {Real(1.05) * static_cast<Real>(x) + Real(0.1) * static_cast<Real>(y % 2),
                                  Real(0.5) + Real(1.01) * static_cast<Real>(y), Real(1.05) * static_cast<Real>(z)};
                    world.createBody(d);
                }
        for (int i = 0; i < 5; ++i) world.step(Real(1) / 60);  // warm-up: pool and per-worker buffers
        long allocations = 0;
        {
            CountAllocations counter;
            for (int i = 0; i < 40; ++i) world.step(Real(1) / 60);
            allocations = counter.count();
        }
        EXPECT_EQ(allocations, 0) << "config " << config;
        Real comY = 0;
        int boxes = 0;
        for (const BodyId id : world.bodies()) {
            if (world.bodyType(id) == BodyType::Static) continue;
            comY += world.position(id).y;
            ++boxes;
        }
        EXPECT_GT(comY / static_cast<Real>(boxes), Real(0.5) - Real(0.01));
    }
}
