#pragma once
// The three integrators, written as the stages of a sub-step (see the design
// comment at the top of src/world/step.cpp for how the stages fit together and
// where the constraint solver goes).
#include "fulcrum/world.hpp"
#include "world/world_impl.hpp"

namespace fulcrum::detail {

// Stage 2: turn the evaluated forces (w.forces) into velocities, apply damping.
//   explicit Euler:       v += a h, w += I^-1 (tau - w x I w) h   (gyroscopic term explicit);
//                         remembers the change so positions can use the old velocity.
//   semi-implicit Euler:  v += a h, w += I^-1 tau h (the gyroscopic effect comes from the drift).
//   Verlet:               first half kick v += a h/2, w += I^-1 tau h/2.
// Damping v *= 1 / (1 + h c) for every integrator.
// The range [begin, end) of w.awakeBodies only (sleeping and static bodies
// never move): bodies are independent, so the step runs disjoint ranges on
// several threads (src/world/step.cpp).
void integrateVelocities(WorldImpl& w, Integrator method, Real h, std::size_t begin, std::size_t end);
inline void integrateVelocities(WorldImpl& w, Integrator method, Real h) {
    integrateVelocities(w, method, h, 0, w.awakeBodies.size());
}

// Stage 4: advance positions and orientations from the (possibly solver-corrected) velocities.
//   explicit Euler:       x += v_old h, q rotated by w_old.
//   semi-implicit Euler:  x += v h; q turns at constant angular momentum (as Verlet).
//   Verlet:               drift x += v_half h; q turns at constant angular momentum.
// Kinematic bodies move at their velocity whatever the integrator.
// Refreshes every moved body's world inverse inertia.
void integratePositions(WorldImpl& w, Integrator method, Real h, std::size_t begin, std::size_t end);
inline void integratePositions(WorldImpl& w, Integrator method, Real h) {
    integratePositions(w, method, h, 0, w.awakeBodies.size());
}

// Stage 5: Verlet's second half kick (evaluates forces at the new positions at
// `timeAfter`); nothing for the Euler methods.
void finalizeSubstep(WorldImpl& w, Integrator method, Real h, double timeAfter);

// World inertia tensor R I_body R^T (not inverted).
inline Mat3 worldInertia(const Quat& q, const Mat3& inertiaBody) {
    const Mat3 r = toMat3(q);
    return r * inertiaBody * transpose(r);
}

}  // namespace fulcrum::detail
