#pragma once
// ThreadPool: the built-in TaskSystem (created through fulcrum::makeThreadPool).
//
// ---- How a call runs ------------------------------------------------------------
// parallelFor cuts [0, count) into chunks of max(minRange, count / (workers *
// rangesPerWorker)) indices (the last chunk also takes the remainder, so no
// range is shorter than minRange), publishes the job by storing the chunk count into
// one atomic counter, wakes sleeping workers only if there are any, and then
// works on the job itself. Every participant claims the next chunk with a
// single fetch_sub on that counter (no CAS loop, no lock), runs it, and counts
// it done. The caller returns when every chunk is done.
//
// Why this is safe without per-job sequence numbers: a participant reads the
// job's fields (function, count, chunk size) only *after* its fetch_sub
// returned a positive value, i.e. after it owns an unfinished chunk of the job
// that is current at that moment; the caller cannot publish the next job before
// that chunk is counted done, so the fields cannot change under it. A late
// fetch_sub on an exhausted counter just drives it below zero, and the next
// publish overwrites it.
//
// ---- Idle workers ---------------------------------------------------------------
// An idle worker polls the counter for def.spinIterations pause instructions
// (back-to-back calls, as in the solver's colour loop, then cost no system
// call), then sleeps on a condition variable. The publisher notifies only when
// the sleeper count is non-zero; the seq_cst store of the counter and the
// seq_cst increment of the sleeper count (under the mutex, before the worker
// re-checks the counter) form a Dekker pair, so a wake-up is never lost.
//
// ---- Worker indices -------------------------------------------------------------
// The caller is worker 0, pool thread i is worker i. Calls from several outside
// threads are serialised by a mutex (they would otherwise share index 0); a
// parallelFor issued from inside a range function of the same pool runs inline
// with the current worker's index (a thread-local records it).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "fulcrum/task_system.hpp"

namespace fulcrum::detail {

class ThreadPool final : public TaskSystem {
public:
    explicit ThreadPool(const ThreadPoolDef& def);
    ~ThreadPool() override;
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    std::uint32_t workerCount() const noexcept override { return workerCount_; }
    void parallelFor(std::uint32_t count, std::uint32_t minRange, RangeFn fn) override;

    // Chunk size parallelFor uses for a call (exposed for tests and benchmarks).
    std::uint32_t chunkSize(std::uint32_t count, std::uint32_t minRange) const noexcept;

private:
    void workerMain(std::uint32_t workerIndex) noexcept;
    // Claims and runs chunks of the current job until none is left.
    void runChunks(std::uint32_t workerIndex) noexcept;
    void runRange(std::uint32_t begin, std::uint32_t end, std::uint32_t workerIndex) noexcept;
    void waitForWork() noexcept;
    void stopAndJoin() noexcept;  // spin, then sleep, until a job is published or stop

    std::uint32_t workerCount_ = 1;
    std::uint32_t spinIterations_ = 0;
    std::uint32_t rangesPerWorker_ = 1;
    std::vector<std::thread> threads_;

    // The current job. Written by the caller before the release of
    // unclaimedChunks_, read by participants only while they own a chunk.
    const RangeFn* fn_ = nullptr;
    std::uint32_t count_ = 0;
    std::uint32_t chunkSize_ = 1;
    std::int64_t chunkCount_ = 0;

    // Each on its own cache line: every participant hammers them.
    alignas(64) std::atomic<std::int64_t> unclaimedChunks_{0};
    alignas(64) std::atomic<std::int64_t> doneChunks_{0};
    alignas(64) std::atomic<bool> cancelled_{false};  // a range threw: skip the rest
    std::atomic<bool> stop_{false};
    std::atomic<std::uint32_t> sleepers_{0};

    std::mutex sleepMutex_;
    std::condition_variable wake_;
    std::mutex submitMutex_;  // one outside caller at a time
    std::mutex errorMutex_;
    std::exception_ptr firstError_;
};

}  // namespace fulcrum::detail
