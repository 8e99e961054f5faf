// The step pipeline.
//
// Design
// ------
// A step of `dt` runs `substeps` sub-steps of h = dt / substeps. Each sub-step
// is a fixed sequence of stages over the dense body arrays:
//
//   1. compute forces        gravity, drag, springs, user forces, callbacks -> w.forces
//   2. integrate velocities  v, w from the forces (+ damping)
//   3. solve                 contacts: warm start, then velocity constraints with
//                            soft position bias (Box2D v3 soft step, src/solver)
//   4. integrate positions   x, q from the velocities
//   4b. relax                the solver's bias-free pass on the step's anchors
//   5. finalize              Verlet's second kick
//
// Around the sub-steps: before them the collision pipeline (broad phase, contacts,
// narrow phase, events) and the solver's prepare (constraints on the step's start
// configuration, graph colouring); after them restitution, impulse storage,
// continuous collision (time of impact), islands and sleeping; the contact
// report is only marked stale (built when read: world_impl.hpp).
//
// Every per-body stage walks the awake list (WorldImpl::awakeBodies, ascending
// dense indices of the awake non-static bodies), so sleeping and static bodies
// cost nothing per step (docs/solver.md, "Sleeping").
//
// This is the shape of Box2D v3's soft step (integrate velocities, warm start
// and solve, integrate positions, relax), so the constraint solver slots in
// between stages 2 and 4 without touching the integrators: every integrator
// leaves in w.motion the velocity that positions will use, and position
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
// After the sub-steps: user forces are cleared, time advances, and every moving
// body's state is checked for NaN/inf (NumericalError names the body).
//
// Threads (docs/threading.md): the per-body and per-pair loops run as
// parallelFor calls on taskSystem(): the broad phase's tree queries, the
// narrow phase per contact with the tree re-insertions beside it
// (ContactManager::update), the contact report (ContactManager::report, when
// read), the contact solver's per-body, per-constraint and per-colour loops
// (ContactSolver), the islands' per-index parts (SleepManager), and here the
// start transforms, force evaluation (all but ForceCallbacks), the velocity and
// position integration per body and the end-of-step NaN check.
// Every range writes only the slots of the indices it covers and anything
// order-dependent (contact creation, events, wakes, tree updates) is applied
// afterwards on this thread in index order, so results are bit-identical for
// every thread count and scheduler (tests/threads/step_determinism_test.cpp).
// No heap allocation happens here in steady state: every scratch array is
// sized at body creation, per-worker buffers on the first step with a given
// worker count.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include "dynamics/forces.hpp"
#include "dynamics/integrators.hpp"
#include "dynamics/validation.hpp"
#include "contacts/continuous.hpp"
#include "threads/staged_parallel.hpp"
#include "world/invariants.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

namespace {

// Which part of a body's state is not finite ("" when all is).
const char* firstNonFinite(const detail::BodyMotion& m) {
    if (!isFinite(m.com)) return "position";
    if (!isFinite(m.q)) return "orientation";
    if (!isFinite(m.v)) return "linear velocity";
    if (!isFinite(m.w)) return "angular velocity";
    return "";
}

constexpr std::uint32_t kNoIndexBody = UINT32_MAX;

// World::lastStepProfile's clock: lap() is the milliseconds since the last lap.
class PhaseClock {
public:
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
        last_ = now;
        return ms;
    }
    double since(std::chrono::steady_clock::time_point start) const {
        return std::chrono::duration<double, std::milli>(last_ - start).count();
    }
    std::chrono::steady_clock::time_point last() const { return last_; }

private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

// Bodies per range of the per-body loops: integrating one costs ~20-60 ns, so
// 64 of them (1-4 us) amortise a range's scheduling (~0.1-0.2 us on the
// pool). Was 256: box_pile's ~950 still-awake bodies (steps 160-250) then
// made 3 ranges, and 2 threads were no faster than one there.
constexpr std::uint32_t kBodiesPerRange = 64;

// FULCRUM_STAGED=0 turns the staged sub-steps off (staged_parallel.hpp).
std::atomic<bool> gStagedSubSteps{[] {
    const char* value = std::getenv("FULCRUM_STAGED");
    return value == nullptr || value[0] != '0';
}()};

}  // namespace

