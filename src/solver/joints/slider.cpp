// Slider (prismatic): B keeps its rest orientation relative to A (3-row
// angular block) and its anchor stays on A's axis through A's anchor (2 linear
// rows perpendicular to the axis, a 2x2 block). Along the axis: spring to a
// target position, motor (speed, max force), lower/upper limits. The position
// is the anchors' separation along the axis (0 at creation).
//
// The linear rows act at B's anchor; on A the lever arm is rA + d (the point
// of A under B's anchor), which makes the rows exact for any separation
// (Catto's prismatic joint, Box2D).
#include "solver/joints/coupled_row.hpp"
#include "solver/joints/slider.hpp"

namespace fulcrum::detail {

namespace {

Real axialImpulse(const JointImpulses& i) { return i.spring + i.motor + i.lower - i.upper; }

void applyLinear(SolverBody& a, SolverBody& b, const Vec3& leverA, const Vec3& rB, const Vec3& P) {
    a.v -= P * a.invMass;
    a.w -= a.invI * cross(leverA, P);
    b.v += P * b.invMass;
    b.w += b.invI * cross(rB, P);
}

void solvePerpendicular(SolverBody& a, SolverBody& b, const Vec3& axis, const Vec3& leverA, const Vec3& rB, const Vec3& d,
                        Vec3& lambda, const JointContext& ctx) {
    Vec3 p1, p2;
    orthonormalBasis(axis, p1, p2);
    const Real m = a.invMass + b.invMass;
    const Vec3 a1 = cross(leverA, p1), a2 = cross(leverA, p2);
    const Vec3 b1 = cross(rB, p1), b2 = cross(rB, p2);
    const Real k11 = m + dot(a1, a.invI * a1) + dot(b1, b.invI * b1);
    const Real k12 = dot(a1, a.invI * a2) + dot(b1, b.invI * b2);
    const Real k22 = m + dot(a2, a.invI * a2) + dot(b2, b.invI * b2);
    const Real det = k11 * k22 - k12 * k12;
    if (!(det > 0)) return;
    const Vec3 dv = b.v + cross(b.w, rB) - a.v - cross(a.w, leverA);
    Real r1 = dot(p1, dv), r2 = dot(p2, dv);
    Real massScale = 1, impulseScale = 0;
    if (ctx.useBias) {
        r1 += ctx.soft.biasRate * dot(p1, d);
        r2 += ctx.soft.biasRate * dot(p2, d);
        massScale = ctx.soft.massScale;
        impulseScale = ctx.soft.impulseScale;
    }
    const Real inv = 1 / det;
    const Real d1 = -massScale * inv * (k22 * r1 - k12 * r2) - impulseScale * dot(p1, lambda);
    const Real d2 = -massScale * inv * (k11 * r2 - k12 * r1) - impulseScale * dot(p2, lambda);
    const Vec3 P = p1 * d1 + p2 * d2;
    lambda += P;
    applyLinear(a, b, leverA, rB, P);
}

}  // namespace

// ---- definition

SliderJointDef SliderJoint::fromJointDef(const JointDef& def, const JointEnds& ends) {
    SliderJointDef d = axisDefFromJointDef<SliderJointDef>(def, ends);
    d.frictionForce = def.frictionTorque;  // JointDef's one friction field: a force along a slider's axis
    return d;
}

void SliderJoint::validateLimits(const Subject& who, bool enabled, Real lower, Real upper) {
    detail::validateLimits(who, enabled, lower, upper, false);
}

JointSetup SliderJoint::setup(const Def& def, const Subject& who, const JointEnds& ends) {
    JointSetup s = setupAxisJoint(def, who, ends, kType, false);
    validateFrictionTorque(who, def.frictionForce);
    s.record.frictionTorque = def.frictionForce;
    return s;
}

// ---- solver

void SliderJoint::warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    const Vec3 axis = rotate(f.qA, j.localAxisA);
    j.impulse.linear -= axis * dot(axis, j.impulse.linear);
    applyLinear(a, b, f.rA + f.d, f.rB, j.impulse.linear);
    a.w -= a.invI * j.impulse.angular;
    b.w += b.invI * j.impulse.angular;
    // The axial rows move B along the axis with the angular lock's and the
    // perpendicular rows' share (coupled_row.hpp), once per sub-step.
    if (j.spring || j.motor || j.limit) {
        coupleSliderRow(a, b, f.rA + f.d, f.rB, axis, j.axial);
        applyRow(j.axial.apply, a, b, axialImpulse(j.impulse));
    }
}

void SliderJoint::solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    const Vec3 axis = rotate(f.qA, j.localAxisA);
    const Vec3 leverA = f.rA + f.d;
    const Real x = dot(f.d, axis);
    JointImpulses& i = j.impulse;
    if (j.spring || j.motor || j.limit) {
        CoupledRow row = j.axial;
        row.measure = linearRow(axis, leverA, f.rB);
        if (j.spring) {
            solveCoupledSpring(row, a, b, x - j.springTarget, j.springBias, j.springGamma, j.maxSpringImpulse, i.spring);
        }
        if (j.motor) solveCoupledMotor(row, a, b, j.motorSpeed, j.maxMotorImpulse, i.motor);
        if (j.limit) {
            solveCoupledLimit(row, 1, a, b, x - j.lower, i.lower, ctx);
            solveCoupledLimit(row, -1, a, b, j.upper - x, i.upper, ctx);
        }
    }
    solveAngularBlock(a, b, angularError(j, f.qA, f.qB), i.angular, ctx);
    solvePerpendicular(a, b, axis, leverA, f.rB, f.d, i.linear, ctx);
}

}  // namespace fulcrum::detail

namespace fulcrum {

SliderJointDef SliderJointDef::fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor, Vec3 axis) {
    const detail::JointEnds ends = detail::jointEnds(world, a, b, "SliderJointDef::fromWorld");
    SliderJointDef d;
    d.bodyA = a;
    d.bodyB = b;
    d.localAnchorA = ends.a.localPoint(anchor);
    d.localAnchorB = ends.b.localPoint(anchor);
    const Vec3 unit = detail::worldAxisArgument(axis, "SliderJointDef::fromWorld");
    d.localAxisA = ends.a.localAxis(unit);
    d.localAxisB = ends.b.localAxis(unit);
    return d;
}

}  // namespace fulcrum
