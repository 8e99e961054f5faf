// The step pipeline.
//
// Design
// ------
// A step of `dt` is this pipeline (WorldImpl::step below):
//
//   collide      proxies follow the awake bodies; broad phase, contacts,
//                narrow phase, events (wakes what awake bodies touch)
//   prepare      the awake set is filled from the records (BodyStore::beginStep),
//                the contact and joint constraints are built on the step's start
//                configuration, graph colouring, the first forces
//   sub-steps    ONE list of stages (buildSubSteps), run by one scheduler
//   restitution  once per step on the final velocities, then the impulses
//   + store      are stored (contacts and joints; breaking)
//   continuous   time of impact (and the joint projection it may need)
//   records      the awake set written back into the body records, once
//   particles, sleep, finish (user forces cleared, NaN check, time advances)
//
// Each sub-step of h = dt / substeps is a fixed sequence of stages:
//
//   1. compute forces        gravity, drag, springs, user forces, callbacks -> forces[]
//   2. integrate velocities  v, w from the forces (+ damping)
//   3. solve                 joints then contacts: warm start, then velocity
//                            constraints with soft position bias (Box2D v3 soft
//                            step, src/solver), solverIterations times
//   4. integrate positions   x, q from the velocities; the pose change since the
//                            step's start for the kernels (dp, dtheta; with joints
//                            after 4b)
//   4b. project              joints: anchors put back together at the position level
//   4c. relax                the solver's bias-free pass on the step's anchors
//   5. finalize              Verlet's second kick
//
// One home for body state: from prepare to the records stage every stage
// reads and writes the awake bodies in the body store's awake set
// (src/dynamics/body_store.hpp): integrators, forces, contact and joint
// kernels, projection and time of impact work on the same arrays, so nothing
// is copied between sub-steps (before, velocities crossed between the
// integrators' records and the solver's bodies four times per sub-step).
// Every per-body stage walks the awake list, so sleeping and static bodies
// cost nothing per step (docs/solver.md, "Sleeping").
//
// This is the shape of Box2D v3's soft step (integrate velocities, warm start
// and solve, integrate positions, relax), so the constraint solver slots in
// between stages 2 and 4 without touching the integrators: every integrator
// leaves in the awake set the velocity that positions will use, and position
// integration reads it back after the solver has corrected it.
//
// How each integrator maps onto the stages:
//   semi-implicit Euler  stage 2 is v += a h (the standard form), stage 4 x += v h.
//                        Nothing to finalize. This is the engine's default and
//                        the solver's natural partner (Catto, Box2D, bepu, Jolt).
//   explicit Euler       positions must move with the *old* velocity. Stage 2
//                        stores the velocity change due to forces (scratch.dv);
//                        stage 4 drifts with v - dv, i.e. the old velocity plus
//                        any correction the solver made. Same cost as semi-implicit.
//   Verlet               velocity Verlet in kick-drift-kick form: stage 2 is the
//                        first half kick v += a h/2, stage 4 the drift x += v h,
//                        stage 5 evaluates forces at the new positions and gives
//                        the second half kick. Its positions are exactly those of
//                        the position form x' = 2x - x_prev + a h^2 (test:
//                        VerletMatchesPositionForm). The stage-5 evaluation is
//                        reused as the next sub-step's stage 1 ("first same as
//                        last"), so Verlet costs substeps + 1 force evaluations per
//                        step; stage 1 of a step's first sub-step always
//                        re-evaluates, because the user may have changed bodies
//                        or forces between steps.
//
// The stage list (docs/threading.md): per-body stages (units of
// kBodiesPerRange awake bodies), the contact solver's passes (a stage per
// graph colour, units of wide blocks; the overflow colour one unit), serial
// single-unit stages (springs, the joint projection), and caller stages, run
// on the calling thread between the parallel segments: the ForceCallbacks in
// body order (user code) and the joint solver's passes (they spread their own
// colours and trees over the task system). StagedParallel runs
// the list: with one worker every stage in order on this thread; with more,
// each run of stages between two caller stages inside ONE parallelFor, each
// stage's units independent. A stage is added in one place, for every
// thread count, and per-body work that needs nothing from other bodies
// shares a stage (the next sub-step's forces with its velocities) so its data
// stays in cache.
//
// Every range writes only the slots of the indices it covers and anything
// order-dependent (contact creation, events, wakes, tree updates, callbacks,
// springs) is applied on one thread in index order, so results are
// bit-identical for every thread count and scheduler
// (tests/threads/step_determinism_test.cpp). No heap allocation happens here
// in steady state: every scratch array is sized at body creation, per-worker
// buffers and the stage list on the first step with a given size.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#if defined(__x86_64__) || defined(_M_X64)
#if defined(_MSC_VER)
#include <intrin.h>
#else
#include <x86intrin.h>
#endif
#endif

