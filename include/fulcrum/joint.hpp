#pragma once
// Joints: constraints between two bodies (or a body and the static world),
// solved by the same iterative solver as contacts.
#include <cstdint>
#include <limits>
#include <string>

#include "fulcrum/body.hpp"

namespace fulcrum {

enum class JointType : std::uint8_t { Ball, Hinge, Slider, Distance, Fixed, ConeTwist };
const char* toString(JointType type);


struct JointMotor {
    bool enabled = false;
    Real speed = 0;       // hinge: rad/s; slider: m/s
    Real maxForce = 0;    // hinge: N m; slider: N
};

// Spring towards a target angle (hinge) or position along the axis (slider).
struct JointSpring {
    bool enabled = false;
    Real target = 0;
    Real stiffness = 0;   // N m/rad or N/m
    Real damping = 0;
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

    // Dry friction in the joint (N m): a torque up to this opposes the relative
    // spin of B against A. Ball and cone-twist: about any axis; hinge: about its
    // axis when the motor is off (a motor at speed 0 does the same). Ragdolls
    // use it so limbs stop instead of swinging for ever. >= 0; 0: frictionless.
    Real frictionTorque = 0;

    Real breakForce = std::numeric_limits<Real>::infinity();   // N; the joint breaks above it
    Real breakTorque = std::numeric_limits<Real>::infinity();  // N m
    bool collideConnected = false;
};

}  // namespace fulcrum
