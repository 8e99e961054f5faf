#pragma once
// The fixed joint: here its members and the per-step glue; fixed.cpp its
// definition, warm start and rows; scalar kernels only.
// The members every joint type has are described in joint_types.hpp.
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_def.hpp"
#include "solver/joints/joint_wide.hpp"

namespace fulcrum::detail {

struct FixedJoint {
    using Def = FixedJointDef;
    static constexpr JointType kType = JointType::Fixed;
    static constexpr bool kReadsOrientations = true;
    static constexpr bool kHasFreeAxis = false;
    static constexpr bool kHasPointBlock = true;
    static constexpr bool kProjected = true;

    static Def fromJointDef(const JointDef& def, const JointEnds& ends);
    static JointSetup setup(const Def& def, const Subject& who, const JointEnds& ends);
    static void prepare(JointConstraint& j, const StoredJoint& stored, Real h);
    static void warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx);
    static void solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx);
    static bool hasRows(const JointConstraint&) { return true; }
    static WideKind wideKind(const JointConstraint& j);
    static void addReaction(const JointConstraint& j, Vec3& force, Vec3& torque);
    static Real error(const JointPose& pose);
    static Real position(const JointPose& pose);
};

// The per-step glue, inline: called for every joint every step.

inline void FixedJoint::prepare(JointConstraint& j, const StoredJoint&, Real) {
    dropLimitImpulsesIfOff(j);
    dropSpinFriction(j);
}

inline WideKind FixedJoint::wideKind(const JointConstraint&) { return WideKind::NotWide; }

inline void FixedJoint::addReaction(const JointConstraint& j, Vec3&, Vec3& torque) { torque += j.impulse.angular; }

inline Real FixedJoint::error(const JointPose& pose) { return length(pose.d); }

inline Real FixedJoint::position(const JointPose&) { return 0; }

}  // namespace fulcrum::detail