#include "dynamics/forces.hpp"
#include "dynamics/integrators.hpp"
#include "dynamics/validation.hpp"
#include "contacts/continuous.hpp"
#include "world/invariants.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

namespace {

// Which part of a body's state is not finite ("" when all is).
[[gnu::always_inline]] inline const char* firstNonFinite(const detail::BodyMotion& m) {
    if (!isFinite(m.com)) return "position";
    if (!isFinite(m.q)) return "orientation";
    if (!isFinite(m.v)) return "linear velocity";
    if (!isFinite(m.w)) return "angular velocity";
    return "";
}

constexpr std::uint32_t kNoIndexBody = UINT32_MAX;

// World::lastStepProfile's clock. The whole step is timed with steady_clock;
// the phase boundaries read a cheaper counter (the time-stamp counter on
// x86-64) and each phase gets its share of the step's time by that count.
// Nine steady_clock reads were ~0.6 us of a ten-body step of ~8 us on the
// benchmark VM (60-75 ns a read; rdtsc 25-35 ns): the profile is always on,
// so its cost is part of every step's fixed cost.
class PhaseClock {
public:
    // Ends the phase whose time goes to `phase` (written by finish()).
    void lap(double& phase) {
        const std::uint64_t now = ticks();
        laps_[count_] = now > last_ ? now - last_ : 0;  // a core switch may show a counter going back
        phases_[count_++] = &phase;
        last_ = now;
    }
    // The step's steady_clock milliseconds into `total`, and the phases' shares.
    void finish(double& total) {
        total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
        std::uint64_t span = 0;
        for (int i = 0; i < count_; ++i) span += laps_[i];
        const double msPerTick = span > 0 ? total / static_cast<double>(span) : 0.0;
        for (int i = 0; i < count_; ++i) *phases_[i] = static_cast<double>(laps_[i]) * msPerTick;
    }

private:
    static std::uint64_t ticks() {
#if defined(__x86_64__) || defined(_M_X64)
        return __rdtsc();
#else
        return static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
#endif
    }
    static constexpr int kMaxPhases = 8;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::uint64_t last_ = ticks();
    std::uint64_t laps_[kMaxPhases] = {};
    double* phases_[kMaxPhases] = {};
    int count_ = 0;
};

// Bodies per range of the per-body loops: integrating one costs ~20-60 ns, so
// 64 of them (1-4 us) amortise a range's scheduling (~0.1-0.2 us on the
// pool). Was 256: box_pile's ~950 still-awake bodies (steps 160-250) then
// made 3 ranges, and 2 threads were no faster than one there.
constexpr std::uint32_t kBodiesPerRange = 64;
// The joint projection's check (JointSolver::checkProjection): a group of
// four joints is ~450 instructions, so 16 groups a range.
constexpr std::uint32_t kProjectionGroupsPerRange = 16;

// FULCRUM_STAGED=0 turns the staged sub-steps off (staged_parallel.hpp).
std::atomic<bool> gStagedSubSteps{[] {
    const char* value = std::getenv("FULCRUM_STAGED");
    return value == nullptr || value[0] != '0';
}()};

// Tests only: off, every sub-step evaluates the forces again (the path
// before the forces were kept for the step, to compare bit for bit).
std::atomic<bool> gForcesOncePerStep{true};
// Tests only: off, the sub-steps test each body's type, inertia, damping and
// torque again (the path before the MotionKinds, to compare bit for bit).
std::atomic<bool> gMotionKindsPerStep{true};

}  // namespace

