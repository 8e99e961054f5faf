// Contact and sensor events, the joint rule, and no allocation per step with contacts.
#include <gtest/gtest.h>

#include "contacts/helpers.hpp"
#include "support/counting_allocator.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

// A ball dropped on the ground: exactly one begin event (when it lands), then
// lifting it away with setTransform gives exactly one end event.
TEST(Events, ContactBeginAndEnd) {
    World world;
    const BodyId ground = addGround(world);
    const BodyId ball = addSphere(world, {0, 1, 0}, Real(0.2));
    int begins = 0, ends = 0;
    for (int i = 0; i < 120; ++i) {
        world.step(kDt);
        for (const ContactEvent& e : world.contactBeginEvents()) {
            EXPECT_EQ(e.bodyA, ground);
            EXPECT_EQ(e.bodyB, ball);
            ++begins;
        }
        ends += static_cast<int>(world.contactEndEvents().size());
    }
    EXPECT_EQ(begins, 1);
    EXPECT_EQ(ends, 0);
    world.setTransform(ball, {0, 5, 0}, Quat{});
    for (int i = 0; i < 3; ++i) {
        world.step(kDt);
        ends += static_cast<int>(world.contactEndEvents().size());
    }
    EXPECT_EQ(ends, 1);
}

// A sensor reports a falling ball entering and leaving and never pushes it: the
// ball's fall stays exactly the integrator's free fall: semi-implicit Euler
// with n sub-steps of h gives y = y0 - g h^2 n (n + 1) / 2 (within 1 mm).
TEST(Events, SensorReportsOverlapAndDoesNotPush) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    BodyDef s;
    s.type = BodyType::Static;
    s.isSensor = true;
    s.shape = Shape::box({1, Real(0.5), 1});
    s.position = {0, 5, 0};
    const BodyId sensor = world.createBody(s);
    const BodyId ball = addSphere(world, {0, 8, 0}, Real(0.2));
    int begins = 0, ends = 0;
    for (int i = 0; i < 60; ++i) {
        world.step(kDt);
        for (const ContactEvent& e : world.sensorBeginEvents()) {
            EXPECT_EQ(e.bodyA, sensor);
            EXPECT_EQ(e.bodyB, ball);
            ++begins;
        }
        ends += static_cast<int>(world.sensorEndEvents().size());
    }
    EXPECT_EQ(begins, 1);
    EXPECT_EQ(ends, 1);
    const Real h = kDt / static_cast<Real>(def.substeps), n = 60 * static_cast<Real>(def.substeps);
    EXPECT_NEAR(world.position(ball).y, 8 - Real(9.81) * h * h * n * (n + 1) / 2, Real(1e-3));
    EXPECT_TRUE(world.contacts().empty());
}

// Two overlapping boxes joined by a joint don't push each other apart (zero
// gravity: they stay put); with collideConnected they do (momentum stays 0).
TEST(Events, JointedBodiesDoNotCollideUnlessAsked) {
    for (bool collide : {false, true}) {
        WorldDef def;
        def.gravity = {};
        World world(def);
        const BodyId a = addBox(world, {0, 0, 0});
        const BodyId b = addBox(world, {Real(0.8), 0, 0});
        JointDef j;
        j.type = JointType::Ball;
        j.bodyA = a;
        j.bodyB = b;
        j.anchor = {Real(0.4), 0, 0};
        j.collideConnected = collide;
        world.createJoint(j);
        run(world, 30);
        const Real gap = world.position(b).x - world.position(a).x;
        if (collide) {
            // The joint (solved since the joint solver landed) pins the boxes
            // overlapping; allowed to collide, they keep a contact.
            EXPECT_FALSE(world.contacts().empty());
        } else {
            EXPECT_NEAR(gap, Real(0.8), Real(1e-5));
        }
        EXPECT_NEAR(length(world.linearMomentum()), 0, Real(1e-4));
    }
}

// A settled box pile with contacts (and a ball rolling through it) steps
// without touching the heap.
TEST(Allocation, NoAllocationPerStepWithContacts) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    buildPyramid(world, 5);
    BodyDef d;
    d.shape = Shape::sphere(Real(0.3));
    d.position = {-6, Real(0.3), 0};
    d.linearVelocity = {2, 0, 0};
    world.createBody(d);
    run(world, 10);
    fulcrum::test::CountAllocations count;
    run(world, 60);
    EXPECT_EQ(count.stop(), 0);
    EXPECT_FALSE(world.contacts().empty());
}
