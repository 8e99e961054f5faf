// StagedParallel (src/threads/staged_parallel.hpp) and the staged sub-steps of
// World::step (step.cpp): a step's solver and per-body passes run as the
// stages of one parallelFor.
//
// What must hold, whatever the scheduler: each stage's items run exactly once,
// a stage starts only when the one before it is complete (no designated
// driver: a participant that starts late, or ranges run one after another,
// still finish every stage), and the step's results are the bits of the
// one-thread loop.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "../determinism/state_hash.hpp"
#include "fulcrum/task_system.hpp"
#include "fulcrum/world.hpp"
#include "ground.hpp"
#include "reverse_scheduler.hpp"
#include "support/counting_allocator.hpp"
#include "solver/contact_wide.hpp"
#include "threads/staged_parallel.hpp"
#include "threads/thread_pool.hpp"

using namespace fulcrum;

namespace {

// Every range on the calling thread, one after another in reverse order, as
// `workers` workers: the first range to run must do all the work.
class SerialReverseScheduler final : public TaskSystem {
public:
    explicit SerialReverseScheduler(std::uint32_t workers) : workers_(workers) {}
    std::uint32_t calls = 0;
    std::uint32_t workerCount() const noexcept override { return workers_; }
    void parallelFor(std::uint32_t count, std::uint32_t minRange, RangeFn fn) override {
        ++calls;
        if (count == 0) return;
        const std::uint32_t size = std::min(std::max(minRange, 1u), count);
        const std::uint32_t ranges = count / size;
        for (std::uint32_t r = ranges; r-- > 0;) fn(r * size, r + 1 == ranges ? count : (r + 1) * size, r % workers_);
    }

private:
    std::uint32_t workers_;
};

// One std::thread per range, range r starting r * 200 us late: participants
// really run at once, and late ones find stages done (tests only: it allocates).
class StaggeredThreadScheduler final : public TaskSystem {
public:
    std::uint32_t workerCount() const noexcept override { return 3; }
    void parallelFor(std::uint32_t count, std::uint32_t, RangeFn fn) override {
        std::vector<std::thread> threads;
        for (std::uint32_t r = 0; r < count; ++r) {
            threads.emplace_back([r, fn] {
                std::this_thread::sleep_for(std::chrono::microseconds(200 * r));
                fn(r, r + 1, r % 3);
            });
        }
        for (std::thread& t : threads) t.join();
    }
};

// A chain of stages where each reads its neighbours' results of the stage
// before (so a stage that started early, or an item run twice, changes the
// numbers) and records how many items of the previous stage were done when
// each of its items started.
struct StageChain {
    static constexpr std::uint32_t kItems = 1000;
    static constexpr std::uint32_t kStages = 40;
    std::vector<double> a, b;
    std::vector<std::unique_ptr<std::atomic<std::uint32_t>[]>> runs;  // per stage, per item
    std::vector<std::atomic<std::uint32_t>> doneItems;                 // per stage
    std::atomic<std::uint32_t> earlyStarts{0};
    detail::StagedParallel stages;