namespace detail {
bool stagedSubStepsEnabled() { return gStagedSubSteps.load(std::memory_order_relaxed); }
void setStagedSubStepsEnabled(bool enabled) { gStagedSubSteps.store(enabled, std::memory_order_relaxed); }
bool forcesOncePerStepEnabled() { return gForcesOncePerStep.load(std::memory_order_relaxed); }
void setForcesOncePerStepEnabled(bool enabled) { gForcesOncePerStep.store(enabled, std::memory_order_relaxed); }
bool motionKindsPerStepEnabled() { return gMotionKindsPerStep.load(std::memory_order_relaxed); }
void setMotionKindsPerStepEnabled(bool enabled) { gMotionKindsPerStep.store(enabled, std::memory_order_relaxed); }
}  // namespace detail

// The contact pair limit's counts in the profile, and a warning the first
// time the limit held pairs back (WorldDef::maxContactPairs).
void WorldImpl::notePairLimit(StepProfile& prof) {
    const PairUpdateStats& stats = contactManager.lastPairStats();
    prof.contactPairs = contactManager.liveContactCount();
    prof.contactPairLimit = contactManager.lastPairLimit();
    prof.pairsLeftOut = stats.leftOut;
    prof.bodiesOverPairLimit = stats.deferred;
    if (stats.deferred == 0 || warnedPairLimit) return;
    warnedPairLimit = true;
    const std::string setting = settings.maxContactPairs > 0
                                    ? "WorldDef::maxContactPairs"
                                    : "WorldDef::maxContactPairs = 0, automatic: " + std::to_string(kAutoContactPairsPerBody) +
                                          " per body + " + std::to_string(kAutoContactPairsBase);
    warnings.push_back(
        {stepCount + 1,
         "contact pair limit reached: " + std::to_string(prof.contactPairs) + " pairs held, the limit is " +
             std::to_string(prof.contactPairLimit) + " (" + setting +
             "; scene files: world.max_contact_pairs); the new pairs of " + std::to_string(stats.deferred) +
             " bodies wait for room, and until they get it those bodies pass through each other. Raise the limit if "
             "memory allows (about 2 KB per pair), or start the bodies apart"});
}

TaskSystem& WorldImpl::taskSystem() {
    if (userTasks != nullptr) return *userTasks;
    if (settings.threads <= 1 || stepOnCaller) return inlineTasks;
    if (ownedPool == nullptr || ownedPoolThreads != settings.threads) {
        ownedPool.reset();  // join the old threads before starting new ones
        ThreadPoolDef def;
        def.threads = static_cast<std::uint32_t>(settings.threads);
        ownedPool = makeThreadPool(def);
        ownedPoolThreads = settings.threads;
    }
    return *ownedPool;
}

namespace {

// What a stage of the sub-step list runs (WorldImpl::buildSubSteps).
enum StageKind : std::uint32_t {
    kForces,            // per body: stage 1 without ForceCallbacks and springs
    kCallbacks,         // caller stage: the ForceCallbacks in body order (arg: the time, see callbackTime)
    kSprings,           // one unit: the springs
    kVelocities,        // per body: stage 2 (arg 1: with the MotionKinds' plain velocities, integrateVelocities)
    kForcesVelocities,  // per body: stages 1 and 2 body by body (no callback, no spring)
    kJointPass,         // caller stage: the joint solver's pass `arg` (ContactSolver::Pass)
    kContactPass,       // the contact solver's stages (ContactSolver::addPassStages)
    kPositions,         // per body: stage 4 (arg: the kPositions flags below)
    kProjectionCheck,   // per group of four joints: whether the projection has anything to do (4b)
    kProjection,        // one unit: the joints' position projection (4b)
    kDeltas,            // per body: the pose change since the step's start (after the projection)
    kVerletPredict,     // per body: stage 5's predictor velocities
    kVerletKick,        // per body: stage 5's second half kick
};

// A kPositions stage's arg: the step has constraints, so also the pose change
// since the step's start; the bodies' MotionKinds were decided for the step.
constexpr std::uint32_t kPositionsDeltas = 1, kPositionsKinds = 2;

// kForcesVelocities walks its range in blocks of this many bodies, so each
// body's data stays in L1 from its force evaluation to its velocity update.
constexpr std::uint32_t kFusedBlock = 32;

// A kCallbacks stage's arg: sub-step s's start (2 s) or end (2 s + 1, Verlet).
// The end is the start plus hd, rounded as the loop of sub-steps always did.
double callbackTime(double t0, double hd, std::uint32_t arg) {
    const double start = t0 + hd * static_cast<double>(arg / 2);
    return (arg & 1) != 0 ? start + hd : start;
}

}  // namespace

