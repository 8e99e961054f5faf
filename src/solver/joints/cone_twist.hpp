#pragma once
// The cone-twist joint: here its members and the per-step glue; cone_twist.cpp its
// definition, warm start and rows; its SIMD lanes: cone_twist_wide.hpp.
// The members every joint type has are described in joint_types.hpp.
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_def.hpp"
#include "solver/joints/joint_wide.hpp"

namespace fulcrum::detail {

struct ConeTwistJoint {
    using Def = ConeTwistJointDef;
    static constexpr JointType kType = JointType::ConeTwist;
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

inline void ConeTwistJoint::prepare(JointConstraint& j, const StoredJoint& stored, Real) {
    const JointDef& def = stored.def;
    j.limit = true;
    j.swingLimit = def.swingLimit;
    j.lower = def.twistLower;
    j.upper = def.twistUpper;
    dropSpinFrictionIfOff(j);
    if (!def.coneDrive.enabled) j.impulse.drive = {};
}

// The drive's rows are scalar only (cone_twist.cpp): a driven cone-twist stays off the SIMD lanes.
inline WideKind ConeTwistJoint::wideKind(const JointConstraint& j) {
    return j.record != nullptr && j.record->coneDrive.enabled ? WideKind::NotWide : WideKind::ConeTwist;
}

inline void ConeTwistJoint::addReaction(const JointConstraint& j, Vec3& force, Vec3& torque) {
    const JointFrame& f = j.frame;
    const JointImpulses& i = j.impulse;
    if (j.frictionValid) force += j.frictionCoupling * (i.friction + i.drive);
    const Vec3 axisA = rotate(f.qA, j.localAxisA), axisB = rotate(f.qB, j.localAxisB);
    const Vec3 c = cross(axisA, axisB);
    const Real s = length(c);
    const Vec3 mid = axisA + axisB;
    const Real m = length(mid);
    torque += (m > Real(1e-6) ? mid * (1 / m) : axisA) * (i.lower - i.upper) + i.friction + i.drive;  // drive: about B's anchor, as friction
    if (s > Real(1e-6)) torque -= c * (i.swing / s);
}

inline Real ConeTwistJoint::error(const JointPose& pose) { return length(pose.d); }

inline Real ConeTwistJoint::position(const JointPose& pose) {
    return twistAngle(*pose.relativeRotation, pose.orientationA(), *pose.qB, *pose.localAxisA);
}

}  // namespace fulcrum::detail