    StageChain() : a(kItems), b(kItems), doneItems(kStages) {
        for (std::uint32_t s = 0; s < kStages; ++s) runs.push_back(std::make_unique<std::atomic<std::uint32_t>[]>(kItems));
        reset();
        // Stages of different sizes and claim units, some of one item (serial).
        for (std::uint32_t s = 0; s < kStages; ++s) {
            const std::uint32_t count = s % 7 == 3 ? 1 : kItems - 37 * (s % 5);
            stages.add(s, 0, 0, count, 1 + s % 9 * 7);
        }
    }
    void reset() {
        for (std::uint32_t i = 0; i < kItems; ++i) {
            a[i] = 1 + 0.001 * i;
            b[i] = 0;
        }
        for (std::uint32_t s = 0; s < kStages; ++s) {
            doneItems[s].store(0);
            for (std::uint32_t i = 0; i < kItems; ++i) runs[s][i].store(0);
        }
        earlyStarts.store(0);
    }
    // Stage s writes one array from the other's neighbours.
    void item(std::uint32_t s, std::uint32_t i, std::uint32_t count) {
        const std::vector<double>& in = s % 2 == 0 ? a : b;
        std::vector<double>& out = s % 2 == 0 ? b : a;
        const std::uint32_t l = (i + kItems - 1) % kItems, r = (i + 1) % kItems;
        out[i] = std::sqrt(in[l] * 0.3 + in[i] * 0.5 + in[r] * 0.2 + static_cast<double>(s)) + (count == 1 ? in[i] : 0.0);
    }
    void run(TaskSystem& tasks) {
        stages.run(tasks, [&](const detail::Stage& st, std::uint32_t first, std::uint32_t last) {
            const std::uint32_t s = st.kind;
            if (s > 0 && doneItems[s - 1].load() != stages.stages()[s - 1].count) earlyStarts.fetch_add(1);
            for (std::uint32_t i = first; i < last; ++i) {
                runs[s][i].fetch_add(1);
                item(s, i, st.count);
            }
            doneItems[s].fetch_add(last - first);
        });
    }
    // The same stages one after another on this thread.
    static std::vector<double> reference() {
        StageChain c;
        for (std::uint32_t s = 0; s < kStages; ++s) {
            const detail::Stage& st = c.stages.stages()[s];
            for (std::uint32_t i = st.begin; i < st.begin + st.count; ++i) c.item(s, i, st.count);
        }
        return c.a;
    }
};

void expectChainRunsRight(TaskSystem& tasks, const std::string& name) {
    static const std::vector<double> expected = StageChain::reference();
    StageChain chain;
    for (int repeat = 0; repeat < 3; ++repeat) {
        chain.reset();
        chain.run(tasks);
        EXPECT_EQ(chain.earlyStarts.load(), 0u) << name << ": a stage started before the one before it was done";
        for (std::uint32_t s = 0; s < StageChain::kStages; ++s) {
            const std::uint32_t count = chain.stages.stages()[s].count;
            for (std::uint32_t i = 0; i < StageChain::kItems; ++i) {
                ASSERT_EQ(chain.runs[s][i].load(), i < count ? 1u : 0u) << name << ": stage " << s << " item " << i;
            }
        }
        for (std::uint32_t i = 0; i < StageChain::kItems; ++i) {
            ASSERT_EQ(chain.a[i], expected[i]) << name << ": item " << i;  // bit for bit
        }
    }
}

}  // namespace

TEST(StagedParallel, EveryStageRunsOnceAndInOrderOnAnyScheduler) {
    InlineTaskSystem inlineTasks;
    expectChainRunsRight(inlineTasks, "inline");
    for (std::uint32_t threads : {2u, 3u, 4u}) {
        for (std::uint32_t spin : {0u, 100000u}) {
            detail::ThreadPool pool(ThreadPoolDef{threads, spin, 16});
            expectChainRunsRight(pool, "pool " + std::to_string(threads) + " spin " + std::to_string(spin));
        }
    }
    SerialReverseScheduler serial2(2), serial5(5);
    expectChainRunsRight(serial2, "serial reverse, 2 workers");
    expectChainRunsRight(serial5, "serial reverse, 5 workers");
    test::ReverseScheduler reverse;
    expectChainRunsRight(reverse, "ReverseScheduler");
    StaggeredThreadScheduler staggered;
    expectChainRunsRight(staggered, "a thread per range, started late");
}

TEST(StagedParallel, RunsAllocateNothingOnceSized) {
    detail::ThreadPool pool(ThreadPoolDef{2, 100000, 16});
    StageChain chain;
    chain.run(pool);  // sizes the counters
    long allocations = 0;
    {
        test::CountAllocations counter;
        for (int k = 0; k < 20; ++k) chain.run(pool);
        allocations = counter.count();
    }
    EXPECT_EQ(allocations, 0);
}

