// Cone-twist (ragdoll shoulders, hips, neck): a ball joint whose twist axis on
// B may swing inside a cone of half-angle swingLimit about A's axis, and turn
// about itself between twistLower and twistUpper. Both limits are one-sided
// speculative rows; the point block is solved last.
//
// Swing: the angle between A's axis and B's axis; its row turns about
// n = axisA x axisB / |axisA x axisB| (undefined when the axes are parallel,
// where the cone, of positive half-angle, is far away anyway).
// Twist: the twist part of B's rotation relative to A about the axis
// (swing-twist decomposition), its row about the bisector of the two axes.
#include <numbers>

#include "solver/joints/cone_twist.hpp"

namespace fulcrum::detail {

namespace {

struct ConeGeometry {
    bool hasSwing = false;
    Vec3 swingAxis;     // n: the swing angle grows with n . (wB - wA)
    Real swing = 0;     // angle between the axes
    Vec3 twistAxis;
};

ConeGeometry coneGeometry(const JointConstraint& j, const JointFrame& f) {
    ConeGeometry g;
    const Vec3 axisA = rotate(f.qA, j.localAxisA);
    const Vec3 axisB = rotate(f.qB, j.localAxisB);
    const Vec3 c = cross(axisA, axisB);
    const Real s = length(c);
    g.swing = dmath::atan2(s, dot(axisA, axisB));
    if (s > Real(1e-6)) {
        g.hasSwing = true;
        g.swingAxis = c * (1 / s);
    }
    const Vec3 mid = axisA + axisB;
    const Real m = length(mid);
    g.twistAxis = m > Real(1e-6) ? mid * (1 / m) : axisA;
    return g;
}

bool swingLimited(const JointConstraint& j) { return j.swingLimit < std::numbers::pi_v<Real>; }

}  // namespace

// ---- definition

ConeTwistJointDef ConeTwistJoint::fromJointDef(const JointDef& def, const JointEnds& ends) {
    ConeTwistJointDef d;
    static_cast<JointDefBase&>(d) = baseOf(def);
    d.localAnchorA = ends.a.localPoint(def.anchor);
    d.localAnchorB = ends.b.localPoint(def.anchor);
    const Vec3 axis = requireDirection({"joint", def.name}, "axis", def.axis);
    d.localAxisA = ends.a.localAxis(axis);
    d.localAxisB = ends.b.localAxis(axis);
    d.swingLimit = def.swingLimit;
    d.twistLower = def.twistLower;
    d.twistUpper = def.twistUpper;
    d.frictionTorque = def.frictionTorque;
    return d;
}

JointSetup ConeTwistJoint::setup(const Def& def, const Subject& who, const JointEnds& ends) {
    requireFinite(who, "localAnchorA", def.localAnchorA);
    requireFinite(who, "localAnchorB", def.localAnchorB);
    requireUnitAxis(who, "localAxisA", def.localAxisA);
    requireUnitAxis(who, "localAxisB", def.localAxisB);
    validateConeTwistRanges(who, def.swingLimit, def.twistLower, def.twistUpper);
    validateFrictionTorque(who, def.frictionTorque);
    JointSetup s;
    s.record = baseRecord(def, kType);
    setPointAnchors(s, ends, def.localAnchorA, def.localAnchorB);
    setAxes(s, ends, def.localAxisA, def.localAxisB);
    s.record.swingLimit = def.swingLimit;
    s.record.twistLower = def.twistLower;
    s.record.twistUpper = def.twistUpper;
    s.record.frictionTorque = def.frictionTorque;
    return s;
}

// ---- solver

void ConeTwistJoint::warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    const ConeGeometry g = coneGeometry(j, f);
    if (!j.direct) cachePointMass(j, a, b, f.rA, f.rB);
    Vec3 T = g.twistAxis * (j.impulse.lower - j.impulse.upper);
    if (g.hasSwing) T -= g.swingAxis * j.impulse.swing;
    applyPoint(a, b, f.rA, f.rB, j.impulse.linear);
    a.w -= a.invI * T;
    b.w += b.invI * T;
    cacheFriction(j, a, b, f.rA, f.rB);
    if (j.frictionValid) {
        applyFriction(j, a, b, f.rA, f.rB, j.impulse.friction);
    } else {
        j.impulse.friction = {};
    }
}

void ConeTwistJoint::solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    const ConeGeometry g = coneGeometry(j, f);
    JointImpulses& i = j.impulse;
    solveFrictionBlock(j, a, b, f.rA, f.rB);
    if (swingLimited(j) && g.hasSwing) {
        const JointRow inward{Vec3{}, -g.swingAxis, -g.swingAxis};
        solveLimitRow(inward, a, b, j.swingLimit - g.swing, i.swing, ctx);
    }
    const Real twist = twistAngle(j.relative0, f.qA, f.qB, j.localAxisA);
    const JointRow row = angularRow(g.twistAxis);
    solveLimitRow(row, a, b, twist - j.lower, i.lower, ctx);
    const JointRow back{Vec3{}, -g.twistAxis, -g.twistAxis};
    solveLimitRow(back, a, b, j.upper - twist, i.upper, ctx);
    if (!j.direct && j.pointMassValid) solvePointBlock(a, b, f.rA, f.rB, f.d, i.linear, ctx, j.pointMass);
}

}  // namespace fulcrum::detail

namespace fulcrum {

ConeTwistJointDef ConeTwistJointDef::fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor, Vec3 axis) {
    const detail::JointEnds ends = detail::jointEnds(world, a, b, "ConeTwistJointDef::fromWorld");
    ConeTwistJointDef d;
    d.bodyA = a;
    d.bodyB = b;
    d.localAnchorA = ends.a.localPoint(anchor);
    d.localAnchorB = ends.b.localPoint(anchor);
    const Vec3 unit = detail::worldAxisArgument(axis, "ConeTwistJointDef::fromWorld");
    d.localAxisA = ends.a.localAxis(unit);
    d.localAxisB = ends.b.localAxis(unit);
    return d;
}

}  // namespace fulcrum
