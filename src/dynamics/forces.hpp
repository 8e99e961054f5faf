#pragma once
// Force evaluation: the "compute forces" stage of every sub-step.
#include "world/world_impl.hpp"

namespace fulcrum::detail {

// Sums, for every dynamic body, into w.forces[dense]:
//   gravity                 m * gravityScale * g                 (at the centre of mass)
//   drag                    -b v - c |v| v                        (at the centre of mass)
//   user forces / torques   w.applied (applyForce & co.)
//   ForceCallback           called with the body's current kinematics and `time`
//   springs                 -k (d - L0 n) - c (v_rel . n) n on B, the opposite on A,
//                           at the anchors (so each end also gets r x F)
// Reads positions and velocities from w.motion as they are now, so an
// integrator chooses the state it evaluates at by what it has written there.
// Static and kinematic bodies get nothing (infinite mass: forces don't move them).
void evaluateForces(WorldImpl& w, double time);

// evaluateForces in three parts, for the threaded step (step.cpp), with the
// same bits: evaluateBodyForces for the awake-list entries [begin, end)
// writes only those bodies' w.forces (safe in parallel) and leaves out the
// ForceCallbacks, returning whether one of its bodies has one; then, on one
// thread, addCallbackForces adds the callbacks' wrenches in body order
// (callbacks need not be thread-safe) and addSpringForces the springs.
bool evaluateBodyForces(WorldImpl& w, std::uint32_t begin, std::uint32_t end);
void addCallbackForces(WorldImpl& w, double time);
void addSpringForces(WorldImpl& w);

// Force on end B of a spring between world points pA and pB with relative
// velocity vRel = vB - vA (vector form, well defined as the length goes to 0).
Vec3 springForceOnB(const Vec3& pA, const Vec3& pB, const Vec3& vRel, Real restLength, Real stiffness, Real damping);

}  // namespace fulcrum::detail
