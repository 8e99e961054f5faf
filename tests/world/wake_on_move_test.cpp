// Sleeping bodies wake when a static or kinematic body is moved onto or out
// from under them (such bodies never sleep themselves, so waking the moved
// body alone is not enough).
#include <gtest/gtest.h>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// A box asleep on a static floor; the floor is teleported 100 m down. The box
// must wake and fall freely: after t seconds it has dropped g t^2 / 2 (the
// semi-implicit Euler drop at 60 Hz, 5 sub-steps, is within 2 % of that).
TEST(WakeOnMove, SleepingBoxFallsWhenItsStaticFloorIsMovedAway) {
    World world;
    const BodyId ground = addGround(world);
    const BodyId box = addBox(world, {0, Real(0.5), 0});
    run(world, 90);
    ASSERT_FALSE(world.isAwake(box));
    const Real y0 = world.position(box).y;

    world.setTransform(ground, {0, -100, 0}, Quat::identity());
    EXPECT_TRUE(world.isAwake(box));
    const int steps = 30;
    run(world, steps);
    const Real t = static_cast<Real>(steps) * kDt;
    const Real expectedDrop = Real(0.5) * Real(9.81) * t * t;
    EXPECT_NEAR(y0 - world.position(box).y, expectedDrop, Real(0.02) * expectedDrop);
}

// A static box teleported so that it overlaps a sleeping box wakes it, and the
// contact solver pushes the two apart (the dynamic box ends up on top of it).
TEST(WakeOnMove, StaticBodyTeleportedIntoSleepingBodyWakesIt) {
    World world;
    addGround(world);
    const BodyId box = addBox(world, {0, Real(0.5), 0});
    BodyDef wallDef;
    wallDef.type = BodyType::Static;
    wallDef.shape = Shape::box({Real(0.5), Real(0.25), Real(0.5)});
    wallDef.position = {10, Real(0.25), 0};
    const BodyId block = world.createBody(wallDef);
    run(world, 90);
    ASSERT_FALSE(world.isAwake(box));

    // Far from the box: nothing wakes.
    world.setTransform(block, {8, Real(0.25), 0}, Quat::identity());
    EXPECT_FALSE(world.isAwake(box));
    // Under the box (overlapping its lower half): it wakes and is pushed up
    // until it rests on the block's top face at y = 0.5.
    world.setTransform(block, {0, Real(0.25), 0}, Quat::identity());
    EXPECT_TRUE(world.isAwake(box));
    run(world, 120);
    EXPECT_NEAR(world.position(box).y, Real(1.0), Real(0.02));
}

}  // namespace