void WorldImpl::step(Real dt) {
    PhaseClock clock;
    StepProfile prof;
    const Real h = dt / static_cast<Real>(settings.substeps);
    const double hd = static_cast<double>(dt) / settings.substeps;
    const double t0 = time;

    FULCRUM_VALIDATE_PHASE(*this, StepStart);
    // Turning sleeping off wakes everything once.
    if (!settings.sleeping && wasSleeping) {
        for (std::uint32_t i = 0; i < motion.size(); ++i) wakeBody(i);
    }
    wasSleeping = settings.sleeping;
    // The per-body stages walk the awake list only (body_store.hpp): a body
    // that sleeps or is static costs nothing per step.
    refreshAwakeList();
    // A small step runs on this thread alone (WorldDef::parallelMinBodies):
    // decided once, here, for the whole step.
    stepOnCaller = awakeBodies.size() < settings.parallelMinBodies;
    TaskSystem& tasks = taskSystem();
    refreshPrevious(tasks);

    // Collide: broad phase, contacts, narrow phase (wakes what awake bodies
    // touch: they move in this step, so the list is refreshed again).
    contactManager.update(*this, {settings.speculativeMargin, settings.maxContactPairs}, jointPairFilter(), tasks, dt);
    clock.lap(prof.collide);
    notePairLimit(prof);
    refreshAwakeList();
    FULCRUM_VALIDATE_PHASE(*this, AfterCollide);

    // Prepare: the awake set, constraints on the step's start configuration, the first forces.
    const bool anyCallback = prepareSolvers(tasks, h);
    FULCRUM_VALIDATE_PHASE(*this, AfterPrepare);
    const bool hasContacts = contactSolver.constraintCount() > 0;
    const bool hasJoints = jointSolver.constraintCount() > 0;
    clock.lap(prof.prepare);
    prof.awakeBodies = static_cast<std::uint32_t>(awakeBodies.size());
    prof.contactConstraints = static_cast<std::uint32_t>(contactSolver.constraintCount());
    prof.jointConstraints = static_cast<std::uint32_t>(jointSolver.constraintCount());
    prof.workers = tasks.workerCount();

    // The sub-steps: one list of stages, one scheduler.
    buildSubSteps(tasks, anyCallback);
    runSubSteps(tasks, t0, h, hd);
    FULCRUM_VALIDATE_PHASE(*this, AfterSubsteps);
    clock.lap(prof.solve);

    // Restitution once per step on the final velocities (threshold and
    // "received impulse" rule in the solver), then keep the impulses; joint
    // impulses for warm starting, reaction forces, breaking.
    if (hasContacts) {
        contactSolver.pushOutGrown(*this, contactManager, jointSolver.constraints());
        contactSolver.applyRestitution();
        contactSolver.store(contactManager);
    }
    // The hit events are built when read (world_impl.hpp); marked here, not at
    // the end, so that a broken joint's dropped pairs (below) build them first.
    hitEventsStale = true;
    lastStepDt = dt;  // the contact report's forces are the stored impulses / dt
    if (hasJoints) {
        jointSolver.store(*this, joints.slots());
        resetPairsOfBrokenJoints();
    }
    FULCRUM_VALIDATE_PHASE(*this, AfterStore);
    clock.lap(prof.store);

    // Time of impact, on the awake set; it moves fast bodies back alone:
    // close the joints it opened. Then the records, once.
    if (settings.continuousCollision) {
        detail::solveContinuous(*this, jointPairFilter(), contactManager, tasks, dt);
        if (hasJoints) jointSolver.projectPositions(*this);
    }
    tasks.parallelFor(static_cast<std::uint32_t>(awakeBodies.size()), kBodiesPerRange,
                      [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) { writeRecords(begin, end); });
    FULCRUM_VALIDATE_PHASE(*this, AfterContinuous);
    clock.lap(prof.continuous);

    // Particle systems after the rigid bodies, before sleeping (why: world/particle_coupling.hpp).
    detail::stepParticles(*this, dt);
    clock.lap(prof.particles);
    sleepManager.update(*this,
                        {settings.sleeping, settings.linearSleepVelocity, settings.angularSleepVelocity, settings.timeToSleep},
                        contactSolver.pairs(), contactManager, joints.slots(), tasks, dt);
    FULCRUM_VALIDATE_PHASE(*this, AfterSleep);
    clock.lap(prof.sleep);
    // Built when read (World::contacts(), snapshots): world_impl.hpp.
    contactReportStale = true;

    const std::uint32_t firstBad = finishStep(tasks);
    clock.lap(prof.finish);
    clock.finish(prof.total);
    profile = prof;
    stepOnCaller = false;  // the contact report, built when read, may use the pool again
    ++stepCount;
    time = t0 + static_cast<double>(dt);
    FULCRUM_VALIDATE_PHASE(*this, StepEnd);
    if (firstBad != kNoIndexBody) throwNonFinite(firstBad);
}

