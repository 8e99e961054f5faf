// The step pipeline.
//
// Design
// ------
// A step of `dt` runs `substeps` sub-steps of h = dt / substeps. Each sub-step
// is a fixed sequence of stages over the dense body arrays:
//
//   1. compute forces        gravity, drag, springs, user forces, callbacks -> w.forces
//   2. integrate velocities  v, w from the forces (+ damping)
//   3. [solve]               contacts and joints: velocity constraints with soft
//                            position bias (Box2D v3 soft step)      <- solver goes here
//   4. integrate positions   x, q from the velocities
//   5. finalize              Verlet's second kick; [relax: the solver's bias-free pass]
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

}  // namespace

void WorldImpl::step(Real dt) {
    const Integrator method = settings.integrator;
    const int substeps = settings.substeps;
    const Real h = dt / static_cast<Real>(substeps);
    const double hd = static_cast<double>(dt) / substeps;

    for (std::size_t i = 0; i < motion.size(); ++i) previous[i] = originTransform(static_cast<std::uint32_t>(i));

    const double t0 = time;
    for (int s = 0; s < substeps; ++s) {
        const double tStart = t0 + hd * s;
        // Stage 1 (skipped for Verlet after the first sub-step: stage 5 left the
        // forces at exactly this state and time).
        if (method != Integrator::Verlet || s == 0) detail::evaluateForces(*this, tStart);
        // Stage 2
        detail::integrateVelocities(*this, method, h);
        // Stage 3: the constraint solver (contacts, joints) will run here.
        // Stage 4
        detail::integratePositions(*this, method, h);
        // Stage 5
        detail::finalizeSubstep(*this, method, h, tStart + hd);
    }

    for (detail::ForceTorque& a : applied) a = {};
    ++stepCount;
    time = t0 + static_cast<double>(dt);

    for (std::uint32_t i = 0; i < motion.size(); ++i) {
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
