#pragma once
// StagedParallel: a fixed sequence of dependent data-parallel stages (stage
// k + 1 reads what stage k wrote) run inside ONE TaskSystem::parallelFor.
//
// Why: box_pile's sub-steps are ~40 fork-join calls per step (the contact
// solver's two colours × warm start, solve, relax, plus the per-body passes),
// each paying the pool's publish/retire cost and an end-of-call wait on the
// other worker. Box2D v3's solver (solver.c: b2SolverStage, per-block sync
// indices, the main thread driving the stages) runs all of a step's stages in
// one task per worker instead. This is that idea with two differences the
// TaskSystem contract needs (include/fulcrum/task_system.hpp):
//
//  - No designated driver. Every participant walks the stages in order; in a
//    stage it claims units until none is left, adds how many it ran to the
//    stage's done counter, and spins until the counter is full. A participant
//    only ever waits for units some *running* participant has claimed, so it
//    never waits on a range the scheduler has not started: a user scheduler
//    that runs the ranges one after another (or InlineTaskSystem) gets all the
//    work done by the first range, and a range that starts late finds every
//    stage complete and returns.
//  - Affinity by spans. A stage's units are dealt out in contiguous spans, one
//    per participant (participant p owns units [p U / W, (p + 1) U / W)), the
//    same cut for every stage of the same size: the owner claims its span from
//    the front, others steal from the back (one 64-bit word per span, CAS).
//    So the same core tends to run the same blocks of a colour in every
//    iteration and sub-step, and the same bodies in every per-body stage, and
//    their cache lines stay put; stealing keeps the load balanced.
//
// Determinism: the stages run in their fixed order and a stage's units must be
// independent (blocks of one graph colour, per-body work), so results do not
// depend on which participant ran a unit.
//
// Caller stages (addOnCaller): a stage that runs on the calling thread
// between the parallel segments, for work that spreads itself over the task
// system (the joint solver's passes: colours and trees each a parallelFor).
// The list is then run as segments: the stages up to a caller stage in one
// parallelFor, the caller stage, the next segment. With one worker every
// stage runs in order on the calling thread, caller stages included.
//
// Participant p is the `begin` of the range that parallelFor hands it
// (parallelFor over W = workerCount() indices, minRange 1); the worker index
// is not used, so any scheduler that keeps the contract works.
//
// Allocation: the stage list and the per-stage counters only grow (to the
// largest stage count seen), so steady-state steps allocate nothing.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#if defined(__x86_64__) || defined(__i386__) || defined(_M_X64)
#include <immintrin.h>
#endif

#include "fulcrum/task_system.hpp"

namespace fulcrum::detail {

// Whether World::step runs its stage list in segments of one parallelFor each
// (default on; FULCRUM_STAGED=0 in the environment turns it off) or one
// parallelFor per stage: the same bits, so this exists for side-by-side
// measurements and for the tests that check both agree.
bool stagedSubStepsEnabled();
void setStagedSubStepsEnabled(bool enabled);
// Whether the sub-steps after the first keep the step's forces when nothing
// makes them vary (no drag, callback or spring: WorldImpl::buildSubSteps);
// off only to test that path against evaluating them again (bit for bit).
bool forcesOncePerStepEnabled();
void setForcesOncePerStepEnabled(bool enabled);
// Whether each body's integration path (its MotionKind) is decided once per
// step rather than tested at every sub-step (integrators.hpp,
// classifyMotion); off only to test that against the per-sub-step tests.
bool motionKindsPerStepEnabled();
void setMotionKindsPerStepEnabled(bool enabled);

struct Stage {
    std::uint32_t kind = 0;   // the caller's: what to run
    std::uint32_t arg = 0;    // the caller's: a flag or parameter
    std::uint32_t begin = 0;  // items [begin, begin + count)
    std::uint32_t count = 0;
    std::uint32_t unit = 1;   // items per claim
    bool onCaller = false;    // a caller stage (see the top): one exec call on the calling thread
};

class StagedParallel {
public:
    void clear() { stages_.clear(); }
    // Appends a stage (nothing if count is 0).
    void add(std::uint32_t kind, std::uint32_t arg, std::uint32_t begin, std::uint32_t count, std::uint32_t unit) {
        if (count == 0) return;
        stages_.push_back(Stage{kind, arg, begin, count, unit == 0 ? 1u : unit});
    }
    // Appends a caller stage: exec(stage, 0, 1) on the calling thread.
    void addOnCaller(std::uint32_t kind, std::uint32_t arg) { stages_.push_back(Stage{kind, arg, 0, 1, 1, true}); }
    std::size_t size() const { return stages_.size(); }
    const std::vector<Stage>& stages() const { return stages_; }