namespace {

// A 500-box pile on the ground (columns a hair apart, turned a little, so it
// topples and contacts begin and end), stepped under `tasks` (nullptr: the
// built-in pool with `threads`); the state hash after every step.
std::vector<std::uint64_t> pileHashes(int threads, TaskSystem* tasks, int steps, bool staged) {
    detail::setStagedSubStepsEnabled(staged);
    WorldDef def;
    def.parallelMinBodies = 0;
    def.threads = threads;
    World world(def);
    test::addGroundSlab(world);
    for (int y = 0; y < 5; ++y) {
        for (int z = 0; z < 10; ++z) {
            for (int x = 0; x < 10; ++x) {
                BodyDef d;
                d.shape = Shape::box({Real(0.5), Real(0.5), Real(0.5)});
                d.mass = 1;
                d.position = {Real(1.1) * static_cast<Real>(x) + Real(0.05) * static_cast<Real>(y % 3),
                              Real(0.5) + Real(1.02) * static_cast<Real>(y), Real(1.1) * static_cast<Real>(z)};
                const Real angle = Real(0.15) * static_cast<Real>((x + 3 * z + 7 * y) % 5 - 2);
                d.orientation = normalize(Quat{std::cos(angle / 2), 0, std::sin(angle / 2), 0});
                world.createBody(d);
            }
        }
    }
    world.setTaskSystem(tasks);
    std::vector<std::uint64_t> hashes;
    for (int s = 0; s < steps; ++s) {
        world.step(Real(1) / 60);
        hashes.push_back(test::stateHash(world));
    }
    // Physics: the pile rests on the ground, nothing sank through it or rose.
    for (const BodyId id : world.bodies()) {
        if (world.bodyType(id) == BodyType::Static) continue;
        EXPECT_GT(world.position(id).y, Real(0.5) - Real(0.05)) << "a box sank into the ground";
        EXPECT_LT(world.position(id).y, Real(0.5) + Real(1.02) * 4 + Real(0.01)) << "a box rose";
    }
    detail::setStagedSubStepsEnabled(true);
    return hashes;
}

}  // namespace

// The staged sub-steps give the bits of the serial loop (threads = 1) for the
// pool at 2 and 4 workers, InlineTaskSystem (one worker: the loop itself) and
// a user scheduler that runs the ranges serially in reverse order, and so does
// the loop of parallelFor calls they replace.
TEST(StagedSubSteps, SameBitsAsTheSerialStepForAnyScheduler) {
    constexpr int kSteps = 40;
    const std::vector<std::uint64_t> serial = pileHashes(1, nullptr, kSteps, true);
    InlineTaskSystem inlineTasks;
    SerialReverseScheduler reverse2(2), reverse4(4);
    struct Run {
        std::string name;
        int threads;
        TaskSystem* tasks;
    };
    for (const Run& run : {Run{"pool 2", 2, nullptr}, Run{"pool 4", 4, nullptr}, Run{"InlineTaskSystem", 1, &inlineTasks},
                           Run{"serial reverse, 2 workers", 1, &reverse2}, Run{"serial reverse, 4 workers", 1, &reverse4}}) {
        for (const bool staged : {true, false}) {
            const std::vector<std::uint64_t> hashes = pileHashes(run.threads, run.tasks, kSteps, staged);
            for (int s = 0; s < kSteps; ++s) {
                ASSERT_EQ(hashes[static_cast<std::size_t>(s)], serial[static_cast<std::size_t>(s)])
                    << run.name << (staged ? ", staged" : ", loop") << ": differs at step " << s + 1;
            }
        }
    }
}

// The staged path is the one taken: with it, a step's sub-steps are one
// parallelFor call instead of at least two per-body passes and (on the wide
// contact path) one call per solver pass per sub-step (5 sub-steps: >= 25
// calls fewer per step; on the scalar path, FULCRUM_SIMD=scalar and the double
// build's default, whose solver passes run on the calling thread either way,
// the 2 x 5 per-body passes become the one call: >= 9 fewer, measured 9).
TEST(StagedSubSteps, OneParallelForRunsTheSubSteps) {
    constexpr int kSteps = 10;
    SerialReverseScheduler stagedTasks(2), loopTasks(2);
    pileHashes(1, &stagedTasks, kSteps, true);
    pileHashes(1, &loopTasks, kSteps, false);
    const std::uint32_t fewerPerStep = detail::initialSimdPath() == detail::SimdPath::Scalar ? 9u : 25u;
    EXPECT_GE(loopTasks.calls, stagedTasks.calls + fewerPerStep * kSteps)
        << "staged " << stagedTasks.calls << " calls, loop " << loopTasks.calls;
}
