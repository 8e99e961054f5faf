#include "solver/sleep.hpp"

#include <algorithm>

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

    // Islands over touching contacts and joints between awake bodies.
    parent_.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) parent_[i] = i;
    // Solver index of a dense body: the constraints carry them, joints need a lookup.
    for (const ContactSolver::ConstraintPair& k : solver.pairs()) {
        if (k.bodyA == 0 || k.bodyB == 0) continue;
        if (!manager.contacts()[k.contact].touching) continue;
        const std::uint32_t ra = find(k.bodyA), rb = find(k.bodyB);
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

    // Timers of the bodies that were awake this step (the measure: sleep.hpp).
    islandEnergy_.assign(n, 0);
    islandMass_.assign(n, 0);
    for (std::uint32_t i = 1; i < n; ++i) {
        const std::uint32_t d = denseOf[i], root = find(i);
        islandEnergy_[root] += w.params[d].mass * lengthSquared(w.motion[d].v);
        islandMass_[root] += w.params[d].mass;
    }
    const Real bodyCap2 = kBodySpeedCap * kBodySpeedCap * lin2;
    for (std::uint32_t i = 1; i < n; ++i) {
        const std::uint32_t d = denseOf[i], root = find(i);
        BodyParams& p = w.params[d];
        if (!p.awake) continue;
        const BodyMotion& m = w.motion[d];
        const Real v2 = lengthSquared(m.v);
        // Kinematic bodies (no mass, nothing in the island's energy) keep the plain test.
        const bool still = p.mass > 0 ? islandEnergy_[root] <= lin2 * islandMass_[root] && v2 <= bodyCap2 : v2 <= lin2;
        if (!p.allowSleep || !still || lengthSquared(m.w) > ang2) {
            p.sleepTime = 0;
        } else {
            p.sleepTime += dt;
        }
    }

    islandMinTime_.assign(n, Real(1e30));
    for (std::uint32_t i = 1; i < n; ++i) {
        const BodyParams& p = w.params[denseOf[i]];
        const Real t = p.awake ? p.sleepTime : 0;
        Real& slot = islandMinTime_[find(i)];
        slot = std::min(slot, t);
    }
    // Roots are the smallest index of their island, so tags follow solver order: deterministic.
    islandTag_.assign(n, 0);
    for (std::uint32_t i = 1; i < n; ++i) {
        if (find(i) == i && islandMinTime_[i] >= s.timeToSleep) islandTag_[i] = nextIsland_++;
    }
    for (std::uint32_t i = 1; i < n; ++i) {
        const std::uint32_t tag = islandTag_[find(i)];
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
