#pragma once
// The slider joint: here its members and the per-step glue; slider.cpp its
// definition, warm start and rows; scalar kernels only.
// The members every joint type has are described in joint_types.hpp.
#include "solver/joints/coupled_row.hpp"
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_def.hpp"
#include "solver/joints/joint_wide.hpp"

namespace fulcrum::detail {

struct SliderJoint {
    using Def = SliderJointDef;
    static constexpr JointType kType = JointType::Slider;
    static constexpr bool kReadsOrientations = true;
    static constexpr bool kHasFreeAxis = true;
    static constexpr bool kHasPointBlock = false;
    static constexpr bool kProjected = false;

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

inline void SliderJoint::prepare(JointConstraint& j, const StoredJoint& stored, Real h) {
    prepareFreeAxis(j, stored.def, h);
    // Friction along a slider is a motor at speed 0 (only while the motor is off), as a hinge's.
    if (!j.motor && stored.def.frictionTorque > 0) {
        j.motor = true;
        j.motorSpeed = 0;
        j.maxMotorImpulse = j.maxFrictionImpulse;
    }
    dropLimitImpulsesIfOff(j);
    dropSpinFriction(j);
}

inline WideKind SliderJoint::wideKind(const JointConstraint&) { return WideKind::NotWide; }

inline void SliderJoint::addReaction(const JointConstraint& j, Vec3& force, Vec3& torque) {
    addFreeAxisReaction(j, force, torque);
    torque += j.impulse.angular;
}

inline Real SliderJoint::error(const JointPose& pose) {
    // Only motion along the axis (fixed in body A) is free.
    const Vec3 axis = pose.axisA();
    return length(pose.d - axis * dot(pose.d, axis));
}

inline Real SliderJoint::position(const JointPose& pose) { return dot(pose.d, rotate(pose.orientationA(), *pose.localAxisA)); }

}  // namespace fulcrum::detail
