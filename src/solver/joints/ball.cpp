// Ball-and-socket: the anchors of A and B coincide (3 rows, solved as a 3x3 block),
// plus optional dry friction against relative spin.
#include "solver/joints/ball.hpp"

namespace fulcrum::detail {

// ---- definition

BallJointDef BallJoint::fromJointDef(const JointDef& def, const JointEnds& ends) {
    BallJointDef d;
    static_cast<JointDefBase&>(d) = baseOf(def);
    d.localAnchorA = ends.a.localPoint(def.anchor);
    d.localAnchorB = ends.b.localPoint(def.anchor);
    d.frictionTorque = def.frictionTorque;
    return d;
}

JointSetup BallJoint::setup(const Def& def, const Subject& who, const JointEnds& ends) {
    requireFinite(who, "localAnchorA", def.localAnchorA);
    requireFinite(who, "localAnchorB", def.localAnchorB);
    validateFrictionTorque(who, def.frictionTorque);
    JointSetup s;
    s.record = baseRecord(def, kType);
    setPointAnchors(s, ends, def.localAnchorA, def.localAnchorB);
    setDefaultAxes(s, ends);
    s.record.frictionTorque = def.frictionTorque;
    return s;
}

// ---- solver

void BallJoint::warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    if (!j.direct) cachePointMass(j, a, b, f.rA, f.rB);
    applyPoint(a, b, f.rA, f.rB, j.impulse.linear);
    cacheFriction(j, a, b, f.rA, f.rB);
    if (j.frictionValid) {
        applyFriction(j, a, b, f.rA, f.rB, j.impulse.friction);
    } else {
        j.impulse.friction = {};
    }
}

void BallJoint::solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    // The tree solver has the point rows (JointSolver skips a tree's frictionless ball joints).
    if (j.direct && !j.frictionValid) return;
    const JointFrame& f = currentFrame(j, a, b, ctx);
    solveFrictionBlock(j, a, b, f.rA, f.rB);
    if (!j.direct && j.pointMassValid) solvePointBlock(a, b, f.rA, f.rB, f.d, j.impulse.linear, ctx, j.pointMass);
}

}  // namespace fulcrum::detail

namespace fulcrum {

BallJointDef BallJointDef::fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor) {
    const detail::JointEnds ends = detail::jointEnds(world, a, b, "BallJointDef::fromWorld");
    BallJointDef d;
    d.bodyA = a;
    d.bodyB = b;
    d.localAnchorA = ends.a.localPoint(anchor);
    d.localAnchorB = ends.b.localPoint(anchor);
    return d;
}

}  // namespace fulcrum
