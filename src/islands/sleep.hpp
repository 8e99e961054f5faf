#pragma once
// Islands and sleeping.
//
// After each step, the awake bodies are grouped into islands by union-find over
// touching contacts and joints (static bodies don't join islands: a floor
// doesn't tie everything on it together). Each body keeps a sleep timer that
// grows while it is still, and resets otherwise. Still means: its spin is
// below angularSleepVelocity (in a group of two or more bodies, or the speed
// that spin gives its farthest point, |w| * extent, is below
// linearSleepVelocity: Box2D's measure, "Rotation" below), and its island's
// mass-weighted RMS speed
// sqrt(sum m v^2 / sum m) is below linearSleepVelocity with no body of the
// island faster than kBodySpeedCap times it (kinematic bodies: their own speed
// below it). A lone body is thus held to the sleep speed exactly; in a resting
// group, a body may move at up to twice the sleep speed while the group as a
// whole moves less. Why (docs/solver.md, "Sleeping"): box_pile's 400 towers of
// 10 boxes stand but sway for seconds, their top boxes at 0.05-0.1 m/s while
// the towers' RMS speed is ~0.6 of that; with the per-body rule the pile was
// all asleep only at step ~510, with this one at ~270 (PhysX's measure is also
// a mass-normalised kinetic energy, ~0.1 m/s by default). An island whose every
// body's timer has reached timeToSleep falls asleep: velocities zeroed,
// `awake` cleared, all bodies tagged with one island id so that waking any of
// them (contact, joint, user call) wakes the whole island at once
// (BodyStore::wakeBody). Sleeping bodies are skipped by the integrators, the
// broad phase updates, the narrow phase (when both ends sleep or are static)
// and the solver: they cost nothing per step beyond this bookkeeping.
//
// Rotation. A small limb in a resting ragdoll pile rocks at 0.05-0.3 rad/s
// while its farthest point moves at under 3 cm/s (measured at step 1200 of
// bench_joints --scene ragdolls): the per-body spin test kept the pile awake
// for good in some runs (with --gauss-seidel, or after a change in the last
// bits of the integrator: 0-143 of 1100 bodies asleep at step 1800). Bounding
// the farthest point's speed instead lets it sleep by step 600 either way.
// A lone body keeps the plain spin test, as it keeps the plain speed test.
//
// Held bodies. The speeds tested are each the smaller of the body's velocity
// and the rate it actually moved over the step (centre of mass, and turn while
// that is under a radian a step). A body held where its constraints disagree
// (a forearm wedged between the floor, another ragdoll and its own elbow,
// whose joint the position projection pulls back each sub-step while the
// contacts push it out) can stand still with a velocity the next sub-step
// undoes again: 0.027 m/s and 0.39 rad/s while it moved 0.4 mm/s, for
// thousands of steps, keeping a 100-ragdoll pile awake. Jolt's sleep test is
// likewise on positions (points of the body staying inside small spheres).
// A moving body moves: its displacement rate is its speed.
//
// Rebuilding islands every step (instead of Box2D's persistent islands with
// deferred splitting) costs one near-linear pass over awake bodies and
// constraints; it is simple and deterministic.
#include <cstdint>
#include <vector>

#include "fulcrum/math.hpp"
#include "fulcrum/task_system.hpp"
#include "dynamics/body_store.hpp"
#include "math/real_bits.hpp"
#include "solver/contact_solver.hpp"

namespace fulcrum {
struct SnapshotAccess;  // src/world/snapshot.cpp: saves and restores private state
}

namespace fulcrum::detail {

class ContactManager;
struct JointData;

// The settings the islands read (WorldDef's sleeping and sleep thresholds).
struct SleepSettings {
    bool sleeping = true;
    Real linearSleepVelocity = Real(0.05), angularSleepVelocity = Real(0.05), timeToSleep = Real(0.5);
};

// Union-find on parent[] (parent[i] == i: a root) that several threads may
// run at once, each call on any elements: `uniteConcurrently` links the
// larger of the two roots under the smaller with a CAS that succeeds only
// while it is still a root (else it finds again), and finds shorten paths
// with relaxed stores. Links always point to a smaller index, so every root
// is the smallest element of its set, whatever order the links happen in:
// after the threads are done (a barrier), the roots are exactly those of the
// serial union-find with the same rule, for any thread count and scheduler
// (tests/threads/island_union_find_test.cpp). Lock-free; the idea of CAS
// linking is Anderson and Woll, "Wait-free parallel algorithms for the
// union-find problem" (STOC 1991).
std::uint32_t findRootConcurrently(std::uint32_t* parent, std::uint32_t i);
void uniteConcurrently(std::uint32_t* parent, std::uint32_t a, std::uint32_t b);

class SleepManager {
public:
    // Updates timers and puts resting islands to sleep. Reads the store's
    // awake set's list (the awake bodies of this step) and its start poses,
    // the records as the step left them, the contact solver's constraint
    // pairs, the contacts' touching flags and the joints; wakes bodies
    // through the store's wake queue.
    void update(BodyStore& w, const SleepSettings& s, const std::vector<ContactSolver::ConstraintPair>& pairs,
                const ContactManager& contacts, const std::vector<JointData>& joints, TaskSystem& tasks, Real dt);

    void reserve(std::size_t bodyCount) {
        if (parent_.capacity() < bodyCount + 1) {
            const auto perBody = [&](auto&... v) { (v.reserve(2 * bodyCount + 1), ...); };
            perBody(parent_, islandMinTime_, islandTag_, islandEnergy_, islandMass_, root_, bodyEnergy_, bodyMass_,
                    bodyTime_, speed2_, spin2_);
        }
    }

    // Tests: false makes every update build the islands, even when every body
    // fails the test by itself (update's shortcut; the same results).
    void setIslandShortcut(bool enabled) { islandShortcut_ = enabled; }
    // How many updates took the shortcut (tests).
    std::uint64_t islandsSkippedCount() const { return islandsSkippedCount_; }

private:
    friend struct fulcrum::SnapshotAccess;
    std::uint32_t find(std::uint32_t i);
    // slotBits = min(slot, value) for timers (>= +0), as the floats' bits.
    static void lowerConcurrently(RealBits& slotBits, Real value);
    std::vector<std::uint32_t> parent_;
    std::vector<RealBits> islandMinTime_;  // per island root: its bodies' smallest timer, as Real's bits
    std::vector<std::uint32_t> islandTag_;
    std::vector<Real> islandEnergy_;  // per island root: sum of m v^2
    std::vector<Real> islandMass_;    // per island root: sum of m
    std::vector<std::uint32_t> root_;  // per solver body: its island's root (after the unions)
    std::vector<Real> bodyEnergy_;     // per solver body: m v^2
    std::vector<Real> bodyMass_;       // per solver body: m
    std::vector<Real> speed2_, spin2_;  // per solver body: the squared speed and spin the test uses
    std::vector<Real> bodyTime_;       // per solver body: its timer (0 when not awake), for the island minimum
    static constexpr Real kBodySpeedCap = 2;  // times linearSleepVelocity, for a body in a still island
    std::uint32_t nextIsland_ = 1;
    bool islandShortcut_ = true;
    bool islandsSkipped_ = false;  // the last update skipped the islands (update: where their entries are written)
    std::uint64_t islandsSkippedCount_ = 0;
};

}  // namespace fulcrum::detail
