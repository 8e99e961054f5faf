// Sleeping and waking, continuous collision, kinematic bodies, determinism.
#include <gtest/gtest.h>

#include <cstring>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

// A box at rest on the ground falls asleep after timeToSleep (0.5 s) below the
// sleep speeds, and a ball dropped on it wakes it; sleeping off: never sleeps.
TEST(Sleep, RestingBoxSleepsAndWakesWhenHit) {
    World world;
    addGround(world);
    const BodyId box = addBox(world, {0, Real(0.5), 0});
    run(world, 60);
    EXPECT_FALSE(world.isAwake(box));
    EXPECT_EQ(length(world.linearVelocity(box)), 0);
    const Vec3 rest = world.position(box);
    run(world, 60);
    EXPECT_EQ(world.position(box).y, rest.y);  // asleep: not integrated at all
    const BodyId ball = addSphere(world, {Real(0.2), 3, 0}, Real(0.2), 5);
    bool woke = false;
    for (int i = 0; i < 60 && !woke; ++i) {
        world.step(kDt);
        woke = world.isAwake(box);
    }
    EXPECT_TRUE(woke);
    EXPECT_TRUE(world.isAwake(ball));

    WorldDef def;
    def.sleeping = false;
    World awake(def);
    addGround(awake);
    const BodyId b2 = addBox(awake, {0, Real(0.5), 0});
    run(awake, 120);
    EXPECT_TRUE(awake.isAwake(b2));
}

// A stack sleeps as one island and wakes as one: poking the bottom box with
// setLinearVelocity wakes the top one too.
TEST(Sleep, IslandWakesTogether) {
    World world;
    addGround(world);
    const BodyId a = addBox(world, {0, Real(0.5), 0});
    const BodyId b = addBox(world, {0, Real(1.5), 0});
    run(world, 90);
    ASSERT_FALSE(world.isAwake(a));
    ASSERT_FALSE(world.isAwake(b));
    world.setLinearVelocity(a, {Real(0.1), 0, 0});
    EXPECT_TRUE(world.isAwake(b));
}

// A 2 cm sphere at 300 m/s (5 m per step, 250 diameters) against a 2 cm thick
// static wall: time of impact stops it on the near side.
TEST(Continuous, FastSmallSphereDoesNotPassThinWall) {
    WorldDef def;
    def.gravity = {};
    World world(def);
    BodyDef wall;
    wall.type = BodyType::Static;
    wall.shape = Shape::box({Real(0.01), 2, 2});
    wall.position = {10, 0, 0};
    world.createBody(wall);
    BodyDef d;
    d.shape = Shape::sphere(Real(0.01));
    d.mass = Real(0.01);
    d.linearVelocity = {300, 0, 0};
    const BodyId ball = world.createBody(d);
    run(world, 30);
    EXPECT_LT(world.position(ball).x, Real(10));
}

// A bullet sphere against a thin dynamic plate (floating, zero gravity).
TEST(Continuous, BulletDoesNotPassThinDynamicPlate) {
    WorldDef def;
    def.gravity = {};
    World world(def);
    BodyDef plate;
    plate.shape = Shape::box({Real(0.02), 2, 2});
    plate.mass = 100;
    plate.position = {10, 0, 0};
    const BodyId p = world.createBody(plate);
    BodyDef d;
    d.shape = Shape::sphere(Real(0.02));
    d.mass = Real(0.01);
    d.linearVelocity = {200, 0, 0};
    d.isBullet = true;
    const BodyId ball = world.createBody(d);
    run(world, 30);
    EXPECT_LT(world.position(ball).x, world.position(p).x);
}

// A kinematic box moving at 1 m/s pushes a dynamic box (frictionless ground)
// and is not pushed back: its velocity and path are exactly the commanded ones.
// The pushed box moves at least at the kinematic speed (within 2 %), at most 5 %
// faster (the soft contact's push-out), and is never pushed into (gap >= 1 cm less
// than touching).
TEST(Kinematic, PushesDynamicAndIsNotPushed) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    addGround(world, 0);
    BodyDef k;
    k.type = BodyType::Kinematic;
    k.shape = Shape::box(Vec3::splat(Real(0.5)));
    k.position = {-2, Real(0.5), 0};
    k.linearVelocity = {1, 0, 0};
    const BodyId kin = world.createBody(k);
    const BodyId box = addBox(world, {0, Real(0.5), 0}, Vec3::splat(Real(0.5)), 5, 0);
    run(world, 180);  // 3 s: contact after ~1 s
    EXPECT_NEAR(world.position(kin).x, 1, Real(1e-4));
    EXPECT_EQ(world.linearVelocity(kin).x, 1);
    EXPECT_GT(world.linearVelocity(box).x, Real(0.98));
    EXPECT_LT(world.linearVelocity(box).x, Real(1.05));
    EXPECT_GT(world.position(box).x - world.position(kin).x, Real(0.99));
}

// Same scene twice -> bit-identical state (pyramid with a ball dropped on it).
TEST(Determinism, ContactSceneIsBitIdentical) {
    auto build = [](World& w) {
        buildPyramid(w, 6);
        addSphere(w, {Real(0.3), 8, Real(0.1)}, Real(0.4), 3, Real(0.3));
    };
    World a, b;
    build(a);
    build(b);
    run(a, 240);
    run(b, 240);
    const std::vector<BodyId> ia = a.bodies(), ib = b.bodies();
    ASSERT_EQ(ia.size(), ib.size());
    for (std::size_t i = 0; i < ia.size(); ++i) {
        const Transform ta = a.transform(ia[i]), tb = b.transform(ib[i]);
        EXPECT_EQ(std::memcmp(&ta, &tb, sizeof ta), 0) << i;
    }
}
