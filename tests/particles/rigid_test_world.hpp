#pragma once
// A minimal rigid world implementing RigidCollider for the particle tests:
// static and dynamic bodies with one shape each, no rigid-rigid collisions;
// dynamic bodies move ballistically (symplectic Euler) when the test says so.
#include <vector>

#include "particles/rigid_collider.hpp"

namespace fulcrum::test_support {

struct TestBody {
    Shape shape;
    Transform transform;
    Transform previousTransform;  // at the start of the last integrate()
    Vec3 linearVelocity, angularVelocity;
    Real inverseMass = 0;
    Mat3 localInverseInertia = Mat3::zero();
    Real friction = Real(0.6);
    Vec3 receivedLinearImpulse;   // sum of what the particles applied
    Vec3 receivedAngularImpulse;
};

class TestRigidWorld final : public RigidCollider {
public:
    std::vector<TestBody> bodies;

    std::uint32_t addStatic(const Shape& shape, const Transform& xf = {}, Real friction = Real(0.6)) {
        TestBody b;
        b.shape = shape;
        b.transform = xf;
        b.previousTransform = xf;
        b.friction = friction;
        bodies.push_back(b);
        return static_cast<std::uint32_t>(bodies.size() - 1);
    }
    std::uint32_t addDynamic(const Shape& shape, const Transform& xf, Real mass, Real friction = Real(0.6)) {
        TestBody b;
        b.shape = shape;
        b.transform = xf;
        b.previousTransform = xf;
        b.friction = friction;
        const MassProperties mp = shape.massProperties(1);
        b.inverseMass = 1 / mass;
        b.localInverseInertia = inverse(mp.inertia * (mass / mp.mass));
        bodies.push_back(b);
        return static_cast<std::uint32_t>(bodies.size() - 1);
    }

    bool isValidBody(std::uint32_t i) const override { return i < bodies.size(); }
    RigidBodyState bodyState(std::uint32_t i) const override {
        const TestBody& b = bodies[i];
        RigidBodyState s;
        s.transform = b.transform;
        s.previousTransform = b.previousTransform;
        s.centerOfMass = b.transform.p;  // the test shapes are centred on their origin
        s.linearVelocity = b.linearVelocity;
        s.angularVelocity = b.angularVelocity;
        s.inverseMass = b.inverseMass;
        const Mat3 r = toMat3(b.transform.q);
        s.inverseInertia = r * b.localInverseInertia * transpose(r);
        s.friction = b.friction;
        return s;
    }
    void queryShapes(const AABB& bounds, RigidShapeVisitor& visitor) const override {
        for (std::uint32_t i = 0; i < bodies.size(); ++i) {
            if (overlaps(bodies[i].shape.bounds(bodies[i].transform), bounds)) {
                visitor.visit(i, bodies[i].shape, bodies[i].transform);
            }
        }
    }
    void applyImpulse(std::uint32_t i, const Vec3& linear, const Vec3& angular) override {
        TestBody& b = bodies[i];
        b.receivedLinearImpulse += linear;
        b.receivedAngularImpulse += angular;
        b.linearVelocity += linear * b.inverseMass;
        b.angularVelocity += bodyState(i).inverseInertia * angular;
    }
    void applyDisplacement(std::uint32_t i, const Vec3& translation, const Quat& rotation) override {
        TestBody& b = bodies[i];  // centre of mass = origin for the test shapes
        b.transform.p += translation;
        b.transform.q = normalize(rotation * b.transform.q);
    }
    // Advances the dynamic bodies (gravity g) over dt.
    void integrate(Real dt, const Vec3& g) {
        for (TestBody& b : bodies) {
            b.previousTransform = b.transform;
            if (b.inverseMass == 0) continue;
            b.linearVelocity += g * dt;
            b.transform.p += b.linearVelocity * dt;
            b.transform.q = integrateRotation(b.transform.q, b.angularVelocity, dt);
        }
    }
};

}  // namespace fulcrum::test_support
