// The task-system contract (include/fulcrum/task_system.hpp), checked for the
// built-in pool at 1..8 threads (more threads than cores on purpose) and for
// the inline system: every index exactly once, ranges no shorter than
// minRange, worker indices in range and never shared by two running ranges,
// exceptions delivered to the caller, nesting and concurrent callers.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "fulcrum/error.hpp"
#include "fulcrum/task_system.hpp"
#include "threads/reverse_scheduler.hpp"
#include "threads/thread_pool.hpp"

using namespace fulcrum;

namespace {

const std::uint32_t kThreadCounts[] = {1, 2, 3, 4, 8};

// Runs one parallelFor and checks the contract; returns the number of ranges.
std::uint32_t checkCoverage(TaskSystem& tasks, std::uint32_t count, std::uint32_t minRange) {
    std::vector<std::atomic<std::uint32_t>> hits(count);
    std::vector<std::atomic<bool>> busy(tasks.workerCount());
    std::atomic<std::uint32_t> ranges{0}, badRanges{0}, badWorkers{0}, sharedWorkers{0};
    tasks.parallelFor(count, minRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
        ranges.fetch_add(1);
        if (worker >= tasks.workerCount()) {
            badWorkers.fetch_add(1);
            return;
        }
        if (busy[worker].exchange(true)) sharedWorkers.fetch_add(1);
        const std::uint32_t expectedMin = std::min(std::max(minRange, 1u), count);
        if (begin >= end || end > count || end - begin < expectedMin) badRanges.fetch_add(1);
        for (std::uint32_t i = begin; i < end && i < count; ++i) hits[i].fetch_add(1);
        busy[worker].store(false);
    });
    EXPECT_EQ(badWorkers.load(), 0u) << "count " << count << " minRange " << minRange;
    EXPECT_EQ(badRanges.load(), 0u) << "count " << count << " minRange " << minRange;
    EXPECT_EQ(sharedWorkers.load(), 0u) << "two running ranges shared a worker index";
    std::uint32_t wrong = 0;
    for (std::uint32_t i = 0; i < count; ++i) wrong += hits[i].load() != 1 ? 1u : 0u;
    EXPECT_EQ(wrong, 0u) << "indices not covered exactly once, count " << count << " minRange " << minRange;
    return ranges.load();
}

const std::uint32_t kCounts[] = {0, 1, 2, 3, 5, 7, 16, 63, 64, 65, 100, 1000, 4097, 20000};
const std::uint32_t kMinRanges[] = {0, 1, 3, 16, 1000, 50000};

}  // namespace

TEST(ThreadPool, CoversEveryIndexExactlyOnce) {
    for (std::uint32_t threads : kThreadCounts) {
        detail::ThreadPool pool(ThreadPoolDef{threads, 2000, 4});
        ASSERT_EQ(pool.workerCount(), threads);
        for (std::uint32_t count : kCounts)
            for (std::uint32_t minRange : kMinRanges) {
                const std::uint32_t ranges = checkCoverage(pool, count, minRange);
                if (count == 0) {
                    EXPECT_EQ(ranges, 0u);
                }
            }
    }
}

TEST(ThreadPool, SleepingWorkersWakeUp) {
    // spinIterations 0: workers sleep at once, so every call goes through the
    // condition variable (the path where a lost wake-up would hang).
    detail::ThreadPool pool(ThreadPoolDef{4, 0, 4});
    for (int round = 0; round < 50; ++round) checkCoverage(pool, 997, 1);
}

TEST(ThreadPool, SplitsWorkAcrossWorkersWhenThereIsEnough) {
    // Not a speed claim: with 4 workers and 64 ranges of 1, ranges exist for
    // everyone (who runs them is up to the OS, so only the count is asserted).
    detail::ThreadPool pool(ThreadPoolDef{4, 2000, 4});
    EXPECT_EQ(pool.chunkSize(64, 1), 4u);  // 64 / (4 workers * 4 ranges each)
    EXPECT_EQ(checkCoverage(pool, 64, 1), 16u);
    EXPECT_EQ(pool.chunkSize(64, 10), 10u);
    EXPECT_EQ(checkCoverage(pool, 64, 10), 6u);  // 5 x 10 + 14: no range below minRange
    EXPECT_EQ(checkCoverage(pool, 64, 40), 1u);  // 64 < 2 * 40: one range, run inline
}

TEST(InlineTaskSystem, RunsOneRangeOnTheCaller) {
    InlineTaskSystem tasks;
    EXPECT_EQ(tasks.workerCount(), 1u);
    for (std::uint32_t count : kCounts) EXPECT_EQ(checkCoverage(tasks, count, 7), count == 0 ? 0u : 1u);
}