namespace detail {
bool stagedSubStepsEnabled() { return gStagedSubSteps.load(std::memory_order_relaxed); }
void setStagedSubStepsEnabled(bool enabled) { gStagedSubSteps.store(enabled, std::memory_order_relaxed); }
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

void WorldImpl::step(Real dt) {
    PhaseClock clock;
    const auto stepStart = clock.last();
    StepProfile prof;
    const Integrator method = settings.integrator;
    const int substeps = settings.substeps;
    const Real h = dt / static_cast<Real>(substeps);
    const double hd = static_cast<double>(dt) / substeps;
    FULCRUM_VALIDATE_PHASE(*this, StepStart);

    // Turning sleeping off wakes everything once.
    if (!settings.sleeping && wasSleeping) {
        for (std::uint32_t i = 0; i < motion.size(); ++i) wakeBody(i);
    }
    wasSleeping = settings.sleeping;

    // The per-body stages walk the awake list only (world_impl.hpp): a body
    // that sleeps or is static costs nothing per step.
    refreshAwakeList();
    // A small step runs on this thread alone (WorldDef::parallelMinBodies):
    // decided once, here, for the whole step.
    stepOnCaller = awakeBodies.size() < settings.parallelMinBodies;
    TaskSystem& tasks = taskSystem();
    // previous[] = the transform at the start of the step: the awake bodies,
    // plus the few that stopped moving since the last step (sleeping, static
    // and teleported bodies keep previous[] equal to their transform).
    if (previousAllStale) {
        const auto all = static_cast<std::uint32_t>(motion.size());
        tasks.parallelFor(all, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
            for (std::uint32_t i = begin; i < end; ++i) previous[i] = originTransform(i);
        });
        previousAllStale = false;
    } else {
        for (const std::uint32_t i : previousStale) previous[i] = originTransform(i);
        const auto awakeCount = static_cast<std::uint32_t>(awakeBodies.size());
        tasks.parallelFor(awakeCount, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
            for (std::uint32_t k = begin; k < end; ++k) previous[awakeBodies[k]] = originTransform(awakeBodies[k]);
        });
    }
    previousStale.clear();

    // Collision: broad phase, contacts, narrow phase (wakes what awake bodies touch).
    contactManager.update(*this, dt);
    prof.collide = clock.lap();
    notePairLimit(prof);
    // The bodies it woke move in this step.
    refreshAwakeList();
    FULCRUM_VALIDATE_PHASE(*this, AfterCollide);
    const auto bodyCount = static_cast<std::uint32_t>(awakeBodies.size());
    // Constraints are prepared once per step on the step's start configuration.
    detail::ContactSolver& solver = contactSolver;
    // The solver splits each large graph colour across the same task system
    // (bit-identical for any thread count: tests/solver/simd_solver_test.cpp).
    solver.setTaskSystem(&tasks);
    solver.prepareConstraintList(*this, contactManager, dt, h);
    // The greedy colouring is serial (each constraint's colour depends on the
    // ones before it); it runs at index 0 of the first sub-step's force
    // evaluation, which needs nothing from the solver, while the other ranges
    // evaluate forces: the same bits, and ~40 us less serial time per step of
    // box_pile's collapse (the colouring was 16.6 M of the 59 M serial
    // instructions left over its first 120 steps).
    bool anyCallback = false;
    {
        std::atomic<bool> callbacks{false};
        tasks.parallelFor(bodyCount + 1, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
            if (begin == 0) {
                solver.colourGreedy();
                ++begin;
            }
            if (begin < end && detail::evaluateBodyForces(*this, begin - 1, end - 1)) {
                callbacks.store(true, std::memory_order_relaxed);
            }
        });
        anyCallback = callbacks.load(std::memory_order_relaxed);
        if (anyCallback) detail::addCallbackForces(*this, time);
        detail::addSpringForces(*this);
    }
    solver.finishPrepare(*this, contactManager);
    // Joints work on the contact solver's bodies, in the same passes, before
    // the contacts (Box2D v3's order; docs/joints.md has the measurements).
    jointSolver.prepare(*this, solver, h);
    FULCRUM_VALIDATE_PHASE(*this, AfterPrepare);
    const bool hasContacts = solver.constraintCount() > 0;
    const bool hasJoints = jointSolver.constraintCount() > 0;
    const bool hasConstraints = hasContacts || hasJoints;
    const int iterations = settings.solverIterations;
    prof.prepare = clock.lap();
    prof.awakeBodies = bodyCount;
    prof.contactConstraints = static_cast<std::uint32_t>(solver.constraintCount());
    prof.jointConstraints = static_cast<std::uint32_t>(jointSolver.constraintCount());
    prof.workers = tasks.workerCount();

    // Stage 1 as evaluateForces computes it (the same bits): the per-body part
    // in parallel, then on this thread the ForceCallbacks (not required to be
    // thread-safe) in body order, if any body has one, and the springs. Force
    // evaluation was 4.5 % of box_pile's one-thread step, all serial.
    // Returns whether a body has a ForceCallback.
    const auto evaluateForcesInParallel = [&](double tEval) {
        std::atomic<bool> callbacks{false};
        tasks.parallelFor(bodyCount, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
            if (detail::evaluateBodyForces(*this, begin, end)) callbacks.store(true, std::memory_order_relaxed);
        });
        const bool any = callbacks.load(std::memory_order_relaxed);
        if (any) detail::addCallbackForces(*this, tEval);
        detail::addSpringForces(*this);
        return any;
    };

    // Fused per-body passes. Without joints (their position projection sits
    // between the position integration and the rotation deltas) and with an
    // integrator that has no stage 5 (Verlet's second kick is serial), every
    // per-body stage between two solver passes touches only its own body, so
    // one parallelFor can run them back to back, body by body:
    //   [velocity integration + gather]   before the warm start and solve,
    //   [scatter + position integration + rotation deltas + gather]   before relax,
    //   [scatter + next sub-step's forces + velocity integration + gather]
    //                                      after relax (when the forces need no
    //                                      ForceCallback or spring: serial parts).
    // Each body gets the same operations in the same order, so the bits do not
    // change; a sub-step then has 2 per-body barriers instead of 8 (box_pile:
    // 5 sub-steps, 40 of its ~65 parallelFor calls per step were these) and
    // reads each body's motion once per pass instead of once per stage.
    // Solver body k + 1 is awakeBodies[k] (ContactSolver::prepare).
    const bool fuse = !hasJoints && method != Integrator::Verlet &&
                      (!hasContacts || solver.denseOfSolverBody().size() == std::size_t{bodyCount} + 1);
    const bool gatherScatter = fuse && hasContacts;
    // Sub-ranges of a range, so a body's data stays in L1 across the fused stages.
    constexpr std::uint32_t kFusedBlock = 32;
    const auto fusedPass = [&](auto&& perBlock) {
        tasks.parallelFor(bodyCount, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
            for (std::uint32_t b = begin; b < end; b += kFusedBlock) perBlock(b, std::min(end, b + kFusedBlock));
        });
    };
    bool forcesAndVelocitiesDone = false;  // by the previous sub-step's last fused pass

    // Staged sub-steps. When every stage of every sub-step is per body or per
    // solver colour (the fused case with contacts, no ForceCallback, no spring)
    // and there are several workers, the whole sub-step loop runs inside ONE
    // parallelFor (StagedParallel, threads/staged_parallel.hpp; Box2D v3's solver
    // stages): the same stages in the same order as the loop below, each
    // stage's units independent, so the same bits; but one fork-join per step
    // instead of ~8 per sub-step (box_pile: 40 of them), no end-of-call wait
    // between stages beyond the stage's own, and each participant keeps the
    // same bodies and colour blocks from stage to stage (docs/threading.md,
    // "Staged sub-steps").
    const double t0 = time;
    const bool staged = gatherScatter && !anyCallback && springs.empty() && tasks.workerCount() > 1 &&
                        detail::stagedSubStepsEnabled();
    if (staged) {
        enum : std::uint32_t { kVelocities, kSolverPass, kPositions, kForcesVelocities, kScatter };
        using Pass = detail::ContactSolver::Pass;
        detail::StagedParallel& stages = solver.subStepStages();
        // Room for the most stages any step can have, so a step with more
        // colours than before allocates nothing.
        const auto passes = static_cast<std::size_t>(2 + iterations);
        stages.reserve(static_cast<std::size_t>(substeps) * (3 + passes * detail::ContactSolver::maxPassStages()),
                       tasks.workerCount());
        stages.clear();
        for (int s = 0; s < substeps; ++s) {
            if (s == 0) stages.add(kVelocities, 0, 0, bodyCount, kBodiesPerRange);
            solver.addPassStages(stages, kSolverPass, Pass::WarmStart);
            for (int it = 0; it < iterations; ++it) solver.addPassStages(stages, kSolverPass, Pass::Solve);
            stages.add(kPositions, 0, 0, bodyCount, kBodiesPerRange);
            solver.addPassStages(stages, kSolverPass, Pass::Relax);
            stages.add(s + 1 < substeps ? kForcesVelocities : kScatter, 0, 0, bodyCount, kBodiesPerRange);
        }
        stages.run(tasks, [&](const detail::Stage& stage, std::uint32_t begin, std::uint32_t end) {
            if (stage.kind == kSolverPass) {
                solver.runPassStage(stage.arg, begin, end);
                return;
            }
            for (std::uint32_t b = begin; b < end; b += kFusedBlock) {
                const std::uint32_t e = std::min(end, b + kFusedBlock);
                switch (stage.kind) {
                    case kVelocities:
                        detail::integrateVelocities(*this, method, h, b, e);
                        solver.gatherVelocities(*this, b, e);
                        break;
                    case kPositions:
                        solver.scatterVelocities(*this, b, e);
                        detail::integratePositions(*this, method, h, b, e);
                        solver.updateDeltas(*this, b, e);
                        solver.gatherVelocities(*this, b, e);
                        break;
                    case kForcesVelocities:
                        solver.scatterVelocities(*this, b, e);
                        detail::evaluateBodyForces(*this, b, e);
                        detail::integrateVelocities(*this, method, h, b, e);
                        solver.gatherVelocities(*this, b, e);
                        break;
                    default:  // kScatter
                        solver.scatterVelocities(*this, b, e);
                        break;
                }
            }
        });
    }
    for (int s = 0; s < substeps && !staged; ++s) {
        const double tStart = t0 + hd * s;
        if (!forcesAndVelocitiesDone) {
            // Stage 1 (skipped for Verlet after the first sub-step: stage 5 left the
            // forces at exactly this state and time; the first sub-step's beside the colouring).
            if (method != Integrator::Verlet && s > 0) anyCallback = evaluateForcesInParallel(tStart);
            // Stage 2
            if (fuse) {
                fusedPass([&](std::uint32_t b, std::uint32_t e) {
                    detail::integrateVelocities(*this, method, h, b, e);
                    if (gatherScatter) solver.gatherVelocities(*this, b, e);
                });
            } else {
                tasks.parallelFor(bodyCount, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
                    detail::integrateVelocities(*this, method, h, begin, end);
                });
            }
        }
        forcesAndVelocitiesDone = false;
        // Stage 3: warm start and solve with soft position bias.
        if (hasConstraints) {
            if (!gatherScatter) solver.gatherVelocities(*this);
            jointSolver.warmStart();
            solver.warmStart();
            for (int it = 0; it < iterations; ++it) {
                jointSolver.solve(true);
                solver.solve(true);
            }
            if (!gatherScatter) solver.scatterVelocities(*this);
        }
        // Stage 4
        if (fuse) {
            fusedPass([&](std::uint32_t b, std::uint32_t e) {
                if (gatherScatter) solver.scatterVelocities(*this, b, e);
                detail::integratePositions(*this, method, h, b, e);
                if (gatherScatter) {
                    solver.updateDeltas(*this, b, e);
                    solver.gatherVelocities(*this, b, e);
                }
            });
        } else {
            tasks.parallelFor(bodyCount, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
                detail::integratePositions(*this, method, h, begin, end);
            });
        }
        // Joints: put the anchors back together at the position level.
        if (hasJoints) jointSolver.projectPositions(*this);
        // Relax: the bias-free pass removes the velocity the soft push added.
        if (hasConstraints) {
            if (!gatherScatter) {
                solver.updateDeltas(*this);
                solver.gatherVelocities(*this);
            }
            jointSolver.solve(false);
            solver.solve(false);
            if (gatherScatter && s + 1 < substeps && !anyCallback && springs.empty()) {
                // This scatter, and the next sub-step's stages 1 and 2 (no
                // callback or spring: the forces are per body alone).
                fusedPass([&](std::uint32_t b, std::uint32_t e) {
                    solver.scatterVelocities(*this, b, e);
                    detail::evaluateBodyForces(*this, b, e);
                    detail::integrateVelocities(*this, method, h, b, e);
                    solver.gatherVelocities(*this, b, e);
                });
                forcesAndVelocitiesDone = true;
            } else {
                solver.scatterVelocities(*this);
            }
        }
        // Stage 5
        detail::finalizeSubstep(*this, method, h, tStart + hd);
    }

    FULCRUM_VALIDATE_PHASE(*this, AfterSubsteps);
    prof.solve = clock.lap();
    if (hasContacts) {
        // Restitution once per step on the final velocities (threshold and
        // "received impulse" rule in the solver), then keep the impulses.
        solver.gatherVelocities(*this);
        solver.applyRestitution();
        solver.scatterVelocities(*this);
        solver.store(*this, contactManager);
    }
    // Joint impulses for warm starting, reaction forces, breaking.
    if (hasJoints) jointSolver.store(*this);
    FULCRUM_VALIDATE_PHASE(*this, AfterStore);
    prof.store = clock.lap();
    if (settings.continuousCollision) {
        detail::solveContinuous(*this, solver, contactManager, dt);
        // Time of impact moves fast bodies back alone: close the joints it opened.
        if (hasJoints) jointSolver.projectPositions(*this);
    }
    FULCRUM_VALIDATE_PHASE(*this, AfterContinuous);
    // Particle systems after the rigid bodies, before sleeping (why: world/particle_coupling.hpp).
    prof.continuous = clock.lap();
    detail::stepParticles(*this, dt);
    prof.particles = clock.lap();
    sleepManager.update(*this, solver, contactManager, dt);
    FULCRUM_VALIDATE_PHASE(*this, AfterSleep);
    prof.sleep = clock.lap();
    // Built when read (World::contacts(), snapshots): world_impl.hpp.
    contactReportStale = true;

    // Clear the user forces and look for a non-finite state, per body range in
    // parallel; the lowest bad index is an order-independent merge (an atomic min).
    // Only the bodies that moved: the awake list of the integration (the sleep
    // manager's removals wait for the next refresh) and the bodies woken since
    // (a particle impulse). A user force wakes its body, so no sleeping body
    // holds one.
    std::atomic<std::uint32_t> firstBad{kNoIndexBody};
    const auto checkBody = [&](std::uint32_t i, std::uint32_t& bad) {
        applied[i] = {};
        if (*firstNonFinite(motion[i]) != '\0') bad = std::min(bad, i);
    };
    tasks.parallelFor(bodyCount, kBodiesPerRange, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        std::uint32_t bad = kNoIndexBody;
        for (std::uint32_t k = begin; k < end; ++k) checkBody(awakeBodies[k], bad);
        std::uint32_t seen = firstBad.load(std::memory_order_relaxed);
        while (bad < seen && !firstBad.compare_exchange_weak(seen, bad, std::memory_order_relaxed)) {
        }
    });
    {
        std::uint32_t bad = firstBad.load(std::memory_order_relaxed);
        for (const std::uint32_t i : wokenBodies) {
            if (params[i].type != BodyType::Static) checkBody(i, bad);
        }
        firstBad.store(bad, std::memory_order_relaxed);
    }
    prof.finish = clock.lap();
    prof.total = clock.since(stepStart);
    profile = prof;
    stepOnCaller = false;  // the contact report, built when read, may use the pool again
    ++stepCount;
    time = t0 + static_cast<double>(dt);
    FULCRUM_VALIDATE_PHASE(*this, StepEnd);
    if (firstBad.load(std::memory_order_relaxed) == kNoIndexBody) return;

    // Contacts spread a NaN to the bodies touching it, so name a body whose
    // forces went non-finite first: that is where the NaN came from.
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
}

}  // namespace fulcrum
