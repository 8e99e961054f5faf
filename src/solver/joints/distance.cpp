// Distance joint between two anchors: a rod (min == max, one rigid-in-the-limit
// equality row), a rope (min 0, max L: one limit row that only pulls, so it
// goes slack), or a soft spring (stiffness / damping, implicit, towards the
// rest length) with its min / max still enforced as limit rows.
#include <algorithm>
#include <cmath>
#include <limits>

#include "solver/joints/distance.hpp"

namespace fulcrum::detail {

namespace {

// Unit direction A -> B and length; a degenerate (coincident) pair has no direction.
bool direction(const JointFrame& f, Vec3& n, Real& len) {
    len = length(f.d);
    if (len < Real(1e-6)) return false;
    n = f.d * (1 / len);
    return true;
}

}  // namespace

// ---- definition

DistanceJointDef DistanceJoint::fromJointDef(const JointDef& def, const JointEnds& ends) {
    DistanceJointDef d;
    static_cast<JointDefBase&>(d) = baseOf(def);
    d.localAnchorA = ends.a.localPoint(def.anchor);
    d.localAnchorB = ends.b.localPoint(def.anchorB);
    // JointDef's negative lengths (joint.hpp): the distance between its world
    // anchors, or for a soft joint no limit on that side.
    const Real d0 = distance(def.anchor, def.anchorB);
    const bool soft = def.stiffness > 0 || def.damping > 0;
    d.length = d0;
    d.minLength = def.minLength < 0 ? (soft ? 0 : d0) : def.minLength;
    d.maxLength = def.maxLength < 0 ? (soft ? std::numeric_limits<Real>::infinity() : d0) : def.maxLength;
    d.stiffness = def.stiffness;
    d.damping = def.damping;
    return d;
}

JointSetup DistanceJoint::setup(const Def& def, const Subject& who, const JointEnds& ends) {
    requireFinite(who, "localAnchorA", def.localAnchorA);
    requireFinite(who, "localAnchorB", def.localAnchorB);
    requireNonNegative(who, "length", def.length);
    requireNonNegative(who, "minLength", def.minLength);
    if (std::isnan(def.maxLength) || def.maxLength < 0) {
        fail(who, "maxLength", "must not be negative (+infinity: no limit), got " + formatReal(def.maxLength));
    }
    if (def.minLength > def.maxLength) {
        fail(who, "minLength", "(" + formatReal(def.minLength) + ") is above maxLength (" + formatReal(def.maxLength) + ")");
    }
    requireNonNegative(who, "stiffness", def.stiffness);
    requireNonNegative(who, "damping", def.damping);
    JointSetup s;
    s.record = baseRecord(def, kType);
    s.localAnchorA = def.localAnchorA;
    s.localAnchorB = def.localAnchorB;
    s.record.anchor = ends.a.worldPoint(def.localAnchorA);
    s.record.anchorB = ends.b.worldPoint(def.localAnchorB);
    setDefaultAxes(s, ends);
    s.record.minLength = def.minLength;
    s.record.maxLength = def.maxLength;
    s.record.stiffness = def.stiffness;
    s.record.damping = def.damping;
    s.minLength = def.minLength;
    s.maxLength = def.maxLength;
    s.restLength = std::clamp(def.length, def.minLength, def.maxLength);
    return s;
}

// ---- solver

void DistanceJoint::warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    Vec3 n;
    Real len = 0;
    if (!direction(f, n, len)) return;
    const JointImpulses& i = j.impulse;
    applyPoint(a, b, f.rA, f.rB, n * (i.axial + i.spring + i.lower - i.upper));
}

void DistanceJoint::solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    Vec3 n;
    Real len = 0;
    if (!direction(f, n, len)) return;
    const JointRow row = linearRow(n, f.rA, f.rB);
    JointImpulses& i = j.impulse;
    if (j.rigidDistance) {
        solveEqualityRow(row, a, b, len - j.restLength, i.axial, ctx);
        return;
    }
    if (j.spring) solveSpringRow(row, a, b, len - j.restLength, j.springBias, j.springGamma, i.spring);
    if (j.lower > 0) solveLimitRow(row, a, b, len - j.lower, i.lower, ctx);
    if (j.upper < std::numeric_limits<Real>::infinity()) {
        const JointRow pull{-row.linear, -row.angularA, -row.angularB};
        solveLimitRow(pull, a, b, j.upper - len, i.upper, ctx);
    }
}

}  // namespace fulcrum::detail

namespace fulcrum {

DistanceJointDef DistanceJointDef::fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchorA, Vec3 anchorB) {
    const detail::JointEnds ends = detail::jointEnds(world, a, b, "DistanceJointDef::fromWorld");
    DistanceJointDef d;
    d.bodyA = a;
    d.bodyB = b;
    d.localAnchorA = ends.a.localPoint(anchorA);
    d.localAnchorB = ends.b.localPoint(anchorB);
    d.length = d.minLength = d.maxLength = distance(anchorA, anchorB);
    return d;
}

}  // namespace fulcrum