    // Runs every stage, in order, across `tasks`; exec(stage, first, last)
    // processes items [first, last) of `stage` and must be noexcept. With one
    // worker each stage is one exec call over all its items (no atomics).
    // `segments` false: one parallelFor per stage instead of per segment.
    template <class Exec>
    void run(TaskSystem& tasks, Exec&& exec, bool segments = true) {
        if (stages_.empty()) return;
        const std::uint32_t workers = tasks.workerCount();
        if (workers <= 1) {
            for (const Stage& s : stages_) exec(s, s.begin, s.begin + s.count);
            return;
        }
        if (!segments) {
            for (const Stage& s : stages_) {
                if (s.onCaller || s.count <= s.unit) {
                    exec(s, s.begin, s.begin + s.count);
                    continue;
                }
                const std::uint32_t units = (s.count + s.unit - 1) / s.unit;
                tasks.parallelFor(units, 1, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
                    for (std::uint32_t u = begin; u < end; ++u) {
                        const std::uint32_t first = s.begin + u * s.unit;
                        exec(s, first, std::min(first + s.unit, s.begin + s.count));
                    }
                });
            }
            return;
        }
        prepareSync(workers);
        const std::size_t stageCount = stages_.size();
        for (std::size_t first = 0; first < stageCount;) {
            if (stages_[first].onCaller) {
                const Stage& s = stages_[first++];
                exec(s, s.begin, s.begin + s.count);
                continue;
            }
            std::size_t last = first;
            while (last < stageCount && !stages_[last].onCaller) ++last;
            tasks.parallelFor(workers, 1, [&](std::uint32_t begin, std::uint32_t, std::uint32_t) {
                participate(begin, workers, exec, first, last);
            });
            first = last;
        }
    }

private:
    static void pause() noexcept {
#if defined(__x86_64__) || defined(__i386__) || defined(_M_X64)
        _mm_pause();
#elif defined(__aarch64__)
        asm volatile("yield");
#endif
    }

    // A stage's done counter, alone on its cache line (every participant spins on it).
    struct alignas(64) Done {
        std::atomic<std::uint32_t> units{0};
    };
    using SpanWord = std::atomic<std::uint64_t>;  // one span: [next, end) of its units, packed
    static std::uint64_t pack(std::uint32_t next, std::uint32_t end) {
        return std::uint64_t{next} | (std::uint64_t{end} << 32);
    }

public:
    // Sizes the counters for `stageCount` stages and `workers` participants
    // ahead (run() grows them otherwise: an allocation on the first step with
    // more stages than before).
    void reserve(std::size_t stageCount, std::uint32_t workers) {
        stages_.reserve(stageCount);
        if (stageCount > doneCapacity_) {
            doneCapacity_ = stageCount;
            done_ = std::make_unique<Done[]>(doneCapacity_);
            unitCount_.reserve(doneCapacity_);
        }
        // Participant p's spans are row p: [p * stride, p * stride + stages),
        // rows apart by whole cache lines (each owner claims in its own row).
        const std::size_t stride = (doneCapacity_ + 7) / 8 * 8;
        if (stride * workers > spanCapacity_) {
            spanCapacity_ = stride * workers;
            spans_ = std::make_unique<Row[]>(spanCapacity_ / 8);
        }
        spanStride_ = stride;
    }

private:
    struct alignas(64) Row {
        SpanWord word[8];
    };
    SpanWord& span(std::uint32_t participant, std::size_t stage) {
        const std::size_t i = participant * spanStride_ + stage;
        return spans_[i / 8].word[i % 8];
    }

