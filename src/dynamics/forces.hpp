#pragma once
// Force evaluation: the "compute forces" stage of every sub-step. It works on
// the body store's awake set (src/dynamics/body_store.hpp): the awake bodies'
// pose and velocities as the sub-step left them.
#include <span>

#include "dynamics/body_store.hpp"
#include "dynamics/slot_pool.hpp"

namespace fulcrum::detail {

// A spring's record (WorldImpl::springs).
struct SpringData : PoolSlot {  // alive, generation: WorldImpl::springs is a SlotPool
    BodyId bodyA, bodyB;             // null: the static world
    Vec3 localA, localB;             // from the centre of mass, body axes; world point for a world end
    Real restLength = 0, stiffness = 0, damping = 0;
};

// Sums, for every awake dynamic body, into b.forces[dense]:
//   gravity                 m * gravityScale * g                 (at the centre of mass)
//   drag                    -b v - c |v| v                        (at the centre of mass)
//   user forces / torques   b.applied (applyForce & co.)
//   ForceCallback           called with the body's current kinematics and `time`
//   springs                 -k (d - L0 n) - c (v_rel . n) n on B, the opposite on A,
//                           at the anchors (so each end also gets r x F)
// Reads positions and velocities from the awake set as they are now, so an
// integrator chooses the state it evaluates at by what it has written there.
// Static and kinematic bodies get nothing (infinite mass: forces don't move them).
// In three parts, so the step can run the first in parallel with the same
// bits: evaluateBodyForces for the awake-list entries [begin, end) writes
// only those bodies' forces and leaves out the ForceCallbacks, returning
// whether one of its bodies has one; then, on one thread, addCallbackForces
// adds the callbacks' wrenches in body order (callbacks need not be
// thread-safe) and addSpringForces the springs. With `dragged`, also sets
// *dragged when one of its bodies has drag (a force that depends on the
// velocity; without it, callbacks and springs, a body's force is the same
// at every sub-step of a step: WorldImpl::buildSubSteps).
bool evaluateBodyForces(BodyStore& b, const Vec3& gravity, std::uint32_t begin, std::uint32_t end, bool* dragged = nullptr);
void addCallbackForces(BodyStore& b, double time);
void addSpringForces(BodyStore& b, std::span<const SpringData> springs);

// Force on end B of a spring between world points pA and pB with relative
// velocity vRel = vB - vA (vector form, well defined as the length goes to 0).
Vec3 springForceOnB(const Vec3& pA, const Vec3& pB, const Vec3& vRel, Real restLength, Real stiffness, Real damping);

}  // namespace fulcrum::detail
