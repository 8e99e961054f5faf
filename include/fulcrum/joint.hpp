#pragma once
// Joints: constraints between two bodies (or a body and the static world),
// solved by the same iterative solver as contacts.
#include <array>
#include <cstdint>
#include <limits>
#include <string>

#include "fulcrum/body.hpp"

namespace fulcrum {

enum class JointType : std::uint8_t { Ball, Hinge, Slider, Distance, Fixed, ConeTwist, SixDof };
const char* toString(JointType type);


struct JointMotor {
    bool enabled = false;
    Real speed = 0;       // hinge: rad/s; slider: m/s
    Real maxForce = 0;    // hinge: N m; slider: N
};

// Spring towards a target angle (hinge) or position along the axis (slider):
// the position drive. Its force is clamped to maxForce (as the motor's), so a
// stiff spring is "a target held with at most maxForce" (docs/joints.md).
struct JointSpring {
    bool enabled = false;
    Real target = 0;
    Real stiffness = 0;   // N m/rad or N/m
    Real damping = 0;
    Real maxForce = std::numeric_limits<Real>::infinity();  // N m or N, >= 0; +infinity: unlimited
};

// ---- six-degree-of-freedom joint: its axes (docs/joints.md, "Six-DOF")
//
// The joint frame sits at the anchor; its three linear axes are x, y, z of
// the frame fixed in body A, its three angles are B's frame turned against
// A's as intrinsic x-y-z Euler angles (rx about A's x, then ry about the
// turned y, then rz about B's z). Each axis is free, limited to [lower,
// upper] or locked at 0 (its position at creation), and has a motor and a
// spring like a hinge's or slider's.

enum class AxisMode : std::uint8_t { Free, Limited, Locked };
const char* toString(AxisMode mode);

// Indices into the six axes: linear x, y, z, then angular x, y, z.
enum SixDofAxisIndex : int { kAxisX = 0, kAxisY = 1, kAxisZ = 2, kAxisRotX = 3, kAxisRotY = 4, kAxisRotZ = 5 };
inline constexpr int kSixDofAxes = 6;

struct SixDofAxis {
    AxisMode mode = AxisMode::Locked;
    Real lower = 0, upper = 0;   // Limited: m (linear), rad (angular: rx, rz within [-pi, pi]; ry within (-pi/2, pi/2))
    JointMotor motor;            // m/s and N, or rad/s and N m
    JointSpring spring;          // target m or rad; N/m or N m/rad; N s/m or N m s/rad
};
using SixDofAxes = std::array<SixDofAxis, kSixDofAxes>;

// Per-axis read-out of a six-DOF joint (World::sixDofReading), axes as above:
// position m / rad, velocity m/s / rad/s, effort N / N m (the joint's reaction
// on B along each axis; angular: about each Euler angle's own axis).
struct SixDofReading {
    std::array<Real, kSixDofAxes> position{}, velocity{}, effort{};
};

// Cone-twist drive: pulls B towards a target orientation relative to A, as a
// spring-damper about the rotation between them (PD), or, with infinite
// stiffness, holds the target as rigidly as the joint's other rows; either
// way with a torque up to maxTorque.
struct ConeTwistDrive {
    bool enabled = false;
    Quat target;              // B's rotation from its rest pose relative to A, in A's body axes (identity: the rest pose)
    Real stiffness = 0;       // N m/rad, >= 0; +infinity: rigid
    Real damping = 0;         // N m s/rad, >= 0
    Real maxTorque = std::numeric_limits<Real>::infinity();  // N m, > 0
};

struct JointDef {
    std::string name;
    JointType type = JointType::Ball;
    BodyId bodyA = kWorldBody;      // null: the static world
    BodyId bodyB;
    Vec3 anchor;                    // world space at creation
    Vec3 anchorB;                   // distance joints: second anchor, world space at creation
    Vec3 axis{0, 1, 0};             // hinge, slider, cone-twist (twist axis); world space at creation

    bool hasLimits = false;
    Real lowerLimit = 0;            // hinge: rad; slider: m
    Real upperLimit = 0;
    JointMotor motor;
    JointSpring spring;

    // Distance joints: a rod when min == max, a rope when min = 0, max = L.
    // Negative values mean "the distance between the anchors at creation".
    Real minLength = -1;
    Real maxLength = -1;
    Real stiffness = 0;             // > 0 makes the distance joint a soft spring (N/m)
    Real damping = 0;               // N s/m

    // Cone-twist: swing cone half-angle and twist range, radians.
    Real swingLimit = Real(0.7853982);
    Real twistLower = Real(-0.7853982);
    Real twistUpper = Real(0.7853982);
    ConeTwistDrive coneDrive;       // cone-twist: a target orientation

    // Six-DOF: the joint frame's x axis is `axis`, its y axis `axisY` (made
    // perpendicular to x; zero: world y, or world z when x is near y), world space at creation;
    // and the six axes' modes, limits, motors and springs.
    Vec3 axisY;
    SixDofAxes axes;

    // Dry friction in the joint (N m): a torque up to this opposes the relative
    // spin of B against A. Ball and cone-twist: about any axis; hinge: about its
    // axis when the motor is off (a motor at speed 0 does the same). Ragdolls
    // use it so limbs stop instead of swinging for ever. Slider: a force (N)
    // along its axis when the motor is off. >= 0; 0: frictionless.
    Real frictionTorque = 0;