    void prepareSync(std::uint32_t workers) {
        const std::size_t stageCount = stages_.size();
        if (stageCount > doneCapacity_ || spanStride_ * workers > spanCapacity_) reserve(2 * stageCount, workers);
        spanStride_ = (doneCapacity_ + 7) / 8 * 8;
        unitCount_.resize(stageCount);
        for (std::size_t s = 0; s < stageCount; ++s) {
            const Stage& st = stages_[s];
            const std::uint32_t units = (st.count + st.unit - 1) / st.unit;
            unitCount_[s] = units;
            done_[s].units.store(0, std::memory_order_relaxed);
            for (std::uint32_t p = 0; p < workers; ++p) {
                const auto first = static_cast<std::uint32_t>(std::uint64_t{units} * p / workers);
                const auto last = static_cast<std::uint32_t>(std::uint64_t{units} * (p + 1) / workers);
                span(p, s).store(pack(first, last), std::memory_order_relaxed);
            }
        }
        // parallelFor publishes these stores to the participants (its own
        // synchronisation: a range runs after the call that hands it out).
    }

    // Claims a unit of the span: its front (the owner's end) or its back (a
    // thief's end); UINT32_MAX if the span is empty.
    static std::uint32_t claim(SpanWord& target, bool front) {
        std::uint64_t word = target.load(std::memory_order_relaxed);
        for (;;) {
            const auto next = static_cast<std::uint32_t>(word);
            const auto end = static_cast<std::uint32_t>(word >> 32);
            if (next >= end) return UINT32_MAX;
            const std::uint64_t rest = front ? pack(next + 1, end) : pack(next, end - 1);
            if (target.compare_exchange_weak(word, rest, std::memory_order_relaxed)) return front ? next : end - 1;
        }
    }

    template <class Exec>
    void participate(std::uint32_t self, std::uint32_t workers, Exec& exec, std::size_t firstStage, std::size_t lastStage) {
        for (std::size_t s = firstStage; s < lastStage; ++s) {
            const Stage& st = stages_[s];
            const std::uint32_t units = unitCount_[s];
            Done& done = done_[s];
            // A late participant skips the stages already complete.
            if (done.units.load(std::memory_order_acquire) == units) continue;
            const auto runUnit = [&](std::uint32_t u) {
                const std::uint32_t first = st.begin + u * st.unit;
                const std::uint32_t last = first + st.unit < st.begin + st.count ? first + st.unit : st.begin + st.count;
                exec(st, first, last);
            };
            std::uint32_t ran = 0;
            for (std::uint32_t u; (u = claim(span(self, s), true)) != UINT32_MAX; ++ran) runUnit(u);
            for (std::uint32_t k = 1; k < workers; ++k) {
                SpanWord& victim = span((self + k) % workers, s);
                for (std::uint32_t u; (u = claim(victim, false)) != UINT32_MAX; ++ran) runUnit(u);
            }
            // Release what this participant wrote; then wait for the units others
            // are still running (all are claimed, so their runners are running).
            if (ran > 0) done.units.fetch_add(ran, std::memory_order_acq_rel);
            for (std::uint32_t spins = 0; done.units.load(std::memory_order_acquire) != units; ++spins) {
                if (spins < 4096) {
                    pause();
                } else {
                    std::this_thread::yield();  // the runner may have been preempted (oversubscribed machine)
                }
            }
        }
    }

    std::vector<Stage> stages_;
    std::vector<std::uint32_t> unitCount_;
    std::unique_ptr<Row[]> spans_;
    std::size_t spanCapacity_ = 0;  // span words
    std::size_t spanStride_ = 0;
    std::unique_ptr<Done[]> done_;
    std::size_t doneCapacity_ = 0;
};

}  // namespace fulcrum::detail
