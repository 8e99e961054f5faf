#pragma once
// ThreadPool: the built-in TaskSystem (created through fulcrum::makeThreadPool).
//
// ---- How a call runs ------------------------------------------------------------
// parallelFor cuts [0, count) into chunks of max(minRange, count / (workers *
// rangesPerWorker)) indices (the last chunk also takes the remainder, so no
// range is shorter than minRange) and deals the chunks out in contiguous spans,
// one per worker: worker w owns chunks [w C / W, (w + 1) C / W). Each worker
// claims the chunks of its own span first and then takes what is left of the
// others' spans, in worker order. So the same indices go to the same core call
// after call (a body's data stays in that core's cache from the velocity loop
// to the solver to the position loop) and no worker waits while work is left.
// Interleaving the chunks through one shared counter, as before, moved each
// body's cache lines between the cores at every call: measured on box_pile
// (docs/threading.md).
//
// Each span is one 64-bit atomic word: the job's generation (24 bits), the
// span's end and its next unclaimed chunk (20 bits each). A chunk is claimed
// by a CAS that moves `next` on, which succeeds only while the word still
// carries the generation the claimer is working on; so a claim always belongs
// to the current job, whose fields (function, count, chunk size) were written
// before the words were published (release) and are read after the claim
// (acquire), and cannot change before the claimed chunk is counted done. A
// worker that comes late to a finished job sees another generation and leaves.
//
// ---- Idle workers ---------------------------------------------------------------
// An idle worker polls the job generation for def.spinIterations pause
// instructions (back-to-back calls, as in the solver's colour loop, then cost no
// system call), then sleeps on a condition variable. The publisher notifies
// only when the sleeper count is non-zero; the seq_cst store of the generation
// and the seq_cst increment of the sleeper count (under the mutex, before the
// worker re-checks the generation) form a Dekker pair, so a wake-up is never lost.
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
    // Claims and runs chunks of job `generation`, its own span first, until
    // none is left (or another job is current).
    void runChunks(std::uint32_t workerIndex, std::uint64_t generation) noexcept;
    void runRange(std::uint32_t begin, std::uint32_t end, std::uint32_t workerIndex) noexcept;
    // Spins, then sleeps, until a job other than `seen` is published or stop.
    void waitForWork(std::uint32_t seen) noexcept;
    void stopAndJoin() noexcept;  // spin, then sleep, until a job is published or stop

    std::uint32_t workerCount_ = 1;
    std::uint32_t spinIterations_ = 0;
    std::uint32_t rangesPerWorker_ = 1;
    std::vector<std::thread> threads_;

    // The current job. Written by the caller before the spans are published
    // (release), read by participants only while they own a chunk.
    const RangeFn* fn_ = nullptr;
    std::uint32_t count_ = 0;
    std::uint32_t chunkSize_ = 1;
    std::int64_t chunkCount_ = 0;
    std::uint32_t generation_ = 0;  // of the current job; the caller's only

    // One span of chunks per worker (header comment), each on its own cache line.
    struct alignas(64) Span {
        std::atomic<std::uint64_t> word{0};
    };
    std::vector<Span> spans_;
    alignas(64) std::atomic<std::uint32_t> published_{0};  // generation of the latest job
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
