#pragma once
// WorldImpl: the internal state behind fulcrum::World: a BodyStore (every
// body's data and, during a step, the awake set: src/dynamics/body_store.hpp)
// plus the springs, joints, subsystems, settings and bookkeeping of the world.
// The BodyStore is its base rather than a member so that the world's code,
// the Python binding, io and the tests keep reading bodies as `w.motion[d]`;
// a subsystem is handed the BodyStore part (`*this` converts) and sees
// nothing else of the world.
//
// The subsystems below the world (src/contacts, src/solver, src/islands,
// src/dynamics) never see this struct: the step (src/world/step.cpp) hands
// each one the body store, the settings it needs and the task system, and
// applies what they hand back (wake-ups go through the store's wake queue,
// broken joints' pair resets and the contact report are the world's). So a
// subsystem's contract is its own header, not this one.
//
// Springs and joints
// ------------------
// Stored in slot pools (dynamics/slot_pool.hpp: a generation and an `alive`
// flag per slot; they are few and rarely iterated outside the step, so holes
// are fine). They refer to
// bodies by BodyId and resolve the dense index when used; a body's
// destruction destroys its springs and joints first, so they never hold a
// stale BodyId. Anchors are stored relative to the body's centre of mass in
// body axes (world-fixed ends keep their world point).
//
// Contacts
// --------
// `contacts` holds the touching manifolds of the last step as ContactReports
// (src/contacts/contact_manager.hpp fills it). World::contacts() returns a copy of
// the first contactReportCount entries. The report is built lazily: the step
// only marks it stale, and ensureContactReport() builds it from the contacts as
// the step left them when someone reads it (World::contacts(), snapshots), or
// before anything changes those contacts between steps (a body destroyed, a
// joint resetting pairs). Same reports as building it in every step, without
// the O(all contacts) pass per step (23 % of an all-asleep box_pile step).
//
// No heap allocation per step: every scratch array is sized when bodies are
// created and reused.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fulcrum/task_system.hpp"
#include "fulcrum/world.hpp"
#include "dynamics/body_store.hpp"
#include "dynamics/forces.hpp"
#include "contacts/contact_manager.hpp"
#include "dynamics/slot_pool.hpp"
#include "solver/contact_solver.hpp"
#include "solver/joint_data.hpp"
#include "solver/joint_solver.hpp"
#include "islands/sleep.hpp"
#include "threads/staged_parallel.hpp"
#include "world/particle_coupling.hpp"
#include "world/stray_bodies.hpp"
#include "character/character_system.hpp"
#include "vehicle/vehicle_system.hpp"

namespace fulcrum {

struct WorldImpl : detail::BodyStore {
    WorldDef settings;
    double time = 0;                 // double: a float clock loses sub-steps after hours
    std::uint64_t stepCount = 0;
    StepProfile profile;  // the last step's (World::lastStepProfile)
    std::uint64_t nonFiniteSinceStep = 0;  // != 0: that step threw NumericalError (World::step)
    std::uint64_t outOfMemoryAtStep = 0;   // != 0: that step ran out of memory; no more steps (World::step)
    // Freed when a step runs out of memory, so that the error's message (a
    // few hundred bytes) can still be built: without it std::bad_alloc, not
    // the explanation, would leave World::step (World::step's handler).
    std::unique_ptr<char[]> outOfMemoryReserve = std::make_unique<char[]>(16 * 1024);
    std::vector<WorldWarning> warnings;    // World::warnings: each kind once
    bool warnedPairLimit = false;          // the contact pair limit was reached (step.cpp)
    std::uint64_t nextBodySerial = 0;
    // What createBody last reserved the contact buffers for (World::createBody).
    struct ReservedFor {
        std::size_t bufferBodies = SIZE_MAX;
        std::int64_t maxContactPairs = -1;
        std::uint64_t step = 0;
        bool operator==(const ReservedFor&) const = default;
    };
    ReservedFor reservedFor;

    // ---- springs and joints
    detail::SlotPool<detail::SpringData, SpringId> springs;
    detail::SlotPool<detail::JointData, JointId> joints;

