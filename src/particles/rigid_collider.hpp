#pragma once
// RigidCollider: what the particle solver needs from the rigid-body world, and
// nothing more, so the particle module never depends on World internals. The
// World implements it over its bodies and broad phase; tests implement a tiny
// analytic one.
//
// Timing contract (how World::step uses it): the World advances its bodies
// over [t, t + dt], then calls ParticleWorld::step(dt, collider). During the
// particle step the bodies are seen at their end-of-step pose; the particles
// push them through applyImpulse (momentum exactly opposite to what the
// particles received), which the next rigid step integrates.
#include <cstdint>

#include "fulcrum/math.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {

// A body's state as the particles see it.
struct RigidBodyState {
    Transform transform;            // body origin frame (the shape's frame), world space
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
};

}  // namespace fulcrum
