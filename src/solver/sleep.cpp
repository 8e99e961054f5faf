#include "solver/sleep.hpp"

#include <algorithm>

#include "fulcrum/task_system.hpp"
#include "solver/contact_manager.hpp"
#include "solver/contact_solver.hpp"
#include "world/world_impl.hpp"

namespace fulcrum::detail {

std::uint32_t SleepManager::find(std::uint32_t i) {
    while (parent_[i] != i) {
        parent_[i] = parent_[parent_[i]];  // path halving
        i = parent_[i];
    }
    return i;
}

void SleepManager::update(WorldImpl& w, const ContactSolver& solver, const ContactManager& manager, Real dt) {
    const std::vector<std::uint32_t>& denseOf = solver.denseOfSolverBody();
    const std::size_t n = denseOf.size();  // entry 0 is the static stand-in
    const WorldDef& s = w.settings;
    const Real lin2 = s.linearSleepVelocity * s.linearSleepVelocity;
    const Real ang2 = s.angularSleepVelocity * s.angularSleepVelocity;

    if (!s.sleeping) {
        for (std::size_t i = 1; i < n; ++i) w.params[denseOf[i]].sleepTime = 0;
        return;
    }

    // The per-index parts run on the task system (each index writes only its
    // own slots); the union-find and every sum or minimum over an island stay
    // on this thread, in solver order, so the bits do not depend on the
    // thread count. The parallel parts are the ones that read the contacts
    // and bodies (a cache miss each): islands were 1.4-1.7 % of the one-thread
    // step of the pile collapses, all serial.
    TaskSystem& tasks = w.taskSystem();
    const std::vector<ContactSolver::ConstraintPair>& pairs = solver.pairs();
    const auto pairCount = static_cast<std::uint32_t>(pairs.size());
    const auto bodyCount = static_cast<std::uint32_t>(n);
    joins_.resize(pairCount);
    tasks.parallelFor(pairCount, 256, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t k = begin; k < end; ++k) {
            const ContactSolver::ConstraintPair& c = pairs[k];
            joins_[k] = c.bodyA != 0 && c.bodyB != 0 && manager.contacts()[c.contact].touching ? 1 : 0;
        }
    });
    parent_.resize(n);
    bodyEnergy_.resize(n);
    bodyMass_.resize(n);
    if (n > 0) parent_[0] = 0;
    // The speeds the test uses: each the smaller of the body's velocity and
    // how fast it actually moved over the step (sleep.hpp, "Held bodies").
    const Real invDt = dt > 0 ? Real(1) / dt : 0;
    speed2_.resize(n);
    spin2_.resize(n);
    tasks.parallelFor(bodyCount - 1, 256, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t i = begin + 1; i <= end; ++i) {
            const std::uint32_t d = denseOf[i];
            const BodyMotion& m = w.motion[d];
            const Real moved2 = lengthSquared(m.com - solver.startCom(i)) * invDt * invDt;
            speed2_[i] = std::min(lengthSquared(m.v), moved2);
            // The turn over the step is only known modulo a full turn: used
            // while the spin turns the body by less than a radian a step. And
            // only asked for when the spin alone fails the test (the turn is
            // an atan2 per body; a spin under the sleep spin passes anyway).
            const Real w2 = lengthSquared(m.w);
            spin2_[i] = w2;
            if (w2 > ang2 && w2 * dt * dt < 1) {
                const Vec3 turn = toRotationVector(m.q * conjugate(solver.startOrientation(i)));
                spin2_[i] = std::min(w2, lengthSquared(turn) * invDt * invDt);
            }
            parent_[i] = i;
            bodyEnergy_[i] = w.params[d].mass * speed2_[i];
            bodyMass_[i] = w.params[d].mass;
        }
    });

    // Islands over touching contacts and joints between awake bodies.
    for (std::uint32_t k = 0; k < pairCount; ++k) {
        if (joins_[k] == 0) continue;
        const std::uint32_t ra = find(pairs[k].bodyA), rb = find(pairs[k].bodyB);
        if (ra != rb) parent_[std::max(ra, rb)] = std::min(ra, rb);
    }
    for (const JointData& j : w.joints) {
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
        const std::uint32_t ia = solver.solverIndexOf(da), ib = solver.solverIndexOf(db);
        if (ia == 0 || ib == 0) continue;
        const std::uint32_t ra = find(ia), rb = find(ib);
        if (ra != rb) parent_[std::max(ra, rb)] = std::min(ra, rb);
    }

    // Each body's root, and the islands' sums in solver order.
    islandEnergy_.assign(n, 0);
    islandMass_.assign(n, 0);
    root_.resize(n);
    for (std::uint32_t i = 1; i < n; ++i) {
        const std::uint32_t root = find(i);
        root_[i] = root;
        islandEnergy_[root] += bodyEnergy_[i];
        islandMass_[root] += bodyMass_[i];
    }
    // Timers of the bodies that were awake this step (the measure: sleep.hpp),
    // per body in parallel; bodyTime_ is what the island minimum below reads.
    const Real bodyCap2 = kBodySpeedCap * kBodySpeedCap * lin2;
    bodyTime_.resize(n);
    tasks.parallelFor(bodyCount - 1, 256, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t i = begin + 1; i <= end; ++i) {
            const std::uint32_t d = denseOf[i], root = root_[i];
            BodyParams& p = w.params[d];
            bodyTime_[i] = 0;
            if (!p.awake) continue;
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
    });

    islandMinTime_.assign(n, Real(1e30));
    for (std::uint32_t i = 1; i < n; ++i) {
        Real& slot = islandMinTime_[root_[i]];
        slot = std::min(slot, bodyTime_[i]);
    }
    // Roots are the smallest index of their island, so tags follow solver order: deterministic.
    islandTag_.assign(n, 0);
    bool anyAsleep = false;
    for (std::uint32_t i = 1; i < n; ++i) {
        if (root_[i] == i && islandMinTime_[i] >= s.timeToSleep) {
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
        // transform for the rest of its sleep (world_impl.hpp).
        w.awakeListHasSleepers = true;
        w.markPreviousStale(denseOf[i]);
    }
}

}  // namespace fulcrum::detail
