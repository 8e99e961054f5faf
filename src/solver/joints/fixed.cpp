// Fixed (weld): the anchors coincide and B keeps its rest orientation relative
// to A (3 linear + 3 angular rows, two 3x3 blocks). The angular block goes
// first so the point block, solved last, has the final word on the anchors,
// the error users see.
#include "solver/joints/fixed.hpp"

namespace fulcrum::detail {

// ---- definition

FixedJointDef FixedJoint::fromJointDef(const JointDef& def, const JointEnds& ends) {
    FixedJointDef d;
    static_cast<JointDefBase&>(d) = baseOf(def);
    d.localAnchorA = ends.a.localPoint(def.anchor);
    d.localAnchorB = ends.b.localPoint(def.anchor);
    return d;
}

JointSetup FixedJoint::setup(const Def& def, const Subject& who, const JointEnds& ends) {
    requireFinite(who, "localAnchorA", def.localAnchorA);
    requireFinite(who, "localAnchorB", def.localAnchorB);
    JointSetup s;
    s.record = baseRecord(def, kType);
    setPointAnchors(s, ends, def.localAnchorA, def.localAnchorB);
    setDefaultAxes(s, ends);
    return s;
}

// ---- solver

void FixedJoint::warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    if (!j.direct) cachePointMass(j, a, b, f.rA, f.rB);
    applyPoint(a, b, f.rA, f.rB, j.impulse.linear);
    a.w -= a.invI * j.impulse.angular;
    b.w += b.invI * j.impulse.angular;
}

void FixedJoint::solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    solveAngularBlock(a, b, angularError(j, f.qA, f.qB), j.impulse.angular, ctx);
    if (!j.direct && j.pointMassValid) solvePointBlock(a, b, f.rA, f.rB, f.d, j.impulse.linear, ctx, j.pointMass);
}

}  // namespace fulcrum::detail

namespace fulcrum {

FixedJointDef FixedJointDef::fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor) {
    const detail::JointEnds ends = detail::jointEnds(world, a, b, "FixedJointDef::fromWorld");
    FixedJointDef d;
    d.bodyA = a;
    d.bodyB = b;
    d.localAnchorA = ends.a.localPoint(anchor);
    d.localAnchorB = ends.b.localPoint(anchor);
    return d;
}

}  // namespace fulcrum
