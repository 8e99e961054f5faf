#pragma once
// The ball-and-socket joint: here its members and the per-step glue; ball.cpp its
// definition, warm start and rows; its SIMD lanes: ball_wide.hpp, and
// cone_twist_wide.hpp's blocks for one with friction.
// The members every joint type has are described in joint_types.hpp.
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_def.hpp"
#include "solver/joints/joint_wide.hpp"

namespace fulcrum::detail {

struct BallJoint {
    using Def = BallJointDef;
    static constexpr JointType kType = JointType::Ball;
    static constexpr bool kReadsOrientations = false;
    static constexpr bool kHasFreeAxis = false;
    static constexpr bool kHasPointBlock = true;
    static constexpr bool kProjected = true;

    static Def fromJointDef(const JointDef& def, const JointEnds& ends);
    static JointSetup setup(const Def& def, const Subject& who, const JointEnds& ends);
    static void prepare(JointConstraint& j, const StoredJoint& stored, Real h);
    static void warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx);
    static void solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx);
    // A joint tree's frictionless ball joint has no Gauss-Seidel rows (the tree solver has its point block).
    static bool hasRows(const JointConstraint& j) { return !(j.direct && !(j.maxFrictionImpulse > 0)); }
    static WideKind wideKind(const JointConstraint& j);
    static void addReaction(const JointConstraint& j, Vec3& force, Vec3& torque);
    static Real error(const JointPose& pose);
    static Real position(const JointPose& pose);
};

// The per-step glue, inline: called for every joint every step.

inline void BallJoint::prepare(JointConstraint& j, const StoredJoint&, Real) {
    dropLimitImpulsesIfOff(j);
    dropSpinFrictionIfOff(j);
}

inline WideKind BallJoint::wideKind(const JointConstraint& j) {
    // With friction: a cone-twist without limits (in a tree or not); a tree's
    // frictionless one has no rows there.
    if (j.maxFrictionImpulse > 0) return WideKind::ConeTwist;
    return !j.direct ? WideKind::Ball : WideKind::NotWide;
}

inline void BallJoint::addReaction(const JointConstraint& j, Vec3& force, Vec3& torque) {
    // Friction carries the point rows' share that goes with it (cacheFriction).
    if (j.frictionValid) force += j.frictionCoupling * j.impulse.friction;
    torque += j.impulse.friction;
}

inline Real BallJoint::error(const JointPose& pose) { return length(pose.d); }

inline Real BallJoint::position(const JointPose&) { return 0; }

}  // namespace fulcrum::detail
