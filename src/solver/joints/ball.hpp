#pragma once
// The ball-and-socket joint (ball.cpp; its SIMD lanes: ball_wide.hpp, and
// cone_twist_wide.hpp's blocks for one with friction).
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

}  // namespace fulcrum::detail
