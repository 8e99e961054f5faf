#pragma once
// The three integrators, written as the stages of a sub-step (see the design
// comment at the top of src/world/step.cpp for how the stages fit together and
// where the constraint solver goes). They work on the body store's awake set
// (body_store.hpp): awake-list entry k is solver index k + 1.
#include "fulcrum/world.hpp"
#include "dynamics/body_store.hpp"

namespace fulcrum::detail {

// What the sub-steps do with an awake body, decided once per step by
// classifyMotion (BodyStore::motionKind, per solver index) from what cannot
// change within a step: the body's type, its local inertia's symmetry, its
// damping and, after the step's first force evaluation, whether it has a
// torque. The low bits are the position stage's path; kPlainVelocity marks a
// dynamic body with no damping and no torque, whose velocity stage is
// v += a h alone while the forces are kept for the step. Re-decided every
// step, so a body the user changed between steps (a torque applied or
// ended, damping set, a body destroyed and another created in its dense
// slot) takes its new path at the next step.
enum MotionKind : std::uint8_t {
    kStill = 0,                // neither dynamic nor kinematic: not moved
    kKinematicMotion = 1,      // at its velocity
    kIsotropicMotion = 2,      // I = s identity: a rotation at constant w
    kAxisymmetricMotion = 3,   // 3, 4, 5: two equal principal moments, the symmetry axis 0, 1, 2
    kGeneralMotion = 6,        // any other inertia
    kPositionKindMask = 7,
    kPlainVelocity = 8,
};
// Awake-list entries [begin, end); run after the step's first force
// evaluation of those bodies (their torques).
void classifyMotion(BodyStore& b, std::size_t begin, std::size_t end);

// Stage 2: turn the evaluated forces (b.forces) into velocities, apply damping.
//   explicit Euler:       v += a h, w += I^-1 (tau - w x I w) h   (gyroscopic term explicit);
//                         remembers the change so positions can use the old velocity.
//   semi-implicit Euler:  v += a h, w += I^-1 tau h (the gyroscopic effect comes from the drift).
//   Verlet:               first half kick v += a h/2, w += I^-1 tau h/2.
// Damping v *= 1 / (1 + h c) for every integrator.
// The awake-list entries [begin, end) only (sleeping and static bodies never
// move): bodies are independent, so the step runs disjoint ranges on several
// threads (src/world/step.cpp).
// With `plainKept` (the semi-implicit integrator, the step's forces kept for
// all its sub-steps: no drag, ForceCallback or spring), the bodies that
// classifyMotion marked kPlainVelocity take v += a h alone.
void integrateVelocities(BodyStore& b, Integrator method, Real h, bool plainKept, std::size_t begin, std::size_t end);

// Stage 4: advance positions and orientations from the (possibly solver-corrected) velocities.
//   explicit Euler:       x += v_old h, q rotated by w_old.
//   semi-implicit Euler:  x += v h; q turns at constant angular momentum (as Verlet).
//   Verlet:               drift x += v_half h; q turns at constant angular momentum.
// Kinematic bodies move at their velocity whatever the integrator. The spin
// limit is maxTurn (WorldDef::maxRotationPerSubstep).
// Refreshes every moved body's world inverse inertia and, with `deltas` (the
// step has contact constraints and no joints), the pose change since the
// step's start (SolverBody::dp, dtheta) of the bodies the contact kernels
// read (BodyStore::contactDeltas).
// With `kindsKept`, each body's path is the step's MotionKind (classifyMotion),
// else it is worked out from the body's parameters (the same path).
void integratePositions(BodyStore& b, Integrator method, Real h, Real maxTurn, bool deltas, bool kindsKept,
                        std::size_t begin, std::size_t end);

// Stage 5, Verlet's second half kick, in three parts (entries [begin, end)
// each): verletPredict moves the velocities to the predictor the forces are
// evaluated at, the step evaluates the forces at the new positions, and
// verletKick gives the second half kick from the velocities before the
// predictor. Nothing for the Euler methods.
void verletPredict(BodyStore& b, Real h, std::size_t begin, std::size_t end);
void verletKick(BodyStore& b, Real h, std::size_t begin, std::size_t end);

// World inertia tensor R I_body R^T (not inverted).
inline Mat3 worldInertia(const Quat& q, const Mat3& inertiaBody) {
    const Mat3 r = toMat3(q);
    return r * inertiaBody * transpose(r);
}

}  // namespace fulcrum::detail
