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

// Force on end B of a spring between world points pA and pB with relative
// velocity vRel = vB - vA (vector form, well defined as the length goes to 0).
Vec3 springForceOnB(const Vec3& pA, const Vec3& pB, const Vec3& vRel, Real restLength, Real stiffness, Real damping);

}  // namespace fulcrum::detail