    // ---- contacts of the last step (filled by the collision pipeline): the
    // first contactReportCount entries are valid; the rest keep their capacity
    // so reporting allocates nothing in steady state.
    std::vector<ContactReport> contacts;
    std::size_t contactReportCount = 0;
    bool contactReportStale = false;  // the step ran since `contacts` was built (see above)
    Real lastStepDt = 0;              // the last step's dt: the report's forces are its impulses / dt
    // The last step's impacts (World::contactHitEvents), built like the report
    // when read, from the solver's constraint list of that step.
    std::vector<ContactHitEvent> hitEvents;
    bool hitEventsStale = false;
    void ensureContactReport() {
        ensureHitEvents();  // from the same contacts, before they change
        if (!contactReportStale) return;
        contactManager.report(*this, contacts, contactReportCount, lastStepDt, taskSystem());
        contactReportStale = false;
    }
    void ensureHitEvents() {
        if (!hitEventsStale) return;
        contactManager.hitEvents(*this, contactSolver.pairs(), settings.hitEventThreshold, hitEvents);
        hitEventsStale = false;
    }

    // ---- subsystems: collision pipeline (src/contacts), solvers (src/solver), islands (src/islands)
    detail::ContactManager contactManager;
    detail::ContactSolver contactSolver;
    detail::JointSolver jointSolver;
    detail::SleepManager sleepManager;
    bool wasSleeping = true;         // settings.sleeping at the last step (turning it off wakes all)

    // ---- particle systems: ropes and cloths (src/world/particle_coupling.hpp)
    detail::WorldParticles particles;

    // ---- characters (src/character/character_system.hpp): moved after each step
    detail::CharacterSystem characters;
    // ---- vehicles (src/vehicle/vehicle_system.hpp): forces applied before each step
    detail::VehicleSystem vehicles;

    // ---- world queries (src/world/world_queries.cpp): bodies that have left
    // their broad-phase proxy since it was last moved. Rebuilt lazily per step;
    // code that moves bodies outside step() and setTransform must invalidate it.
    detail::StrayBodies strayBodies;

    // ---- threads (src/world/step.cpp, docs/threading.md): the scheduler the
    // step's parallel loops run on. A user's (setTaskSystem) if set, else the
    // inline one for threads == 1, else a pool created on first use.
    TaskSystem* userTasks = nullptr;
    std::unique_ptr<TaskSystem> ownedPool;
    int ownedPoolThreads = 0;
    InlineTaskSystem inlineTasks;
    bool stepOnCaller = false;  // this step is below settings.parallelMinBodies: inline
    TaskSystem& taskSystem();
    // The sub-steps' stage list (step.cpp), kept between steps so that its
    // storage is reused (no allocation per step).
    detail::StagedParallel subSteps;
    // What buildSubSteps made the list from (besides the contact solver's
    // pass stages, ContactSolver::takePassStagesChanged): while it is
    // unchanged the list is kept (rebuilding it was ~1.4 % of a ten-body step).
    struct SubStepKey {
        std::uint32_t bodies = 0, workers = 0, projectionGroups = 0;
        int substeps = 0, iterations = 0;
        Integrator integrator = Integrator::SemiImplicitEuler;
        bool callbacks = false, springs = false, contacts = false, joints = false, built = false;
        bool drag = false, forcesOnce = false, motionKinds = false;
        bool operator==(const SubStepKey&) const = default;
    };
    SubStepKey subStepKey;
    bool anyDrag = false;  // an awake body has drag this step (prepareSolvers; buildSubSteps)
    // The bodies' MotionKinds were decided for this step (prepareSolvers:
    // integrators.hpp, classifyMotion), so the sub-steps read them.
    bool motionKindsKept = false;

    detail::SpringData& resolveSpring(SpringId id, const char* where);
    const detail::SpringData& resolveSpring(SpringId id, const char* where) const;
    detail::JointData& resolveJoint(JointId id, const char* where);
    const detail::JointData& resolveJoint(JointId id, const char* where) const;

    // The step (src/world/step.cpp).
    void step(Real dt);
    void notePairLimit(StepProfile& prof);  // the step's pair-limit counts and warning
    // The step's parts (step.cpp, in this order).
    void refreshPrevious(TaskSystem& tasks);
    bool prepareSolvers(TaskSystem& tasks, Real h);  // returns whether a body has a ForceCallback
    void buildSubSteps(TaskSystem& tasks, bool anyCallback);
    void runSubSteps(TaskSystem& tasks, double t0, Real h, double hd);
    std::uint32_t finishStep(TaskSystem& tasks);  // clears user forces; returns the first non-finite body
    [[noreturn]] void throwNonFinite(std::uint32_t firstBad) const;
    // After jointSolver.store(): the pairs of the joints it broke may collide again.
    void resetPairsOfBrokenJoints();
    // What the contact manager and the time of impact ask the joints.
    detail::JointPairFilter jointPairFilter() const { return {&jointSolver.graph(), &joints.slots()}; }
};

}  // namespace fulcrum
