#pragma once
// The distance joint: here its members and the per-step glue; distance.cpp its
// definition, warm start and rows; scalar kernels only.
// The members every joint type has are described in joint_types.hpp.
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_def.hpp"
#include "solver/joints/joint_wide.hpp"

namespace fulcrum::detail {

struct DistanceJoint {
    using Def = DistanceJointDef;
    static constexpr JointType kType = JointType::Distance;
    static constexpr bool kReadsOrientations = false;
    static constexpr bool kHasFreeAxis = false;
    static constexpr bool kHasPointBlock = false;
    static constexpr bool kProjected = true;

    static Def fromJointDef(const JointDef& def, const JointEnds& ends);
    static JointSetup setup(const Def& def, const Subject& who, const JointEnds& ends);
    static void prepare(JointConstraint& j, const StoredJoint& stored, Real h);
    static void warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx);
    static void solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx);
    static bool hasRows(const JointConstraint&) { return true; }
    // The length error beyond the slop that JointSolver::projectPositions
    // removes at `len` (0: within the limits, or within the slop of them).
    static Real projectionError(const JointConstraint& j, Real len, Real slop);
    static WideKind wideKind(const JointConstraint& j);
    static void addReaction(const JointConstraint& j, Vec3& force, Vec3& torque);
    static Real error(const JointPose& pose);
    static Real position(const JointPose& pose);
};

// The per-step glue, inline: called for every joint every step.

inline void DistanceJoint::prepare(JointConstraint& j, const StoredJoint& stored, Real h) {
    const JointDef& def = stored.def;
    j.lower = stored.minLength;
    j.upper = stored.maxLength;
    j.restLength = stored.restLength;
    j.spring = def.stiffness > 0 || def.damping > 0;
    j.rigidDistance = !j.spring && stored.minLength == stored.maxLength;
    springCoefficients(def.stiffness, def.damping, h, j.springBias, j.springGamma);
    dropSpinFriction(j);  // its limit impulses stay: its min / max rows are always on
}

inline WideKind DistanceJoint::wideKind(const JointConstraint&) { return WideKind::NotWide; }

inline void DistanceJoint::addReaction(const JointConstraint& j, Vec3& force, Vec3&) {
    const JointImpulses& i = j.impulse;
    const Real axial = i.spring + i.motor + i.lower - i.upper;
    const Real len = length(j.frame.d);
    force = len > Real(1e-6) ? j.frame.d * ((i.axial + axial) / len) : Vec3{};
}

inline Real DistanceJoint::error(const JointPose& pose) {
    const Real len = length(pose.d);
    if (len < *pose.minLength) return *pose.minLength - len;
    if (len > *pose.maxLength) return len - *pose.maxLength;
    return 0;
}

inline Real DistanceJoint::position(const JointPose& pose) { return length(pose.d); }

inline Real DistanceJoint::projectionError(const JointConstraint& j, Real len, Real slop) {
    Real C = 0;
    if (j.rigidDistance) {
        C = len - j.restLength;
    } else if (len > j.upper) {
        C = len - j.upper;
    } else if (len < j.lower) {
        C = len - j.lower;
    } else {
        return 0;
    }
    return C > slop ? C - slop : (C < -slop ? C + slop : 0);
}

}  // namespace fulcrum::detail
