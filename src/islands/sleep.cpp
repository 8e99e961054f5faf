#include "islands/sleep.hpp"

#include <algorithm>
#include <atomic>
#include <bit>

#include "fulcrum/task_system.hpp"
#include "contacts/contact_manager.hpp"
#include "solver/joint_data.hpp"

namespace fulcrum::detail {

namespace {

// Bodies (and constraints) per range of the parallel passes: as step.cpp's.
constexpr std::uint32_t kBodiesPerRange = 64;

std::atomic_ref<std::uint32_t> atomicSlot(std::uint32_t& slot) { return std::atomic_ref<std::uint32_t>(slot); }

}  // namespace

std::uint32_t findRootConcurrently(std::uint32_t* parent, std::uint32_t i) {
    // Path splitting with relaxed stores: a parent is only ever replaced by
    // one of its ancestors (an ancestor never stops being one: links only
    // join roots), so even a stale grandparent is a valid shortcut.
    std::uint32_t up = atomicSlot(parent[i]).load(std::memory_order_relaxed);
    while (up != i) {
        const std::uint32_t grand = atomicSlot(parent[up]).load(std::memory_order_relaxed);
        if (grand != up) atomicSlot(parent[i]).store(grand, std::memory_order_relaxed);
        i = up;
        up = grand;
    }
    return i;
}

void uniteConcurrently(std::uint32_t* parent, std::uint32_t a, std::uint32_t b) {
    for (;;) {
        const std::uint32_t ra = findRootConcurrently(parent, a), rb = findRootConcurrently(parent, b);
        if (ra == rb) return;
        // The larger root under the smaller, only while it is still a root
        // (a failed CAS: another link got there first; find again).
        std::uint32_t expected = std::max(ra, rb);
        if (atomicSlot(parent[expected]).compare_exchange_strong(expected, std::min(ra, rb), std::memory_order_relaxed)) {
            return;
        }
    }
}

void SleepManager::lowerConcurrently(RealBits& slotBits, Real value) {
    // Timers are non-negative, so their bits order as their values.
    const auto mine = std::bit_cast<RealBits>(value);
    std::atomic_ref<RealBits> bits(slotBits);
    RealBits seen = bits.load(std::memory_order_relaxed);
    while (mine < seen && !bits.compare_exchange_weak(seen, mine, std::memory_order_relaxed)) {
    }
}

std::uint32_t SleepManager::find(std::uint32_t i) {
    while (parent_[i] != i) {
        parent_[i] = parent_[parent_[i]];  // path halving
        i = parent_[i];
    }
    return i;
}

void SleepManager::update(BodyStore& w, const SleepSettings& s, const std::vector<ContactSolver::ConstraintPair>& pairs,
                          const ContactManager& manager, const std::vector<JointData>& joints, TaskSystem& tasks,
                          Real dt) {
    const std::vector<std::uint32_t>& denseOf = w.denseOfSolver;
    const std::size_t n = denseOf.size();  // entry 0 is the static stand-in
    const Real lin2 = s.linearSleepVelocity * s.linearSleepVelocity;
    const Real ang2 = s.angularSleepVelocity * s.angularSleepVelocity;

    if (!s.sleeping) {
        for (std::size_t i = 1; i < n; ++i) w.params[denseOf[i]].sleepTime = 0;
        return;
    }

    // Everything but the islands' sums runs on the task system, and the
    // result is the same bits for any thread count:
    //  - the unions run in parallel over the constraints, each a lock-free
    //    link of the larger root under the smaller (a CAS on the larger
    //    root's parent that succeeds only while it is still a root). Linking
    //    that way keeps every root the smallest index of its set, whatever
    //    order the links happen in, so the roots (and so the islands, their
    //    tags and their sums) are those of the serial union-find
    //    (tests/threads/island_test.cpp compares them);
    //  - each body's root is found in parallel;
    //  - the islands' minimum timers are atomic minima (order-independent);
    //  - the islands' sums of m v^2 and m stay on this thread, in solver
    //    order (floating-point sums: the order is part of the bits), one
    //    streaming pass.
    // Before, the unions, the finds, the minima and the clears were serial:
    // 40.5 M of the 127 M serial instructions of box_pile's first 120 steps
    // (callgrind), the largest serial part of the step after the time of impact.
    const auto pairCount = static_cast<std::uint32_t>(pairs.size());
    const auto bodyCount = static_cast<std::uint32_t>(n);
    parent_.resize(n);
    bodyEnergy_.resize(n);
    bodyMass_.resize(n);
    islandEnergy_.resize(n);
    islandMass_.resize(n);
    islandMinTime_.resize(n);
    islandTag_.resize(n);
    root_.resize(n);
    bodyTime_.resize(n);
    if (n == 0) return;
    parent_[0] = 0;
    // The speeds the test uses: each the smaller of the body's velocity and
    // how fast it actually moved over the step (sleep.hpp, "Held bodies").
    const Real invDt = dt > 0 ? Real(1) / dt : 0;
    speed2_.resize(n);
    spin2_.resize(n);
    const Real bodyCap2 = kBodySpeedCap * kBodySpeedCap * lin2;
    // Whether some body may pass the test below. One that fails it by
    // itself (it may not sleep, or it is faster than any island lets a body
    // be) gets its timer cleared here, as the test would; when every body
    // does (Jolt's HighSpeed: 5000 bullets at tens of m/s), no timer can
    // reach timeToSleep, and the islands (the unions, the finds, the sums in
    // solver order) and the test are skipped: the same timers, nothing falls
    // asleep (the islands were 1.5-2 % of that scene's time).
    // The islands' per-body entries are written in this pass unless the last
    // update skipped the islands (then in a pass of their own if this one
    // needs them: the same entries).
    std::atomic<bool> anyMayRest{false};
    const auto startIsland = [&](std::uint32_t i) {
        const Real mass = w.params[denseOf[i]].mass;
        parent_[i] = i;
        bodyEnergy_[i] = mass * speed2_[i];
        bodyMass_[i] = mass;
        islandEnergy_[i] = 0;
        islandMass_[i] = 0;
        islandMinTime_[i] = std::bit_cast<RealBits>(Real(1e30));
        islandTag_[i] = 0;
    };
    const bool startIslands = !islandsSkipped_;
    tasks.parallelFor(bodyCount - 1, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        bool mayRest = false;
        for (std::uint32_t i = begin + 1; i <= end; ++i) {
            const std::uint32_t d = denseOf[i];
            const BodyMotion& m = w.motion[d];
            const Real moved2 = lengthSquared(m.com - w.startCom[i]) * invDt * invDt;
            speed2_[i] = std::min(lengthSquared(m.v), moved2);
            // The turn over the step is only known modulo a full turn: used
            // while the spin turns the body by less than a radian a step. And
            // only asked for when the spin alone fails the test (the turn is
            // an atan2 per body; a spin under the sleep spin passes anyway).
            // Nor when the body fails the test already by its own speed (the
            // cap below) or may not sleep: the spin is then never read (the
            // chain benchmark's links, every step: 2-3 % of its time in atan2).
            const Real w2 = lengthSquared(m.w);
            spin2_[i] = w2;
            BodyParams& p = w.params[d];
            const bool speedMayPass = p.allowSleep && speed2_[i] <= (p.mass > 0 ? bodyCap2 : lin2);
            if (speedMayPass && w2 > ang2 && w2 * dt * dt < 1) {
                const Vec3 turn = toRotationVector(m.q * conjugate(w.startQ[i]));
                spin2_[i] = std::min(w2, lengthSquared(turn) * invDt * invDt);
            }
            if (startIslands) startIsland(i);
            const bool failsAlone =
                p.awake && (!p.allowSleep || speed2_[i] > (p.mass > 0 ? bodyCap2 : lin2));
            if (failsAlone) {
                p.sleepTime = 0;
            } else {
                mayRest = true;
            }
        }
        if (mayRest) anyMayRest.store(true, std::memory_order_relaxed);
    });
    const bool islandsNeeded = anyMayRest.load(std::memory_order_relaxed) || !(s.timeToSleep > 0) || !islandShortcut_;
    islandsSkipped_ = !islandsNeeded;
    if (islandsNeeded && !startIslands) {
        tasks.parallelFor(bodyCount - 1, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
            for (std::uint32_t i = begin + 1; i <= end; ++i) startIsland(i);
        });
    }

    // Islands over touching contacts between awake bodies (parallel) and
    // joints (this thread, after: they may wake bodies).
    const ContactArray& contacts = manager.contacts();
    if (islandsNeeded) {
        tasks.parallelFor(pairCount, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
            for (std::uint32_t k = begin; k < end; ++k) {
                const ContactSolver::ConstraintPair& c = pairs[k];
                if (c.bodyA != 0 && c.bodyB != 0 && contacts[c.contact].touching) uniteConcurrently(parent_.data(), c.bodyA, c.bodyB);
            }
        });
    }
    for (const JointData& j : joints) {
        if (!j.alive || !j.enabled || j.def.bodyA.isNull() || j.def.bodyB.isNull()) continue;
        const std::uint32_t da = w.bodySlots[j.def.bodyA.index].dense;
        const std::uint32_t db = w.bodySlots[j.def.bodyB.index].dense;
        const bool awakeA = w.params[da].awake, awakeB = w.params[db].awake;
        // A joint to a sleeping body wakes it (the island slept together, so this
        // only happens for a joint made since).
        if (awakeA != awakeB) {
            w.wakeBody(awakeA ? db : da);
            continue;  // joined next step, once both are in the solver
        }
        if (!awakeA) continue;
        const std::uint32_t ia = w.solverIndexOf(da), ib = w.solverIndexOf(db);
        if (ia == 0 || ib == 0 || !islandsNeeded) continue;
        const std::uint32_t ra = find(ia), rb = find(ib);
        if (ra != rb) parent_[std::max(ra, rb)] = std::min(ra, rb);
    }
    if (!islandsNeeded) {
        ++islandsSkippedCount_;
        return;
    }

    // Each body's root in parallel; the islands' sums in solver order here.
    tasks.parallelFor(bodyCount - 1, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t i = begin + 1; i <= end; ++i) root_[i] = findRootConcurrently(parent_.data(), i);
    });
    for (std::uint32_t i = 1; i < n; ++i) {
        const std::uint32_t root = root_[i];
        islandEnergy_[root] += bodyEnergy_[i];
        islandMass_[root] += bodyMass_[i];
    }
    // Timers of the bodies that were awake this step (the measure: sleep.hpp),
    // per body in parallel, and each island's smallest timer (an atomic
    // minimum on the bits: the timers are >= +0, where float order is the
    // order of the bits as unsigned integers).
    // Whether any timer reached timeToSleep: if none did, no island can
    // sleep and the serial pass over the roots is skipped (most steps).
    std::atomic<bool> anyTimerDue{false};
    tasks.parallelFor(bodyCount - 1, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        bool due = false;
        // Runs of bodies of one island (neighbours in solver order often
        // are) take their minimum locally: one atomic per run.
        std::uint32_t runRoot = root_[begin + 1];
        Real runMin = Real(1e30);
        for (std::uint32_t i = begin + 1; i <= end; ++i) {
            const std::uint32_t d = denseOf[i], root = root_[i];
            if (root != runRoot) {
                lowerConcurrently(islandMinTime_[runRoot], runMin);
                runRoot = root;
                runMin = Real(1e30);
            }
            BodyParams& p = w.params[d];
            bodyTime_[i] = 0;
            if (p.awake) {
                const Real v2 = speed2_[i];
                // Kinematic bodies (no mass, nothing in the island's energy) keep the plain test.
                const bool still =
                    p.mass > 0 ? islandEnergy_[root] <= lin2 * islandMass_[root] && v2 <= bodyCap2 : v2 <= lin2;
                // Rotation: the spin below angularSleepVelocity or, in a group, the
                // speed it gives the body's farthest point below the sleep speed
                // (Box2D's measure): sleep.hpp, "Rotation".
                const Real w2 = spin2_[i];
                const bool inGroup = p.mass > 0 && islandMass_[root] > bodyMass_[i];
                const bool turning = w2 > ang2 && !(inGroup && w2 * p.extent * p.extent <= lin2);
                if (!p.allowSleep || !still || turning) {
                    p.sleepTime = 0;
                } else {
                    p.sleepTime += dt;
                }
                bodyTime_[i] = p.sleepTime;
            }
            due = due || bodyTime_[i] >= s.timeToSleep;  // an island's minimum is one of its bodies' timers
            runMin = std::min(runMin, bodyTime_[i]);
        }
        lowerConcurrently(islandMinTime_[runRoot], runMin);
        if (due) anyTimerDue.store(true, std::memory_order_relaxed);
    });
    if (!anyTimerDue.load(std::memory_order_relaxed)) return;

    // Roots are the smallest index of their island, so tags follow solver order: deterministic.
    bool anyAsleep = false;
    for (std::uint32_t i = 1; i < n; ++i) {
        if (root_[i] == i && std::bit_cast<Real>(islandMinTime_[i]) >= s.timeToSleep) {
            islandTag_[i] = nextIsland_++;
            anyAsleep = true;
        }
    }
    if (!anyAsleep) return;
    for (std::uint32_t i = 1; i < n; ++i) {
        const std::uint32_t tag = islandTag_[root_[i]];
        if (tag == 0) continue;
        BodyParams& p = w.params[denseOf[i]];
        BodyMotion& m = w.motion[denseOf[i]];
        p.awake = false;
        p.sleepIsland = tag;
        m.v = {};
        m.w = {};
        // Off the awake list at the next refresh; its previous[] (set at this
        // step's start) needs the one refresh that makes it equal to its
        // transform for the rest of its sleep (body_store.hpp).
        w.awakeListHasSleepers = true;
        w.markPreviousStale(denseOf[i]);
    }
}

}  // namespace fulcrum::detail