// previous[] = the transform at the start of the step: the awake bodies,
// plus the few that stopped moving since the last step (sleeping, static
// and teleported bodies keep previous[] equal to their transform). The
// awake bodies' entries are written by the contact manager's proxy update,
// which forms the same transforms for their tight boxes next
// (ContactManager::update, step 1): one pass over their records, not two
// (a separate pass here was 1.3 % of Jolt's HighSpeed step's instructions
// and 3.5 % of its first-level read misses). So nothing may read previous[]
// between here and that update.
void WorldImpl::refreshPrevious(TaskSystem& tasks) {
    if (previousAllStale) {
        const auto all = static_cast<std::uint32_t>(motion.size());
        tasks.parallelFor(all, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
            for (std::uint32_t i = begin; i < end; ++i) previous[i] = originTransform(i);
        });
        previousAllStale = false;
    } else {
        for (const std::uint32_t i : previousStale) previous[i] = originTransform(i);
    }
    previousStale.clear();
}

bool WorldImpl::prepareSolvers(TaskSystem& tasks, Real h) {
    // From here to the records stage the awake set is the awake bodies' only home.
    beginStep([&](std::size_t count, auto&& fill) {
        tasks.parallelFor(static_cast<std::uint32_t>(count), kBodiesPerRange,
                          [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) { fill(begin, end); });
    });
    // The solver splits its prepare's loops across the same task system
    // (bit-identical for any thread count: tests/solver/simd_solver_test.cpp).
    contactSolver.setTaskSystem(&tasks);
    contactSolver.setPushOut(settings.pushOutGrownOverlaps);  // read by the prepare and pushOutGrown
    contactSolver.prepareConstraintList(
        *this, contactManager,
        {settings.contactHertz, settings.contactDampingRatio, settings.contactPushMaxVelocity, settings.restitutionThreshold},
        h);
    // The greedy colouring is serial (each constraint's colour depends on the
    // ones before it); it runs at index 0 of the first sub-step's force
    // evaluation, which needs nothing from the solver, while the other ranges
    // evaluate forces: the same bits, and ~40 us less serial time per step of
    // box_pile's collapse (the colouring was 16.6 M of the 59 M serial
    // instructions left over its first 120 steps).
    // Each body's MotionKind for the sub-steps is decided beside its first
    // force evaluation (it reads the torque just evaluated).
    std::atomic<bool> callbacks{false}, dragged{false};
    const auto bodyCount = static_cast<std::uint32_t>(awakeBodies.size());
    motionKindsKept = detail::motionKindsPerStepEnabled();
    tasks.parallelFor(bodyCount + 1, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        if (begin == 0) {
            contactSolver.colourGreedy();
            ++begin;
        }
        if (begin == end) return;
        bool drag = false;
        if (detail::evaluateBodyForces(*this, settings.gravity, begin - 1, end - 1, &drag)) {
            callbacks.store(true, std::memory_order_relaxed);
        }
        if (drag) dragged.store(true, std::memory_order_relaxed);
        if (motionKindsKept) detail::classifyMotion(*this, begin - 1, end - 1);
    });
    anyDrag = dragged.load(std::memory_order_relaxed);
    // ForceCallbacks (not required to be thread-safe) in body order, then the springs.
    const bool anyCallback = callbacks.load(std::memory_order_relaxed);
    if (anyCallback) detail::addCallbackForces(*this, time);
    detail::addSpringForces(*this, springs.slots());
    contactSolver.finishPrepare(contactManager);
    // Joints work on the same awake set, in the same passes, before the
    // contacts (Box2D v3's order; docs/joints.md has the measurements).
    jointSolver.prepare(*this, joints.slots(),
                        {settings.jointHertz, settings.jointDampingRatio, settings.jointProjectionSlop, settings.jointDirectSolve},
                        tasks, h);
    return anyCallback;
}