    Real breakForce = std::numeric_limits<Real>::infinity();   // N; the joint breaks above it
    Real breakTorque = std::numeric_limits<Real>::infinity();  // N m
    bool collideConnected = false;
};

// ---- Per-type definitions (World::createJoint overloads)
//
// Each joint type has its own definition holding only the fields it uses,
// with anchors and axes in each body's local frame: body axes, measured from
// the body's centre of mass (World::localCenterOfMass; the body origin for a
// shape centred on it), as JointDef's world-space values are stored. For the
// static world (bodyA null) "local" is world space. Users who think in world
// space build a definition with fromWorld, from the bodies' poses now.
// Angles (hinge and cone-twist twist, spring targets, the fixed joint's and
// slider's locked rotation) are measured from the bodies' relative
// orientation when the joint is created. JointDef (above) stays: it creates
// the same joint through the per-type definition of its type.

class World;

// What every joint has.
struct JointDefBase {
    std::string name;
    BodyId bodyA = kWorldBody;      // null: the static world
    BodyId bodyB;
    Real breakForce = std::numeric_limits<Real>::infinity();   // N; the joint breaks above it
    Real breakTorque = std::numeric_limits<Real>::infinity();  // N m
    bool collideConnected = false;
};

// Ball-and-socket: the anchors coincide; free rotation.
struct BallJointDef : JointDefBase {
    Vec3 localAnchorA, localAnchorB;
    Real frictionTorque = 0;        // N m, >= 0 (JointDef::frictionTorque)
    static BallJointDef fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor);
};

// Hinge (revolute): the anchors coincide and B turns only about the axis.
struct HingeJointDef : JointDefBase {
    Vec3 localAnchorA, localAnchorB;
    Vec3 localAxisA{0, 1, 0}, localAxisB{0, 1, 0};  // unit
    bool hasLimits = false;
    Real lowerLimit = 0, upperLimit = 0;  // rad, within [-pi, pi]
    JointMotor motor;                     // rad/s, N m
    JointSpring spring;                   // target rad, N m/rad, N m s/rad
    Real frictionTorque = 0;              // N m, about the axis while the motor is off
    static HingeJointDef fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor, Vec3 axis);
};

// Slider (prismatic): B keeps its orientation relative to A and its anchor
// moves only along A's axis. Position 0 at creation.
struct SliderJointDef : JointDefBase {
    Vec3 localAnchorA, localAnchorB;
    Vec3 localAxisA{0, 1, 0}, localAxisB{0, 1, 0};  // unit
    bool hasLimits = false;
    Real lowerLimit = 0, upperLimit = 0;  // m
    JointMotor motor;                     // m/s, N
    JointSpring spring;                   // target m, N/m, N s/m
    Real frictionForce = 0;               // N, >= 0: dry friction along the axis while the motor is off (JointDef::frictionTorque)
    static SliderJointDef fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor, Vec3 axis);
};

// Distance between two anchors: a rod (minLength == maxLength), a rope
// (minLength 0, maxLength L: it only pulls) or a soft spring (stiffness or
// damping > 0) towards `length`, its min / max still enforced.
struct DistanceJointDef : JointDefBase {
    Vec3 localAnchorA, localAnchorB;
    Real length = 0;       // rest length (m, >= 0; clamped to the limits)
    Real minLength = 0;    // m, >= 0
    Real maxLength = 0;    // m, >= minLength; +infinity: no upper limit
    Real stiffness = 0;    // N/m; > 0 makes it a soft spring
    Real damping = 0;      // N s/m
    // A rod: length, minLength and maxLength all the anchors' distance now.
    static DistanceJointDef fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchorA, Vec3 anchorB);
};

// Fixed (weld): the anchors coincide and B keeps its orientation relative to A.
struct FixedJointDef : JointDefBase {
    Vec3 localAnchorA, localAnchorB;
    static FixedJointDef fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor);
};

// Cone-twist (ragdoll shoulder): a ball joint whose twist axis (B's) stays in a
// cone about A's, and whose twist about it is limited.
struct ConeTwistJointDef : JointDefBase {
    Vec3 localAnchorA, localAnchorB;
    Vec3 localAxisA{0, 1, 0}, localAxisB{0, 1, 0};  // unit twist axes
    Real swingLimit = Real(0.7853982);   // cone half-angle, rad, (0, pi]
    Real twistLower = Real(-0.7853982);  // rad, within [-pi, pi]
    Real twistUpper = Real(0.7853982);
    Real frictionTorque = 0;             // N m, >= 0
    ConeTwistDrive drive;                // off by default
    static ConeTwistJointDef fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor, Vec3 axis);
};

// Six degrees of freedom: each linear and angular axis of the joint frame
// free, limited or locked, with a motor and a spring (see SixDofAxis above).
// Every axis locked is a fixed joint; all three linear axes locked, the
// anchors meet and the tree solver may take the point rows.
struct SixDofJointDef : JointDefBase {
    Vec3 localAnchorA, localAnchorB;
    Quat localFrameA;   // the joint frame in A's body axes (B's: the same frame at creation)
    SixDofAxes axes;    // all locked by default
    // The frame from world axes now: x = axis, y = axisY made perpendicular
    // (zero: world y, or world z when x is near y).
    static SixDofJointDef fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor, Vec3 axis = {1, 0, 0},
                                    Vec3 axisY = {});
};

}  // namespace fulcrum
