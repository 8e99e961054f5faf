#pragma once
// The hinge joint: here its members and the per-step glue; hinge.cpp its
// definition, warm start and rows; its SIMD lanes: hinge_wide.hpp.
// The members every joint type has are described in joint_types.hpp.
#include "solver/joints/coupled_row.hpp"
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_def.hpp"
#include "solver/joints/joint_wide.hpp"

namespace fulcrum::detail {

struct HingeJoint {
    using Def = HingeJointDef;
    static constexpr JointType kType = JointType::Hinge;
    static constexpr bool kReadsOrientations = true;
    static constexpr bool kHasFreeAxis = true;
    static constexpr bool kHasPointBlock = true;
    static constexpr bool kProjected = true;

    static Def fromJointDef(const JointDef& def, const JointEnds& ends);
    static JointSetup setup(const Def& def, const Subject& who, const JointEnds& ends);
    // World::setJointLimits's check of new limits.
    static void validateLimits(const Subject& who, bool enabled, Real lower, Real upper);
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

inline void HingeJoint::prepare(JointConstraint& j, const StoredJoint& stored, Real h) {
    prepareFreeAxis(j, stored.def, h);
    // Friction in a hinge is a motor at speed 0 (only while the motor is off).
    if (!j.motor && stored.def.frictionTorque > 0) {
        j.motor = true;
        j.motorSpeed = 0;
        j.maxMotorImpulse = j.maxFrictionImpulse;
    }
    dropLimitImpulsesIfOff(j);
    dropSpinFriction(j);
}

inline WideKind HingeJoint::wideKind(const JointConstraint&) { return WideKind::Hinge; }

inline void HingeJoint::addReaction(const JointConstraint& j, Vec3& force, Vec3& torque) {
    addFreeAxisReaction(j, force, torque);
    torque += j.impulse.angular;
}

inline Real HingeJoint::error(const JointPose& pose) { return length(pose.d); }

inline Real HingeJoint::position(const JointPose& pose) {
    return twistAngle(*pose.relativeRotation, pose.orientationA(), *pose.qB, *pose.localAxisA);
}

}  // namespace fulcrum::detail
