// Hinge (revolute): the anchors coincide (3-row point block) and B's axis stays
// aligned with A's (2 angular rows perpendicular to the axis, a 2x2 block), so
// B only turns about the axis. Along the axis: an optional spring to a target
// angle, a motor (target speed, max torque) and lower/upper angle limits, in
// that order (the limits, solved after the motor, win over it), then the
// alignment and point rows last, since they carry the joint's error.
//
// The angle is B's rotation relative to A about the axis, measured from the
// pose at creation (swing-twist decomposition, joint_common.hpp), in (-pi, pi].
#include "solver/joints/coupled_row.hpp"
#include "solver/joints/hinge.hpp"

namespace fulcrum::detail {

namespace {

// Torque impulse of the axial rows, about the axis.
Real axialImpulse(const JointImpulses& i) { return i.spring + i.motor + i.lower - i.upper; }

// Two rows keep axisB parallel to axisA: C = axisA x axisB projected on a
// basis (p1, p2) perpendicular to axisA; Cdot = p . (wB - wA).
void solveAlignment(SolverBody& a, SolverBody& b, const Vec3& axisA, const Vec3& axisB, Vec3& lambda, const JointContext& ctx) {
    Vec3 p1, p2;
    orthonormalBasis(axisA, p1, p2);
    const Mat3 I = a.invI + b.invI;
    const Vec3 Ip1 = I * p1, Ip2 = I * p2;
    const Real k11 = dot(p1, Ip1), k12 = dot(p1, Ip2), k22 = dot(p2, Ip2);
    const Real det = k11 * k22 - k12 * k12;
    if (!(det > 0)) return;
    const Vec3 C = cross(axisA, axisB);
    const Vec3 dw = b.w - a.w;
    Real r1 = dot(p1, dw), r2 = dot(p2, dw);
    Real massScale = 1, impulseScale = 0;
    if (ctx.useBias) {
        r1 += ctx.soft.biasRate * dot(p1, C);
        r2 += ctx.soft.biasRate * dot(p2, C);
        massScale = ctx.soft.massScale;
        impulseScale = ctx.soft.impulseScale;
    }
    const Real inv = 1 / det;
    const Real d1 = -massScale * inv * (k22 * r1 - k12 * r2) - impulseScale * dot(p1, lambda);
    const Real d2 = -massScale * inv * (k11 * r2 - k12 * r1) - impulseScale * dot(p2, lambda);
    const Vec3 T = p1 * d1 + p2 * d2;
    lambda += T;
    a.w -= a.invI * T;
    b.w += b.invI * T;
}

}  // namespace

// ---- definition

HingeJointDef HingeJoint::fromJointDef(const JointDef& def, const JointEnds& ends) {
    HingeJointDef d = axisDefFromJointDef<HingeJointDef>(def, ends);
    d.frictionTorque = def.frictionTorque;
    return d;
}

void HingeJoint::validateLimits(const Subject& who, bool enabled, Real lower, Real upper) {
    detail::validateLimits(who, enabled, lower, upper, true);
}

JointSetup HingeJoint::setup(const Def& def, const Subject& who, const JointEnds& ends) {
    JointSetup s = setupAxisJoint(def, who, ends, kType, true);
    validateFrictionTorque(who, def.frictionTorque);
    s.record.frictionTorque = def.frictionTorque;
    return s;
}

// ---- solver

void HingeJoint::warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    const Vec3 axis = rotate(f.qA, j.localAxisA);
    if (!j.direct) cachePointMass(j, a, b, f.rA, f.rB);
    // Only the perpendicular part of the alignment impulse belongs to its rows.
    j.impulse.angular -= axis * dot(axis, j.impulse.angular);
    applyPoint(a, b, f.rA, f.rB, j.impulse.linear);
    a.w -= a.invI * j.impulse.angular;
    b.w += b.invI * j.impulse.angular;
    // The axial rows turn B about the axis with the point and alignment rows'
    // share (coupled_row.hpp): coupled at the step's first warm start, then
    // kept or coupled again by the relax passes (couplingStale), whose
    // positions this warm start shares.
    if (j.spring || j.motor || j.limit) {
        if (couplingStale(j.axialCoupled, false, ctx.rotations[j.bodyA], ctx.rotations[j.bodyB])) {
            coupleHingeRow(a, b, f.rA, f.rB, axis, j.axial);
            j.axialCoupled = kAxialAtStart;
        }
        applyRow(j.axial.apply, a, b, axialImpulse(j.impulse));
    }
}

void HingeJoint::solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    const Vec3 axisA = rotate(f.qA, j.localAxisA);
    const Vec3 axisB = rotate(f.qB, j.localAxisB);
    JointImpulses& i = j.impulse;
    if (j.spring || j.motor || j.limit) {
        // A relax pass has new positions: the guard (coupled_row.hpp).
        if (couplingStale(j.axialCoupled, !ctx.useBias, ctx.rotations[j.bodyA], ctx.rotations[j.bodyB])) {
            coupleHingeRow(a, b, f.rA, f.rB, axisA, j.axial);
            j.axialCoupled = kAxialMoved;
        }
        CoupledRow row = j.axial;
        row.measure = angularRow(axisA);
        const Real angle = j.spring || j.limit ? twistAngle(j.relative0, f.qA, f.qB, j.localAxisA) : Real(0);
        if (j.spring) {
            solveCoupledSpring(row, a, b, angle - j.springTarget, j.springBias, j.springGamma, j.maxSpringImpulse, i.spring);
        }
        if (j.motor) solveCoupledMotor(row, a, b, j.motorSpeed, j.maxMotorImpulse, i.motor);
        if (j.limit) {
            solveCoupledLimit(row, 1, a, b, angle - j.lower, i.lower, ctx);
            solveCoupledLimit(row, -1, a, b, j.upper - angle, i.upper, ctx);
        }
    }
    solveAlignment(a, b, axisA, axisB, i.angular, ctx);
    if (!j.direct && j.pointMassValid) solvePointBlock(a, b, f.rA, f.rB, f.d, i.linear, ctx, j.pointMass);
}

}  // namespace fulcrum::detail

namespace fulcrum {

HingeJointDef HingeJointDef::fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor, Vec3 axis) {
    const detail::JointEnds ends = detail::jointEnds(world, a, b, "HingeJointDef::fromWorld");
    HingeJointDef d;
    d.bodyA = a;
    d.bodyB = b;
    d.localAnchorA = ends.a.localPoint(anchor);
    d.localAnchorB = ends.b.localPoint(anchor);
    const Vec3 unit = detail::worldAxisArgument(axis, "HingeJointDef::fromWorld");
    d.localAxisA = ends.a.localAxis(unit);
    d.localAxisB = ends.b.localAxis(unit);
    return d;
}

}  // namespace fulcrum
