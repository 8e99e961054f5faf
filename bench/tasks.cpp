// Task-system benchmark: what one parallelFor costs.
//
//   cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DFULCRUM_BUILD_BENCH=ON
//   cmake --build build-bench -j2 --target bench_tasks
//   build-bench/bench/bench_tasks --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// BM_EmptyCall/threads/spin: back-to-back calls over 64 indices of no work
//   (minRange 1, so the pool cuts 16 ranges at 4 threads): the fixed cost per
//   call when workers are spinning (spin 2000) or asleep (spin 0: every call
//   wakes them through the condition variable).
// BM_CallAfterIdle/threads: a call of 64 us of work issued after 2 ms of
//   idleness (workers asleep whatever the spin budget), manual timing: the
//   wall time minus 64 us / threads is roughly the wake-up latency; the
//   "helped" counter is the share of indices the pool threads ran.
// BM_Inline: InlineTaskSystem, the floor (a virtual call).
// BM_Sum/threads: a real but small job, 2^16 floats summed through
//   BlockReduction (blocks of 1024), to show when threads start to pay
//   (items/s from wall time: Google Benchmark's CPU time counts only the
//   calling thread, which flatters the pool).
// BM_StagedStages/threads/units: StagedParallel (threads/staged_parallel.hpp)
//   running 41 dependent stages of `units` units of ~0.1 us each -- a box
//   pile step's sub-steps -- in one call: wall time per stage, the cost of a
//   stage's hand-over on top of its work (compare with threads 1).
#include <benchmark/benchmark.h>

#include <chrono>
#include <thread>
#include <vector>

#include "threads/deterministic_parallel.hpp"
#include "threads/staged_parallel.hpp"
#include "threads/thread_pool.hpp"

namespace fulcrum {
namespace {

void noWork(std::uint32_t begin, std::uint32_t end, std::uint32_t) { benchmark::DoNotOptimize(begin + end); }

void BM_Inline(benchmark::State& state) {
    InlineTaskSystem inlineTasks;
    TaskSystem& tasks = inlineTasks;
    for (auto _ : state) tasks.parallelFor(64, 1, noWork);
}
BENCHMARK(BM_Inline);

void BM_EmptyCall(benchmark::State& state) {
    detail::ThreadPool pool(ThreadPoolDef{std::uint32_t(state.range(0)), std::uint32_t(state.range(1)), 4});
    for (auto _ : state) pool.parallelFor(64, 1, noWork);
}
BENCHMARK(BM_EmptyCall)->ArgNames({"threads", "spin"})->ArgsProduct({{1, 2, 4}, {0, 2000}});

void BM_CallAfterIdle(benchmark::State& state) {
    detail::ThreadPool pool(ThreadPoolDef{std::uint32_t(state.range(0)), 2000, 4});
    std::vector<std::uint32_t> perWorker(pool.workerCount());
    for (auto _ : state) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        const auto start = std::chrono::steady_clock::now();
        // 64 indices of ~1 us busy work each (64 us on one thread), in enough
        // ranges that every worker is woken and has something to pick up.
        pool.parallelFor(64, 1, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
            const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(end - begin);
            while (std::chrono::steady_clock::now() < until) {
            }
            perWorker[worker] += end - begin;
        });
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::uint32_t helped = 0, total = 0;
    for (std::size_t w = 0; w < perWorker.size(); ++w) total += perWorker[w], helped += w > 0 ? perWorker[w] : 0;
    state.counters["helped"] = total ? double(helped) / total : 0.0;
}
BENCHMARK(BM_CallAfterIdle)->ArgName("threads")->Arg(1)->Arg(2)->Arg(4)->UseManualTime()->Iterations(300);

void BM_Sum(benchmark::State& state) {
    std::vector<float> values(1 << 16, 0.25f);
    detail::ThreadPool pool(ThreadPoolDef{std::uint32_t(state.range(0)), 2000, 4});
    detail::BlockReduction<float> reduction;
    for (auto _ : state) {
        const float sum = reduction.run(
            pool, std::uint32_t(values.size()), 1024, 0.0f,
            [&](std::uint32_t begin, std::uint32_t end) {
                float s = 0;
                for (std::uint32_t i = begin; i < end; ++i) s += values[i] * values[i];
                return s;
            },
            [](float a, float b) { return a + b; });
        benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(values.size()));
}
BENCHMARK(BM_Sum)->ArgName("threads")->Arg(1)->Arg(2)->Arg(4)->UseRealTime();

void BM_StagedStages(benchmark::State& state) {
    detail::ThreadPool pool(ThreadPoolDef{std::uint32_t(state.range(0)), 2000, 4});
    const auto units = std::uint32_t(state.range(1));
    constexpr std::uint32_t kStages = 41;
    detail::StagedParallel stages;
    stages.reserve(kStages, pool.workerCount());
    std::vector<float> work(std::size_t{units} * 64, 1.0f);
    double seconds = 0;
    for (auto _ : state) {
        const auto start = std::chrono::steady_clock::now();
        stages.clear();
        for (std::uint32_t k = 0; k < kStages; ++k) stages.add(0, 0, 0, units, 1);
        stages.run(pool, [&](const detail::Stage&, std::uint32_t first, std::uint32_t last) noexcept {
            // ~0.1 us per unit: 64 dependent multiply-adds on the unit's own floats.
            for (std::uint32_t u = first; u < last; ++u) {
                float x = work[std::size_t{u} * 64];
                for (int i = 0; i < 64; ++i) x = x * 0.999f + 0.001f;
                work[std::size_t{u} * 64] = x;
            }
        });
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    state.counters["us_per_stage"] = 1e6 * seconds / double(state.iterations()) / kStages;
}
BENCHMARK(BM_StagedStages)->ArgNames({"threads", "units"})->ArgsProduct({{1, 2}, {8, 64}})->UseRealTime();

}  // namespace
}  // namespace fulcrum

BENCHMARK_MAIN();
