#pragma once
// The distance joint (distance.cpp; scalar kernels only).
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

}  // namespace fulcrum::detail