TEST(ThreadPool, MakeThreadPoolValidatesItsDefinition) {
    EXPECT_EQ(makeThreadPool(ThreadPoolDef{3, 100, 2})->workerCount(), 3u);
    EXPECT_GE(makeThreadPool(ThreadPoolDef{0, 100, 2})->workerCount(), 1u);  // hardware concurrency
    try {
        makeThreadPool(ThreadPoolDef{2, 100, 0});
        ADD_FAILURE() << "rangesPerWorker 0 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("rangesPerWorker"), std::string::npos) << e.what();
    }
    try {
        makeThreadPool(ThreadPoolDef{static_cast<std::uint32_t>(-1), 100, 1});
        ADD_FAILURE() << "4 billion threads accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("threads"), std::string::npos) << e.what();
    }
}

TEST(ThreadPool, ManySmallCallsFinish) {
    // No deadlock or lost range over many tiny calls, spinning and sleeping.
    for (std::uint32_t spin : {0u, 2000u}) {
        detail::ThreadPool pool(ThreadPoolDef{4, spin, 4});
        std::atomic<std::uint64_t> sum{0};
        std::uint64_t expected = 0;
        for (std::uint32_t call = 0; call < 3000; ++call) {
            const std::uint32_t count = 2 + call % 13;
            pool.parallelFor(count, 1, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
                for (std::uint32_t i = begin; i < end; ++i) sum.fetch_add(i + 1, std::memory_order_relaxed);
            });
            expected += std::uint64_t(count) * (count + 1) / 2;
        }
        EXPECT_EQ(sum.load(), expected) << "spinIterations " << spin;
    }
}

TEST(ThreadPool, ExceptionsReachTheCaller) {
    for (std::uint32_t threads : {1u, 2u, 4u}) {
        detail::ThreadPool pool(ThreadPoolDef{threads, 2000, 4});
        for (std::uint32_t count : {1u, 100u, 10000u}) {
            std::atomic<std::uint32_t> ran{0};
            try {
                pool.parallelFor(count, 1, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
                    ran.fetch_add(1);
                    if (begin <= count / 2 && count / 2 < end) throw std::runtime_error("index " + std::to_string(count / 2));
                });
                ADD_FAILURE() << "no exception, threads " << threads << " count " << count;
            } catch (const std::runtime_error& e) {
                EXPECT_EQ(std::string(e.what()), "index " + std::to_string(count / 2));
            }
            // The pool is usable afterwards, and no error is left behind.
            checkCoverage(pool, count, 1);
        }
    }
}

TEST(ThreadPool, NestedCallsRunInlineOnTheSameWorker) {
    detail::ThreadPool pool(ThreadPoolDef{4, 2000, 4});
    std::vector<std::atomic<std::uint32_t>> hits(64 * 10);
    std::atomic<std::uint32_t> wrongWorker{0};
    pool.parallelFor(64, 1, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t outer) {
        for (std::uint32_t i = begin; i < end; ++i)
            pool.parallelFor(10, 1, [&](std::uint32_t b, std::uint32_t e, std::uint32_t inner) {
                if (inner != outer) wrongWorker.fetch_add(1);
                for (std::uint32_t k = b; k < e; ++k) hits[i * 10 + k].fetch_add(1);
            });
    });
    EXPECT_EQ(wrongWorker.load(), 0u);
    for (auto& h : hits) EXPECT_EQ(h.load(), 1u);
}

TEST(ThreadPool, CallsFromSeveralThreadsAreSerialised) {
    detail::ThreadPool pool(ThreadPoolDef{3, 2000, 4});
    std::atomic<std::uint32_t> failures{0};
    auto caller = [&] {
        for (int round = 0; round < 200; ++round) {
            std::vector<std::atomic<std::uint32_t>> hits(300);
            pool.parallelFor(300, 1, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
                for (std::uint32_t i = begin; i < end; ++i) hits[i].fetch_add(1);
            });
            for (auto& h : hits)
                if (h.load() != 1) failures.fetch_add(1);
        }
    };
    std::thread a(caller), b(caller);
    a.join();
    b.join();
    EXPECT_EQ(failures.load(), 0u);
}


TEST(TaskSystem, UserSchedulerIsCalledThroughTheInterface) {
    test::ReverseScheduler user;
    TaskSystem& tasks = user;
    EXPECT_EQ(checkCoverage(tasks, 100, 7), 14u);  // 13 x 7 + 9
    EXPECT_EQ(user.calls, 1u);
}

TEST(FunctionRef, CallsTheReferencedCallableWithoutCopyingIt) {
    int state = 0;
    auto add = [&state](int v) { state += v; return state; };
    FunctionRef<int(int)> ref = add;
    EXPECT_EQ(ref(2), 2);
    EXPECT_EQ(ref(3), 5);  // the same lambda object: state accumulates
    static_assert(sizeof(FunctionRef<int(int)>) == 2 * sizeof(void*));
    int (*negate)(int) = [](int v) { return -v; };
    EXPECT_EQ(FunctionRef<int(int)>(negate)(4), -4);   // a function pointer
    EXPECT_EQ(FunctionRef<int(int)>(*negate)(4), -4);  // a function
    static_assert(std::is_trivially_copyable_v<FunctionRef<int(int)>>);
}