// The sub-steps as one list of stages (the design comment at the top). Whether
// a body has a ForceCallback, and the springs, do not change during a step,
// so the list is fixed once prepared.
void WorldImpl::buildSubSteps(TaskSystem& tasks, bool anyCallback) {
    using Pass = detail::ContactSolver::Pass;
    const bool verlet = settings.integrator == Integrator::Verlet;
    const bool hasContacts = contactSolver.constraintCount() > 0;
    const bool hasJoints = jointSolver.constraintCount() > 0;
    const auto bodies = static_cast<std::uint32_t>(awakeBodies.size());
    const int substeps = settings.substeps, iterations = settings.solverIterations;
    // The list is a function of these and of the contact solver's pass stages
    // only: kept while none changed (a small world's list is the same step
    // after step).
    SubStepKey key;
    key.bodies = bodies;
    key.workers = tasks.workerCount();
    key.projectionGroups = hasJoints ? jointSolver.projectionGroupCount() : 0;
    key.substeps = substeps;
    key.iterations = iterations;
    key.integrator = settings.integrator;
    key.callbacks = anyCallback;
    key.springs = !springs.empty();
    key.drag = anyDrag;
    key.forcesOnce = detail::forcesOncePerStepEnabled();
    key.motionKinds = motionKindsKept;
    key.contacts = hasContacts;
    key.joints = hasJoints;
    key.built = true;
    const bool contactStagesChanged = hasContacts && contactSolver.takePassStagesChanged();
    if (!contactStagesChanged && key == subStepKey) return;
    subStepKey = key;
    // Room for the most stages any step can have, so a step with more colours
    // than before allocates nothing.
    const auto passes = static_cast<std::size_t>(2 + iterations);
    subSteps.reserve(static_cast<std::size_t>(substeps) * (10 + passes * (1 + detail::ContactSolver::maxPassStages())),
                     tasks.workerCount());
    subSteps.clear();
    // Stage 1 (forces at callbackTime(timeArg)) and, with withVelocities, stage 2.
    const auto addForces = [&](std::uint32_t timeArg, bool withVelocities) {
        if (withVelocities && !anyCallback && springs.empty()) {
            subSteps.add(kForcesVelocities, 0, 0, bodies, kBodiesPerRange);
            return;
        }
        subSteps.add(kForces, 0, 0, bodies, kBodiesPerRange);
        // ForceCallbacks are user code: on the calling thread, as every step calls them.
        if (anyCallback) subSteps.addOnCaller(kCallbacks, timeArg);
        if (!springs.empty()) subSteps.add(kSprings, 0, 0, 1, 1);
        if (withVelocities) subSteps.add(kVelocities, 0, 0, bodies, kBodiesPerRange);
    };
    // Without drag, callbacks and springs every later sub-step's forces
    // are the first's (gravity and the user's forces, fixed for the step:
    // the same values evaluated again, ~45 instructions a body and
    // sub-step), so they stay as prepareSolvers left them; so do the
    // torques, and a body's velocity stage then follows its MotionKind
    // (integrateVelocities).
    const bool forcesKept = key.forcesOnce && !anyDrag && !anyCallback && springs.empty();
    const bool plainVelocities = forcesKept && motionKindsKept;
    const auto solverPass = [&](Pass pass) {
        if (hasJoints) subSteps.addOnCaller(kJointPass, static_cast<std::uint32_t>(pass));
        if (hasContacts) contactSolver.addPassStages(subSteps, kContactPass, pass);
    };
    for (int s = 0; s < substeps; ++s) {
        const auto sub = static_cast<std::uint32_t>(s);
        // Stages 1 and 2. The first sub-step's forces were evaluated beside the
        // colouring (prepareSolvers); Verlet's later ones by stage 5 ("first
        // same as last"): the same state and time. Without drag, callbacks
        // and springs the later sub-steps keep the first's (forcesKept).
        if (s == 0 || verlet || forcesKept) {
            subSteps.add(kVelocities, plainVelocities ? 1 : 0, 0, bodies, kBodiesPerRange);
        } else {
            addForces(2 * sub, true);
        }
        // Stage 3: warm start and solve with soft position bias.
        solverPass(Pass::WarmStart);
        for (int it = 0; it < iterations; ++it) solverPass(Pass::Solve);
        // Stage 4, the joints' projection, and the relax pass.
        // The pose change since the step's start (dp, dtheta) for the relax
        // pass and the store: with the position stage, body by body; with
        // joints after their projection, which moves bodies again.
        subSteps.add(kPositions, (hasContacts && !hasJoints ? kPositionsDeltas : 0) | (motionKindsKept ? kPositionsKinds : 0),
                     0, bodies, kBodiesPerRange);
        if (hasJoints) {
            subSteps.add(kProjectionCheck, 0, 0, jointSolver.projectionGroupCount(), kProjectionGroupsPerRange);
            subSteps.add(kProjection, 0, 0, 1, 1);
            subSteps.add(kDeltas, 0, 0, bodies, kBodiesPerRange);
        }
        solverPass(Pass::Relax);
        // Stage 5
        if (verlet) {
            subSteps.add(kVerletPredict, 0, 0, bodies, kBodiesPerRange);
            addForces(2 * sub + 1, false);
            subSteps.add(kVerletKick, 0, 0, bodies, kBodiesPerRange);
        }
    }
}

