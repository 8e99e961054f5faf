#pragma once
// RigidCollider: what the particle solver needs from the rigid-body world, and
// nothing more, so the particle module never depends on World internals. The
// World implements it over its bodies and broad phase; tests implement a tiny
// analytic one.
//
// Timing contract (how World::step uses it): the World advances its bodies
// over [t, t + dt], then calls ParticleWorld::step(dt, collider). During the
// particle sub-steps a body moves along the straight path from its pose at t
// (previousTransform) to its pose at t + dt (transform), plus its response to
// the particles' pushes; the particles push it through applyImpulse (momentum
// exactly opposite to what the particles received) and applyDisplacement (the
// position change that push caused within the sub-steps, as in PBD), which the
// next rigid step continues from.
#include <cstdint>

#include "fulcrum/math.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {

// A body's state as the particles see it.
struct RigidBodyState {
    Transform transform;            // body origin frame (the shape's frame), world space
    // The pose at the start of the rigid step just taken (World::previousTransform).
    // The particle sub-steps see the body move from here to `transform`, so the
    // body's motion is spread over the sub-steps as the particles' is.
    Transform previousTransform;
    Vec3 centerOfMass;              // world space
    Vec3 linearVelocity;            // of the centre of mass
    Vec3 angularVelocity;
    Real inverseMass = 0;           // 0 for static and kinematic bodies: particles cannot push them
    Mat3 inverseInertia = Mat3::zero();  // world frame, about the centre of mass
    Real friction = Real(0.6);
};

// Receives the shapes found by RigidCollider::queryShapes.
class RigidShapeVisitor {
public:
    virtual void visit(std::uint32_t bodyIndex, const Shape& shape, const Transform& shapeTransform) = 0;

protected:
    ~RigidShapeVisitor() = default;
};

class RigidCollider {
public:
    virtual ~RigidCollider() = default;
    // True if `bodyIndex` names a live body (attachments are checked with it).
    virtual bool isValidBody(std::uint32_t bodyIndex) const = 0;
    virtual RigidBodyState bodyState(std::uint32_t bodyIndex) const = 0;
    // Every shape whose world bounds overlap `bounds`, in a deterministic order.
    // The Shape references must stay valid until the end of the particle step.
    virtual void queryShapes(const AABB& bounds, RigidShapeVisitor& visitor) const = 0;
    // Changes the body's velocities at once: linear impulse (N s) through the
    // centre of mass and angular impulse (N m s) about it. Ignored for static
    // and kinematic bodies.
    virtual void applyImpulse(std::uint32_t bodyIndex, const Vec3& linearImpulse, const Vec3& angularImpulse) = 0;
    // Moves a dynamic body by how far the particles pushed it during their
    // sub-steps: the centre of mass by `translation`, the orientation by
    // `rotation` (composed on the left, about the centre of mass). Without it
    // the push would be lost and re-corrected next step with a 1/h gain - the
    // positional error would turn into energy (measured: a 2 kg ball on a rope
    // was flung 0.5 m up within a second).
    virtual void applyDisplacement(std::uint32_t bodyIndex, const Vec3& translation, const Quat& rotation) = 0;
};

}  // namespace fulcrum
