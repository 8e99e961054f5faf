#pragma once
// What every joint type's file uses to turn its definition (fulcrum/joint.hpp:
// BallJointDef, HingeJointDef...) into a stored joint, and to report on one:
// the poses of the two ends, the result of a creation (JointSetup), the view
// of a stored joint the solver prepares from (StoredJoint) and the one the
// world's queries measure (JointPose), and the checks the types share.
// joint_types.hpp lists the types; src/world/world_joints.cpp stores joints.
#include <limits>
#include <string>

#include "dynamics/validation.hpp"
#include "fulcrum/joint.hpp"

namespace fulcrum::detail {

// A joint end's pose: its centre of mass and orientation (the static world:
// `world`, and local is world space).
struct EndPose {
    Vec3 com;
    Quat q;
    bool world = true;
    Vec3 localPoint(const Vec3& p) const { return world ? p : inverseRotate(q, p - com); }
    Vec3 localAxis(const Vec3& v) const { return world ? v : inverseRotate(q, v); }
    Vec3 worldPoint(const Vec3& local) const { return world ? local : com + rotate(q, local); }
    Vec3 worldAxis(const Vec3& local) const { return world ? local : rotate(q, local); }
};

struct JointEnds {
    EndPose a, b;
};

// The poses of a and b now, through the public API, for the fromWorld
// helpers (`where` names the helper in the error for a stale body; a null
// `a` is the static world).
JointEnds jointEnds(const World& world, BodyId a, BodyId b, const char* where);
// A fromWorld helper's world axis, normalised (a zero or non-finite one is an error).
Vec3 worldAxisArgument(const Vec3& axis, const char* where);

// A joint as a type's setup() makes it from its definition.
struct JointSetup {
    // World::jointDef's view of it: the type and its fields, anchors and axis
    // in world space at creation.
    JointDef record;
    Vec3 localAnchorA, localAnchorB;  // from each centre of mass, body axes (world point for the world)
    Vec3 localAxisA{0, 1, 0}, localAxisB{0, 1, 0};
    Real minLength = 0, maxLength = 0, restLength = 0;  // distance joints, resolved
    Quat localFrameA;                 // six-DOF: the joint frame in A's body axes
};

// A joint whose anchors meet: both local anchors, and the record's world anchor (A's).
inline void setPointAnchors(JointSetup& s, const JointEnds& ends, const Vec3& localA, const Vec3& localB) {
    s.localAnchorA = localA;
    s.localAnchorB = localB;
    s.record.anchor = ends.a.worldPoint(localA);
}
// A joint with an axis: both local axes, and the record's world axis (A's).
inline void setAxes(JointSetup& s, const JointEnds& ends, const Vec3& localA, const Vec3& localB) {
    s.localAxisA = localA;
    s.localAxisB = localB;
    s.record.axis = ends.a.worldAxis(localA);
}
// A type without an axis: each body's local image of the world's y axis (JointDef's default axis).
inline void setDefaultAxes(JointSetup& s, const JointEnds& ends) {
    s.localAxisA = ends.a.localAxis({0, 1, 0});
    s.localAxisB = ends.b.localAxis({0, 1, 0});
}

// The record's common part (name, bodies, break thresholds, collideConnected).
JointDef baseRecord(const JointDefBase& def, JointType type);
// JointDef's common part as a per-type definition's base.
JointDefBase baseOf(const JointDef& def);

// What the solver prepares a joint from each step.
struct StoredJoint {
    const JointDef& def;
    Real minLength, maxLength, restLength;
};

// What World::jointError and World::jointPosition measure a joint by: the
// anchors' separation, and where to read the rest (pointers: most types
// read only d, and the queries read nothing they don't need).
struct JointPose {
    Vec3 d;                        // anchor B - anchor A, world
    const Quat* qA;                // orientations (qA null: A is the static world)
    const Quat* qB;
    const Vec3* localAxisA;
    const Quat* relativeRotation;  // the rest pose
    const Real* minLength;         // distance joints, resolved
    const Real* maxLength;
    const Quat* localFrameA;       // six-DOF
    const SixDofAxes* sixDofAxes;  // six-DOF
    Quat orientationA() const { return qA != nullptr ? *qA : Quat{}; }
    Vec3 axisA() const { return qA != nullptr ? rotate(*qA, *localAxisA) : *localAxisA; }
};

// ---- the free-axis types (hinge, slider): an anchor, an axis, limits, a
// motor and a spring about or along the axis. The halves their definitions
// share; each type adds its own fields (the hinge's friction) after them.

// JointDef's axis-joint fields into a per-type definition (anchors and axis
// as each body's local image of JointDef's world ones).
template <class AxisDef>
AxisDef axisDefFromJointDef(const JointDef& def, const JointEnds& ends) {
    AxisDef d;
    static_cast<JointDefBase&>(d) = baseOf(def);
    d.localAnchorA = ends.a.localPoint(def.anchor);
    d.localAnchorB = ends.b.localPoint(def.anchor);
    const Vec3 axis = requireDirection({"joint", def.name}, "axis", def.axis);
    d.localAxisA = ends.a.localAxis(axis);
    d.localAxisB = ends.b.localAxis(axis);
    d.hasLimits = def.hasLimits;
    d.lowerLimit = def.lowerLimit;
    d.upperLimit = def.upperLimit;
    d.motor = def.motor;
    d.spring = def.spring;
    return d;
}

// Checks the axis-joint fields (limits as angles or as lengths) and makes
// the joint's setup from them.
template <class AxisDef>
JointSetup setupAxisJoint(const AxisDef& def, const Subject& who, const JointEnds& ends, JointType type, bool angular);

// ---- checks shared by the types (errors name the joint and the field)

// Finite or +infinity, and positive (break thresholds: infinity means unbreakable).
void requireBreakThreshold(const Subject& who, const char* field, Real v);
// Finite limits; lower <= upper when enabled; within [-pi, pi] for an angle.
void validateLimits(const Subject& who, bool enabled, Real lower, Real upper, bool angle);
void validateMotor(const Subject& who, const JointMotor& m);
void validateSpring(const Subject& who, const JointSpring& s);
// A position drive's force limit: >= 0, +infinity: none (`field` names it).
void requireForceLimit(const Subject& who, const std::string& field, Real v);
// A finite unit vector (length within 1e-4 of 1: a local axis is used as given).
void requireUnitAxis(const Subject& who, const char* field, const Vec3& v);
void validateFrictionTorque(const Subject& who, Real frictionTorque);
// Cone-twist ranges: swing in (0, pi], twist lower <= upper within [-pi, pi].
void validateConeTwistRanges(const Subject& who, Real swingLimit, Real twistLower, Real twistUpper);
// Cone-twist drive: a finite unit target, stiffness >= 0 (or +infinity), damping >= 0, maxTorque > 0.
void validateConeTwistDrive(const Subject& who, const ConeTwistDrive& drive);

template <class AxisDef>
JointSetup setupAxisJoint(const AxisDef& def, const Subject& who, const JointEnds& ends, JointType type, bool angular) {
    requireFinite(who, "localAnchorA", def.localAnchorA);
    requireFinite(who, "localAnchorB", def.localAnchorB);
    requireUnitAxis(who, "localAxisA", def.localAxisA);
    requireUnitAxis(who, "localAxisB", def.localAxisB);
    validateLimits(who, def.hasLimits, def.lowerLimit, def.upperLimit, angular);
    validateMotor(who, def.motor);
    validateSpring(who, def.spring);
    JointSetup s;
    s.record = baseRecord(def, type);
    setPointAnchors(s, ends, def.localAnchorA, def.localAnchorB);
    setAxes(s, ends, def.localAxisA, def.localAxisB);
    s.record.hasLimits = def.hasLimits;
    s.record.lowerLimit = def.lowerLimit;
    s.record.upperLimit = def.upperLimit;
    s.record.motor = def.motor;
    s.record.spring = def.spring;
    return s;
}

}  // namespace fulcrum::detail
