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

// The drive: the rotation vector C from B's target orientation (qA target
// rest) to B's, driven to zero by an implicit spring-damper on the relative
// spin (Catto's soft constraint with the drive's own stiffness and damping;
// infinite stiffness: the joint's equality softness), the accumulated torque
// impulse clamped to h maxTorque. Like the joint friction, its torque comes
// with the point rows' share and sees the spin as the joint allows it (the
// Schur complement of the point block, cacheFriction): with the free body's
// inertia alone a small ball on a long lever sagged 0.12 rad under a rigid drive.
void solveDrive(const JointConstraint& j, const ConeTwistDrive& drive, SolverBody& a, SolverBody& b, const JointFrame& f,
                Vec3& lambda, const JointContext& ctx) {
    if (!j.frictionValid) return;
    const Vec3 C = toRotationVector(f.qB * conjugate(f.qA * drive.target * j.relative0));
    const Vec3 cdot = b.w - a.w;
    Vec3 d;
    if (std::isinf(drive.stiffness)) {
        d = softBlockImpulse(j.frictionMass, cdot, C, lambda, ctx);  // rigid: the point block's soft step
    } else {
        Real bias = 0, gamma = 0;
        springCoefficients(drive.stiffness, drive.damping, ctx.h, bias, gamma);
        const Mat3 Ks = inverse(j.frictionMass) + Mat3::diagonal(gamma);
        if (!(determinant(Ks) > 0)) return;
        d = -(inverse(Ks) * (cdot + C * bias + lambda * gamma));
    }
    const Vec3 old = lambda;
    lambda += d;
    const Real maxImpulse = ctx.h * drive.maxTorque, len = length(lambda);
    if (len > maxImpulse) lambda *= maxImpulse / len;
    applyFriction(j, a, b, f.rA, f.rB, lambda - old);
}

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
    d.drive = def.coneDrive;
    return d;
}

JointSetup ConeTwistJoint::setup(const Def& def, const Subject& who, const JointEnds& ends) {
    requireFinite(who, "localAnchorA", def.localAnchorA);
    requireFinite(who, "localAnchorB", def.localAnchorB);
    requireUnitAxis(who, "localAxisA", def.localAxisA);
    requireUnitAxis(who, "localAxisB", def.localAxisB);
    validateConeTwistRanges(who, def.swingLimit, def.twistLower, def.twistUpper);
    validateFrictionTorque(who, def.frictionTorque);
    validateConeTwistDrive(who, def.drive);
    JointSetup s;
    s.record = baseRecord(def, kType);
    setPointAnchors(s, ends, def.localAnchorA, def.localAnchorB);
    setAxes(s, ends, def.localAxisA, def.localAxisB);
    s.record.swingLimit = def.swingLimit;
    s.record.twistLower = def.twistLower;
    s.record.twistUpper = def.twistUpper;
    s.record.frictionTorque = def.frictionTorque;
    s.record.coneDrive = def.drive;
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
    const bool driven = j.record->coneDrive.enabled;
    cacheFriction(j, a, b, f.rA, f.rB, driven);
    if (j.frictionValid) {
        applyFriction(j, a, b, f.rA, f.rB, j.impulse.friction + j.impulse.drive);
    } else {
        j.impulse.friction = {};
        j.impulse.drive = {};
    }
}

void ConeTwistJoint::solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    const ConeGeometry g = coneGeometry(j, f);
    JointImpulses& i = j.impulse;
    if (j.maxFrictionImpulse > 0) solveFrictionBlock(j, a, b, f.rA, f.rB);
    if (j.record->coneDrive.enabled) solveDrive(j, j.record->coneDrive, a, b, f, i.drive, ctx);
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