void WorldImpl::runSubSteps(TaskSystem& tasks, double t0, Real h, double hd) {
    using Pass = detail::ContactSolver::Pass;
    const Integrator method = settings.integrator;
    const Real maxTurn = settings.maxRotationPerSubstep;
    const Vec3 gravity = settings.gravity;
    const auto exec = [&](const detail::Stage& stage, std::uint32_t begin, std::uint32_t end) {
        switch (stage.kind) {
            case kForces: detail::evaluateBodyForces(*this, gravity, begin, end); break;
            case kCallbacks: detail::addCallbackForces(*this, callbackTime(t0, hd, stage.arg)); break;
            case kSprings: detail::addSpringForces(*this, springs.slots()); break;
            case kVelocities: detail::integrateVelocities(*this, method, h, stage.arg != 0, begin, end); break;
            case kForcesVelocities:
                for (std::uint32_t b = begin; b < end; b += kFusedBlock) {
                    const std::uint32_t e = std::min(end, b + kFusedBlock);
                    detail::evaluateBodyForces(*this, gravity, b, e);
                    detail::integrateVelocities(*this, method, h, false, b, e);
                }
                break;
            case kJointPass:
                if (stage.arg == static_cast<std::uint32_t>(Pass::WarmStart)) {
                    jointSolver.warmStart();
                } else {
                    jointSolver.solve(stage.arg == static_cast<std::uint32_t>(Pass::Solve));
                }
                break;
            case kContactPass: contactSolver.runPassStage(stage.arg, begin, end); break;
            case kPositions:
                detail::integratePositions(*this, method, h, maxTurn, (stage.arg & kPositionsDeltas) != 0,
                                           (stage.arg & kPositionsKinds) != 0, begin, end);
                break;
            case kProjectionCheck: jointSolver.checkProjection(*this, begin, end); break;
            case kProjection: jointSolver.projectCheckedPositions(*this); break;
            case kDeltas: updateDeltas(begin, end); break;
            case kVerletPredict: detail::verletPredict(*this, h, begin, end); break;
            default: detail::verletKick(*this, h, begin, end); break;
        }
    };
    subSteps.run(tasks, exec, detail::stagedSubStepsEnabled());
}

