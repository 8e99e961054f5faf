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
// continuous collision (time of impact), islands and sleeping, contact reports.
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
// Threads: the step is single-threaded for now; WorldDef::threads is stored
// and validated so scenes and tools can already set it. No heap allocation
// happens here: every scratch array is sized at body creation.
#include <cmath>

#include "dynamics/forces.hpp"
#include "dynamics/integrators.hpp"
#include "dynamics/validation.hpp"
#include "solver/continuous.hpp"
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

}  // namespace

void WorldImpl::step(Real dt) {
    const Integrator method = settings.integrator;
    const int substeps = settings.substeps;
    const Real h = dt / static_cast<Real>(substeps);
    const double hd = static_cast<double>(dt) / substeps;

    for (std::size_t i = 0; i < motion.size(); ++i) previous[i] = originTransform(static_cast<std::uint32_t>(i));

    // Turning sleeping off wakes everything once.
    if (!settings.sleeping && wasSleeping) {
        for (std::uint32_t i = 0; i < motion.size(); ++i) wakeBody(i);
    }
    wasSleeping = settings.sleeping;

    // Collision: broad phase, contacts, narrow phase (wakes what awake bodies touch).
    contactManager.update(*this, dt);
    // Constraints are prepared once per step on the step's start configuration.
    detail::ContactSolver& solver = contactSolver;
    solver.prepare(*this, contactManager, dt, h);
    // Joints work on the contact solver's bodies, in the same passes, before
    // the contacts (Box2D v3's order; docs/joints.md has the measurements).
    jointSolver.prepare(*this, solver, h);
    const bool hasContacts = solver.constraintCount() > 0;
    const bool hasJoints = jointSolver.constraintCount() > 0;
    const bool hasConstraints = hasContacts || hasJoints;
    const int iterations = settings.solverIterations;

    const double t0 = time;
    for (int s = 0; s < substeps; ++s) {
        const double tStart = t0 + hd * s;
        // Stage 1 (skipped for Verlet after the first sub-step: stage 5 left the
        // forces at exactly this state and time).
        if (method != Integrator::Verlet || s == 0) detail::evaluateForces(*this, tStart);
        // Stage 2
        detail::integrateVelocities(*this, method, h);
        // Stage 3: warm start and solve with soft position bias.
        if (hasConstraints) {
            solver.gatherVelocities(*this);
            jointSolver.warmStart();
            solver.warmStart();
            for (int it = 0; it < iterations; ++it) {
                jointSolver.solve(true);
                solver.solve(true);
            }
            solver.scatterVelocities(*this);
        }
        // Stage 4
        detail::integratePositions(*this, method, h);
        // Joints: put the anchors back together at the position level.
        if (hasJoints) jointSolver.projectPositions(*this);
        // Relax: the bias-free pass removes the velocity the soft push added.
        if (hasConstraints) {
            solver.updateDeltas(*this);
            solver.gatherVelocities(*this);
            jointSolver.solve(false);
            solver.solve(false);
            solver.scatterVelocities(*this);
        }
        // Stage 5
        detail::finalizeSubstep(*this, method, h, tStart + hd);
    }

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
    if (settings.continuousCollision) {
        detail::solveContinuous(*this, solver, contactManager, dt);
        // Time of impact moves fast bodies back alone: close the joints it opened.
        if (hasJoints) jointSolver.projectPositions(*this);
    }
    // Particle systems after the rigid bodies, before sleeping (why: world/particle_coupling.hpp).
    detail::stepParticles(*this, dt);
    sleepManager.update(*this, solver, contactManager, dt);
    contactManager.report(*this);

    for (detail::ForceTorque& a : applied) a = {};
    ++stepCount;
    time = t0 + static_cast<double>(dt);

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
