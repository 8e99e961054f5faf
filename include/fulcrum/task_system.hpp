#pragma once
// TaskSystem: how the engine runs work on several threads, and how a user plugs
// in their own job system instead of the built-in thread pool.
//
// ---- The model ----------------------------------------------------------------
// Every parallel phase of a step is a data-parallel loop followed by a barrier:
// broad-phase queries per moved proxy, the narrow phase per pair, the solver per
// constraint colour (a colour's constraints share no dynamic body). So the
// whole interface is one blocking fork-join call:
//
//     parallelFor(count, minRange, fn)
//
// which calls fn(begin, end, workerIndex) for disjoint ranges covering
// [0, count) exactly once, and returns when all of them are done.
//
// Why parallelFor rather than Box2D v3's enqueue/finish pair: enqueue/finish
// lets the caller overlap a task with other work on the calling thread, but the
// step's phases depend on each other in sequence, so Fulcrum would call finish
// right after enqueue anyway. A blocking call has no task handle whose lifetime
// the implementer must manage, maps one-to-one onto the loops of TBB
// (parallel_for), enkiTS, Taskflow, OpenMP or a game's own job system, and is
// the smallest thing a user has to get right.
//
// ---- Contract for implementers ------------------------------------------------
//  1. Call fn on disjoint ranges [begin, end) whose union is [0, count), each
//     exactly once, with begin < end. Ranges should hold at least minRange
//     indices (except when count < minRange); the engine picks minRange so a
//     range amortises the cost of scheduling it.
//  2. workerIndex is in [0, workerCount()) and no two ranges that run at the
//     same time share a workerIndex: the engine indexes per-worker scratch
//     buffers with it, without locks.
//  3. Return only after every call of fn has returned (the calling thread may,
//     and should, run ranges itself).
//  4. The engine's range functions are noexcept and allocate nothing; results
//     never depend on how the ranges were cut or which worker ran them (the
//     engine's determinism does not rest on the scheduler).
// parallelFor is only called from the thread that calls World::step, never
// from inside a range function, so an implementation need not support nesting.
//
// ---- Built-in implementations ---------------------------------------------------
// InlineTaskSystem runs everything on the calling thread (workerCount 1).
// makeThreadPool() returns a pool of N-1 worker threads plus the caller, which
// spin briefly and then sleep when idle (docs/threading.md has the measured
// overhead per call).
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>

namespace fulcrum {

// A non-owning reference to a callable, like C++26's std::function_ref: two
// pointers, trivially copyable, never allocates. The referenced callable must
// outlive every call through the reference (for parallelFor: the call).
template <class Signature>
class FunctionRef;

template <class R, class... Args>
class FunctionRef<R(Args...)> {
public:
    template <class F>
        requires(!std::is_same_v<std::remove_cvref_t<F>, FunctionRef> && std::is_invocable_r_v<R, F&, Args...>)
    FunctionRef(F&& f) noexcept {  // NOLINT(google-explicit-constructor): implicit like std::function_ref
        using T = std::remove_reference_t<F>;
        if constexpr (std::is_function_v<T>) {  // a plain function: keep its address
            target_.function = reinterpret_cast<void (*)()>(&f);
            invoke_ = [](Target t, Args... args) -> R {
                return reinterpret_cast<T*>(t.function)(std::forward<Args>(args)...);
            };
        } else {  // any other callable object: keep a pointer to it
            target_.object = const_cast<void*>(static_cast<const void*>(std::addressof(f)));
            invoke_ = [](Target t, Args... args) -> R { return (*static_cast<T*>(t.object))(std::forward<Args>(args)...); };
        }
    }

    R operator()(Args... args) const { return invoke_(target_, std::forward<Args>(args)...); }

private:
    union Target {
        void* object;
        void (*function)();  // function pointers don't convert to void*
    };
    Target target_{nullptr};
    R (*invoke_)(Target, Args...) = nullptr;
};

// fn(begin, end, workerIndex): process indices [begin, end) as worker workerIndex.
using RangeFn = FunctionRef<void(std::uint32_t begin, std::uint32_t end, std::uint32_t workerIndex)>;

class TaskSystem {
public:
    virtual ~TaskSystem() = default;

    // Number of distinct worker indices parallelFor may pass (>= 1), the
    // calling thread included. Sizes the engine's per-worker scratch buffers.
    virtual std::uint32_t workerCount() const noexcept = 0;

    // Runs fn over [0, count) as described above; count 0 calls nothing.
    virtual void parallelFor(std::uint32_t count, std::uint32_t minRange, RangeFn fn) = 0;

protected:
    TaskSystem() = default;
    TaskSystem(const TaskSystem&) = default;
    TaskSystem& operator=(const TaskSystem&) = default;
};

// Everything on the calling thread, as one range: a virtual call and nothing else.
class InlineTaskSystem final : public TaskSystem {
public:
    std::uint32_t workerCount() const noexcept override { return 1; }
    void parallelFor(std::uint32_t count, std::uint32_t /*minRange*/, RangeFn fn) override {
        if (count > 0) fn(0, count, 0);
    }
};

struct ThreadPoolDef {
    // Total workers including the calling thread (>= 1); 1 starts no thread.
    // 0 means std::thread::hardware_concurrency().
    std::uint32_t threads = 0;
    // How long an idle worker polls for new work before it sleeps on a
    // condition variable, in pause-loop iterations (each ~10-140 cycles,
    // depending on the CPU). Spinning keeps back-to-back parallelFor calls (the
    // solver's colours) cheap; sleeping keeps idle cores free for the rest of
    // the program. 0 sleeps at once. The default (~0.5-2 ms) outlasts the
    // serial gaps inside a step, so a step wakes no sleeper (docs/threading.md).
    std::uint32_t spinIterations = 100000;
    // Target number of ranges per worker per call, for load balancing; the
    // pool never cuts ranges smaller than minRange.
    std::uint32_t rangesPerWorker = 16;
};

// The built-in pool: def.threads - 1 worker threads plus the thread that calls
// parallelFor. Exceptions thrown by fn are caught, the remaining ranges are
// skipped, and the first exception is rethrown on the calling thread once the
// ranges in flight have finished. Calls from several threads are serialised;
// a parallelFor called from inside a range function runs inline on that worker.
// Throws fulcrum::Error if def is invalid or a thread cannot be started.
std::unique_ptr<TaskSystem> makeThreadPool(const ThreadPoolDef& def = {});

}  // namespace fulcrum
