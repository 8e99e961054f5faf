#include "bullet_scenes.hpp"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

namespace bench {

RunResult runBullet(const SceneSpec& scene) {
    RunResult r;
    r.ran = true;
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
    world.setGravity(btVector3(0, -9.81f, 0));

    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btDefaultMotionState>> states;
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    // Bullet combines friction as the product: each body gets sqrt(mu) for a pair value mu.
    const float friction = std::sqrt(scene.friction);
    btCollisionShape* unitBox = nullptr;
    btCollisionShape* unitSphere = nullptr;
    for (const BodySpec& b : scene.bodies) {
        btCollisionShape* shape = nullptr;
        if (b.kind == BodySpec::Kind::Sphere) {
            if (unitSphere == nullptr) {
                shapes.push_back(std::make_unique<btSphereShape>(b.hx));
                unitSphere = shapes.back().get();
            }
            shape = unitSphere;
        } else if (!b.isStatic && b.hx == 0.5f && b.hy == 0.5f && b.hz == 0.5f) {
            if (unitBox == nullptr) {
                shapes.push_back(std::make_unique<btBoxShape>(btVector3(0.5f, 0.5f, 0.5f)));
                unitBox = shapes.back().get();
            }
            shape = unitBox;
        } else {
            shapes.push_back(std::make_unique<btBoxShape>(btVector3(b.hx, b.hy, b.hz)));
            shape = shapes.back().get();
        }
        const float mass = b.isStatic ? 0.0f : b.mass;
        btVector3 inertia(0, 0, 0);
        if (mass > 0) shape->calculateLocalInertia(mass, inertia);
        btTransform xf;
        xf.setIdentity();
        xf.setOrigin(btVector3(b.x, b.y, b.z));
        states.push_back(std::make_unique<btDefaultMotionState>(xf));
        btRigidBody::btRigidBodyConstructionInfo info(mass, states.back().get(), shape, inertia);
        info.m_friction = friction;
        info.m_restitution = 0;
        bodies.push_back(std::make_unique<btRigidBody>(info));
        if (!scene.sleeping && mass > 0) bodies.back()->setActivationState(DISABLE_DEACTIVATION);
        world.addRigidBody(bodies.back().get());
    }

    std::vector<btVector3> start;
    for (const auto& b : bodies) start.push_back(b->getCenterOfMassPosition());
    r.stepMs.reserve(static_cast<std::size_t>(scene.steps));
    for (int i = 0; i < scene.steps; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        world.stepSimulation(scene.dt, 0, scene.dt);
        const auto t1 = std::chrono::steady_clock::now();
        r.stepMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }

    for (std::size_t i = 0; i < bodies.size(); ++i) {
        if (scene.bodies[i].isStatic) continue;
        const btVector3 p = bodies[i]->getCenterOfMassPosition();
        const double dx = p.x() - start[i].x(), dz = p.z() - start[i].z();
        r.drift = std::max(r.drift, std::sqrt(dx * dx + dz * dz));
        if (bodies[i]->getActivationState() == ISLAND_SLEEPING) ++r.asleep;
    }
    if (scene.topIndex >= 0) {
        const auto top = static_cast<std::size_t>(scene.topIndex);
        r.sink = start[top].y() - bodies[top]->getCenterOfMassPosition().y();
    }
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
        const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
        for (int c = 0; c < manifold->getNumContacts(); ++c) {
            r.penetration = std::max(r.penetration, static_cast<double>(-manifold->getContactPoint(c).getDistance()));
        }
    }
    for (const auto& b : bodies) world.removeRigidBody(b.get());
    return r;
}

}  // namespace bench