// A broken joint's bodies may collide again: their pairs are looked at anew
// (after the contact report of the contacts it drops was built).
void WorldImpl::resetPairsOfBrokenJoints() {
    for (const JointBreakEvent& e : jointSolver.breakEvents()) {
        const detail::JointData& data = joints[e.joint.index];
        if (data.def.bodyA.isNull() || data.def.collideConnected) continue;
        ensureContactReport();
        contactManager.resetPairs(*this, data.def.bodyA.index);
    }
}

// Clears the user forces and looks for a non-finite state, per body range in
// parallel; the lowest bad index is an order-independent merge (an atomic min).
// Only the bodies that moved: the awake list of the integration (the sleep
// manager's removals wait for the next refresh) and the bodies woken since
// (a particle impulse). A user force wakes its body, so no sleeping body
// holds one.
std::uint32_t WorldImpl::finishStep(TaskSystem& tasks) {
    std::atomic<std::uint32_t> firstBad{kNoIndexBody};
    const auto checkBody = [&](std::uint32_t i, std::uint32_t& bad) {
        applied[i] = {};
        if (*firstNonFinite(motion[i]) != '\0') bad = std::min(bad, i);
    };
    tasks.parallelFor(static_cast<std::uint32_t>(awakeBodies.size()), kBodiesPerRange,
                      [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
                          std::uint32_t bad = kNoIndexBody;
                          for (std::uint32_t k = begin; k < end; ++k) checkBody(awakeBodies[k], bad);
                          std::uint32_t seen = firstBad.load(std::memory_order_relaxed);
                          while (bad < seen && !firstBad.compare_exchange_weak(seen, bad, std::memory_order_relaxed)) {
                          }
                      });
    std::uint32_t bad = firstBad.load(std::memory_order_relaxed);
    for (const std::uint32_t i : wokenBodies) {
        if (params[i].type != BodyType::Static) checkBody(i, bad);
    }
    return bad;
}

// Contacts spread a NaN to the bodies touching it, so name a body whose
// forces went non-finite first: that is where the NaN came from.
void WorldImpl::throwNonFinite(std::uint32_t firstBad) const {
    std::uint32_t culprit = kNoIndexBody;
    for (std::uint32_t i = 0; i < motion.size() && culprit == kNoIndexBody; ++i) {
        if (params[i].type == BodyType::Static) continue;
        if (!isFinite(forces[i].force) || !isFinite(forces[i].torque)) culprit = i;
    }
    for (std::uint32_t k = 0; k < motion.size(); ++k) {
        const std::uint32_t i = culprit == kNoIndexBody ? k : (k == 0 ? culprit : (k <= culprit ? k - 1 : k));
        if (params[i].type == BodyType::Static) continue;
        const char* bad = firstNonFinite(motion[i]);
        if (*bad != '\0') {
            throw NumericalError(describeBody(i) + " (index " + std::to_string(denseToSlot[i]) + "): " + bad +
                                 " became NaN/inf at step " + std::to_string(stepCount) + " (t = " +
                                 detail::formatReal(time) + " s)");
        }
    }
    throw NumericalError(describeBody(firstBad) + ": state became NaN/inf at step " + std::to_string(stepCount));
}


}  // namespace fulcrum
