#pragma once
// The six-degree-of-freedom joint: here its members, its geometry and the
// per-step glue; six_dof.cpp its definition, warm start and rows; scalar
// kernels only. The members every joint type has are described in joint_types.hpp.
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_def.hpp"
#include "solver/joints/joint_wide.hpp"

namespace fulcrum::detail {

// A six-DOF joint's coordinates now (six_dof.cpp describes them).
struct SixDofGeometry {
    Vec3 linearAxis[3];   // A's joint frame axes x, y, z, world
    Real linear[3];       // B's anchor from A's along them (m)
    Real angle[3];        // Euler angles x, y, z (rad)
    Vec3 angularRow[3];   // each angle's rate is dot(angularRow[i], wB - wA)
    Vec3 gimbal[3];       // the axis each angle turns about (A's x, the turned y, B's z): efforts
};

// From the orientations qA, qB, the rest pose (conj(qA) qB at creation), the
// joint frame in A's axes and the anchors' separation d (world).
SixDofGeometry sixDofGeometry(const Quat& qA, const Quat& qB, const Quat& relative0, const Quat& localFrameA, const Vec3& d);

struct SixDofJoint {
    using Def = SixDofJointDef;
    static constexpr JointType kType = JointType::SixDof;
    static constexpr bool kReadsOrientations = true;
    static constexpr bool kHasFreeAxis = false;   // its axes have their own setter (World::setSixDofAxis)
    static constexpr bool kHasPointBlock = true;  // when all linear axes are locked (pointBlock)
    static constexpr bool kProjected = false;

    static Def fromJointDef(const JointDef& def, const JointEnds& ends);
    static JointSetup setup(const Def& def, const Subject& who, const JointEnds& ends);
    // Checks one axis's settings (errors name "axes[<axis>].<field>").
    static void validateAxis(const Subject& who, int axis, const SixDofAxis& settings);
    static void prepare(JointConstraint& j, const StoredJoint& stored, Real h);
    static bool pointBlock(const JointConstraint& j) { return j.pointLocked; }
    static void warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx);
    static void solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx);
    static bool hasRows(const JointConstraint&) { return true; }
    static WideKind wideKind(const JointConstraint&) { return WideKind::NotWide; }
    // Its reaction needs the bodies (its coupled rows' share: jointReaction passes them).
    static void addReaction(const JointConstraint& j, const SolverBody& a, const SolverBody& b, Vec3& force, Vec3& torque);
    static Real error(const JointPose& pose);
    static Real position(const JointPose&) { return 0; }  // per axis: World::sixDofReading
};

inline bool allLocked(const SixDofAxes& axes, int first) {
    return axes[first].mode == AxisMode::Locked && axes[first + 1].mode == AxisMode::Locked &&
           axes[first + 2].mode == AxisMode::Locked;
}

inline void SixDofJoint::prepare(JointConstraint& j, const StoredJoint& stored, Real h) {
    const SixDofAxes& axes = stored.def.axes;
    j.pointLocked = allLocked(axes, kAxisX);
    j.rotationLocked = allLocked(axes, kAxisRotX);
    // Rows an axis does not have this step start at zero: its motor, its spring,
    // its lock or limit (a free axis).
    JointImpulses& i = j.impulse;
    for (int k = 0; k < kSixDofAxes; ++k) {
        const SixDofAxis& s = axes[static_cast<std::size_t>(k)];
        Vec3& motor = k < 3 ? i.axisMotorLinear : i.axisMotorAngular;
        Vec3& spring = k < 3 ? i.axisSpringLinear : i.axisSpringAngular;
        const auto c = static_cast<std::size_t>(k % 3);
        const bool driven = s.mode != AxisMode::Locked;
        if (!(driven && s.motor.enabled)) motor[c] = 0;
        if (!(driven && s.spring.enabled)) spring[c] = 0;
        // A position drive's limit lowered since the last step: its warm start stays within it.
        const Real maxSpring = h * s.spring.maxForce;
        if (spring[c] > maxSpring) spring[c] = maxSpring;
        if (spring[c] < -maxSpring) spring[c] = -maxSpring;
        const bool blockOfKind = k < 3 ? j.pointLocked : j.rotationLocked;
        if (!blockOfKind && s.mode == AxisMode::Free) (k < 3 ? i.linear : i.angular)[c] = 0;
    }
    dropSpinFriction(j);
}

}  // namespace fulcrum::detail
