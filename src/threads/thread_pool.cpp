#include "threads/thread_pool.hpp"

#include <algorithm>
#include <string>
#include <system_error>

#include "fulcrum/error.hpp"

#if defined(__x86_64__) || defined(__i386__) || defined(_M_X64)
#include <immintrin.h>
#endif

namespace fulcrum::detail {
namespace {

// A polite busy-wait step: tells the core (and its SMT sibling) we are spinning.
inline void cpuPause() noexcept {
#if defined(__x86_64__) || defined(__i386__) || defined(_M_X64)
    _mm_pause();
#elif defined(__aarch64__)
    asm volatile("yield");
#endif
}

// The pool (if any) whose range function the current thread is running, and
// the worker index it runs as: a nested parallelFor on the same pool runs inline.
thread_local const ThreadPool* tCurrentPool = nullptr;
thread_local std::uint32_t tCurrentWorker = 0;

struct CurrentPoolScope {
    const ThreadPool* savedPool;
    std::uint32_t savedWorker;
    CurrentPoolScope(const ThreadPool* pool, std::uint32_t worker) noexcept
        : savedPool(tCurrentPool), savedWorker(tCurrentWorker) {
        tCurrentPool = pool;
        tCurrentWorker = worker;
    }
    ~CurrentPoolScope() {
        tCurrentPool = savedPool;
        tCurrentWorker = savedWorker;
    }
    CurrentPoolScope(const CurrentPoolScope&) = delete;
    CurrentPoolScope& operator=(const CurrentPoolScope&) = delete;
};

// More workers than this is a mistake (a negative int converted to unsigned).
constexpr std::uint32_t kMaxThreads = 1024;

// A span word: generation (24 bits) | end (20) | next (20) (thread_pool.hpp).
constexpr std::uint64_t kChunkBits = 20;
constexpr std::uint64_t kChunkMask = (std::uint64_t{1} << kChunkBits) - 1;
constexpr std::uint32_t kGenerationMask = (1u << 24) - 1;
constexpr std::uint64_t kMaxChunks = kChunkMask;
std::uint64_t spanWord(std::uint64_t generation, std::uint64_t end, std::uint64_t next) {
    return generation << (2 * kChunkBits) | end << kChunkBits | next;
}
std::uint64_t generationOf(std::uint64_t word) { return word >> (2 * kChunkBits); }
std::uint64_t endOf(std::uint64_t word) { return (word >> kChunkBits) & kChunkMask; }
std::uint64_t nextOf(std::uint64_t word) { return word & kChunkMask; }

}  // namespace

ThreadPool::ThreadPool(const ThreadPoolDef& def) {
    std::uint32_t threads = def.threads;
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    if (threads > kMaxThreads)
        throw Error("ThreadPoolDef: threads must be at most " + std::to_string(kMaxThreads) + ", got " +
                    std::to_string(def.threads));
    if (def.rangesPerWorker == 0) throw Error("ThreadPoolDef: rangesPerWorker must be at least 1, got 0");
    workerCount_ = threads;
    spinIterations_ = def.spinIterations;
    rangesPerWorker_ = def.rangesPerWorker;
    spans_ = std::vector<Span>(threads);
    threads_.reserve(threads - 1);
    try {
        for (std::uint32_t i = 1; i < threads; ++i) threads_.emplace_back([this, i] { workerMain(i); });
    } catch (const std::system_error& e) {
        stopAndJoin();  // the threads already started
        throw Error("ThreadPool: could not start worker thread " + std::to_string(threads_.size() + 1) + " of " +
                    std::to_string(threads) + ": " + e.what());
    }
}

ThreadPool::~ThreadPool() { stopAndJoin(); }

void ThreadPool::stopAndJoin() noexcept {
    stop_.store(true, std::memory_order_seq_cst);
    {
        std::lock_guard lock(sleepMutex_);
        wake_.notify_all();
    }
    for (std::thread& t : threads_)
        if (t.joinable()) t.join();
}

std::uint32_t ThreadPool::chunkSize(std::uint32_t count, std::uint32_t minRange) const noexcept {
    const std::uint64_t target = std::uint64_t(workerCount_) * rangesPerWorker_;
    const std::uint64_t even = (std::uint64_t(count) + target - 1) / target;
    // At most kMaxChunks chunks (a span word's 20-bit fields).
    const std::uint64_t fewest = (std::uint64_t(count) + kMaxChunks - 1) / kMaxChunks;
    return static_cast<std::uint32_t>(std::max<std::uint64_t>({even, fewest, minRange, 1}));
}

void ThreadPool::parallelFor(std::uint32_t count, std::uint32_t minRange, RangeFn fn) {
    if (count == 0) return;
    if (tCurrentPool == this) {  // nested: this thread already holds a worker index
        fn(0, count, tCurrentWorker);
        return;
    }
    const std::uint32_t size = chunkSize(count, minRange);
    if (count / size < 2 || workerCount_ == 1) {  // one range: no reason to wake anyone
        CurrentPoolScope scope(this, 0);
        std::lock_guard submit(submitMutex_);
        fn(0, count, 0);
        return;
    }

    std::lock_guard submit(submitMutex_);
    fn_ = &fn;
    count_ = count;
    chunkSize_ = size;
    chunkCount_ = std::int64_t(count / size);  // >= 2 here; the remainder goes to the last
    doneChunks_.store(0, std::memory_order_relaxed);
    cancelled_.store(false, std::memory_order_relaxed);
    generation_ = (generation_ + 1) & kGenerationMask;
    const std::uint64_t chunks = static_cast<std::uint64_t>(chunkCount_), workers = spans_.size();
    for (std::size_t w = 0; w < workers; ++w) {
        spans_[w].word.store(spanWord(generation_, chunks * (w + 1) / workers, chunks * w / workers),
                             std::memory_order_release);
    }
    // Publish (seq_cst: pairs with the sleeper count, see the header).
    published_.store(generation_, std::memory_order_seq_cst);
    if (const std::uint32_t sleeping = sleepers_.load(std::memory_order_seq_cst); sleeping > 0) {
        // The caller takes a chunk itself, so chunkCount - 1 helpers are enough.
        const std::int64_t helpers = std::min<std::int64_t>(chunkCount_ - 1, sleeping);
        std::lock_guard lock(sleepMutex_);
        if (helpers >= std::int64_t(sleeping))
            wake_.notify_all();
        else
            for (std::int64_t i = 0; i < helpers; ++i) wake_.notify_one();
    }

    {
        CurrentPoolScope scope(this, 0);
        runChunks(0, generation_);
    }
    // Chunks still in flight on other workers: short, so spin, then yield the
    // core in case their thread was preempted (the machine may be oversubscribed).
    for (std::uint32_t spins = 0; doneChunks_.load(std::memory_order_acquire) != chunkCount_; ++spins) {
        if (spins < 256)
            cpuPause();
        else
            std::this_thread::yield();
    }
    fn_ = nullptr;
    if (firstError_) {
        std::exception_ptr error = std::move(firstError_);
        firstError_ = nullptr;
        std::rethrow_exception(error);
    }
}

void ThreadPool::runChunks(std::uint32_t workerIndex, std::uint64_t generation) noexcept {
    // The chunks this worker ran, counted into doneChunks_ once, when it finds
    // no more to claim: one atomic add on the shared counter per worker and
    // call instead of one per chunk (the caller spins on that cache line, so
    // each add used to pull it across cores: 32 chunks a call, ~45 calls a step).
    // The caller cannot see the job as done before every claimed chunk has
    // finished and been counted, and a worker counts nothing for a job it
    // claimed nothing of.
    std::int64_t done = 0;
    const auto countDone = [&] {
        if (done != 0) doneChunks_.fetch_add(done, std::memory_order_release);
    };
    const std::size_t workers = spans_.size();
    for (std::size_t k = 0; k < workers; ++k) {
        std::atomic<std::uint64_t>& span = spans_[(workerIndex + k) % workers].word;
        std::uint64_t word = span.load(std::memory_order_acquire);
        for (;;) {
            if (generationOf(word) != generation) {  // that job is over
                countDone();
                return;
            }
            if (nextOf(word) >= endOf(word)) break;       // this span is done: the next one
            if (!span.compare_exchange_weak(word, word + 1, std::memory_order_acquire, std::memory_order_acquire))
                continue;  // word now holds the current value
            // We own chunk nextOf(word) of this job: its fields are stable.
            // Chunk k is [k count / C, (k + 1) count / C): sizes differ by at
            // most one and none is below count / C >= chunkSize >= minRange.
            // (The last chunk used to take the whole remainder: up to 2x the
            // others, e.g. 438 of 950 bodies in 3 chunks of "256", so one
            // worker got 694 of them.)
            const std::uint64_t chunk = nextOf(word);
            const auto chunks = static_cast<std::uint64_t>(chunkCount_);
            const std::uint64_t begin = chunk * count_ / chunks;
            const std::uint64_t end = (chunk + 1) * count_ / chunks;
            if (!cancelled_.load(std::memory_order_relaxed))
                runRange(static_cast<std::uint32_t>(begin), static_cast<std::uint32_t>(end), workerIndex);
            ++done;
            word = span.load(std::memory_order_acquire);
        }
    }
    countDone();
}

void ThreadPool::runRange(std::uint32_t begin, std::uint32_t end, std::uint32_t workerIndex) noexcept {
    try {
        (*fn_)(begin, end, workerIndex);
    } catch (...) {
        std::lock_guard lock(errorMutex_);
        if (!firstError_) firstError_ = std::current_exception();
        cancelled_.store(true, std::memory_order_relaxed);
    }
}

void ThreadPool::waitForWork(std::uint32_t seen) noexcept {
    for (std::uint32_t i = 0; i < spinIterations_; ++i) {
        if (published_.load(std::memory_order_relaxed) != seen || stop_.load(std::memory_order_relaxed)) return;
        cpuPause();
    }
    std::unique_lock lock(sleepMutex_);
    sleepers_.fetch_add(1, std::memory_order_seq_cst);
    wake_.wait(lock, [this, seen] {
        return published_.load(std::memory_order_seq_cst) != seen || stop_.load(std::memory_order_seq_cst);
    });
    sleepers_.fetch_sub(1, std::memory_order_relaxed);
}

void ThreadPool::workerMain(std::uint32_t workerIndex) noexcept {
    CurrentPoolScope scope(this, workerIndex);
    std::uint32_t seen = 0;
    while (!stop_.load(std::memory_order_acquire)) {
        waitForWork(seen);
        seen = published_.load(std::memory_order_acquire);
        runChunks(workerIndex, seen);
    }
}

}  // namespace fulcrum::detail
