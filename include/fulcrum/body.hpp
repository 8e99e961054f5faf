#pragma once
// Rigid bodies: handles and the definition struct used to create them.
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>

#include "fulcrum/id.hpp"
#include "fulcrum/math.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {

enum class BodyType : std::uint8_t { Static, Kinematic, Dynamic };
const char* toString(BodyType type);

inline constexpr BodyId kWorldBody{};  // "no body": the static world, in joints and springs

// Collision filtering: A and B collide when (A.category & B.mask) and
// (B.category & A.mask) are both non-zero, unless they share a group: a
// positive shared group always collides, a negative one never does.
struct CollisionFilter {
    std::uint32_t category = 1;
    std::uint32_t mask = 0xFFFFFFFFu;
    std::int32_t group = 0;
};

struct BodyDef {
    std::string name;                 // optional; used in errors, events and outputs
    BodyType type = BodyType::Dynamic;
    Shape shape;                      // default: unit sphere
    // Mass: if `mass` > 0 it is used (inertia scaled from the shape's);
    // otherwise mass = density * volume. Dynamic bodies need a positive result.
    Real mass = 0;
    Real density = 1000;
    // Optional inertia tensor about the centre of mass, in body axes, overriding the shape's.
    std::optional<Mat3> inertia;
    // Optional centre of mass in the shape's frame, overriding the shape's
    // centroid (dynamic bodies; a robot link's inertial origin). Give it with
    // `mass` and `inertia`: the inertia is taken about this point as given.
    std::optional<Vec3> centerOfMass;

    Vec3 position;                    // of the body origin (the shape's frame), world space
    Quat orientation;
    Vec3 linearVelocity;              // of the centre of mass
    Vec3 angularVelocity;

    Real friction = Real(0.6);
    Real restitution = 0;
    Real rollingResistance = 0;       // dimensionless; resists rolling of round shapes
    Real linearDamping = 0;           // 1/s: v *= 1 / (1 + h c) each (sub-)step
    Real angularDamping = 0;
    Real linearDrag = 0;              // N s/m:   F = -b v
    Real quadraticDrag = 0;           // N s²/m²: F = -c |v| v
    Real gravityScale = 1;

    CollisionFilter filter;
    bool isSensor = false;            // reports overlaps, never pushes
    bool isBullet = false;            // continuous collision against dynamic bodies too
    bool allowSleep = true;
    bool awake = true;
};

// State of a body handed to a custom force callback.
struct BodyKinematics {
    Vec3 position;          // centre of mass, world
    Quat orientation;
    Vec3 linearVelocity;
    Vec3 angularVelocity;
    Real mass = 0;
    Real time = 0;          // world time at this evaluation
};

struct Wrench {
    Vec3 force;             // applied at the centre of mass
    Vec3 torque;
};

// Custom force (e.g. a central inverse-square field). Called at every force
// evaluation of the integrator; must be deterministic and not touch the World.
using ForceCallback = std::function<Wrench(const BodyKinematics&)>;

}  // namespace fulcrum
