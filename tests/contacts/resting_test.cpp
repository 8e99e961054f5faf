// Resting contact: boxes and spheres come to rest on the ground at the right
// height and stop moving (no jitter).
#include <gtest/gtest.h>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {
WorldDef noSleep() {
    WorldDef d;
    d.sleeping = false;
    return d;
}
}  // namespace

// A box dropped from 0.2 m settles with its bottom face on y = 0 (tolerance:
// 5 mm of soft-contact overlap) and stays still: after settling every speed is
// below 1e-3 m/s for 5 s.
TEST(Resting, BoxSettlesWithoutJitter) {
    World world(noSleep());
    addGround(world);
    const BodyId box = addBox(world, {0, Real(0.7), 0});
    run(world, 120);
    EXPECT_NEAR(world.position(box).y, Real(0.5), Real(0.005));
    Real maxSpeed = 0;
    for (int i = 0; i < 300; ++i) {
        world.step(kDt);
        maxSpeed = std::max(maxSpeed, length(world.linearVelocity(box)));
        maxSpeed = std::max(maxSpeed, length(world.angularVelocity(box)) * Real(0.5));
    }
    EXPECT_LT(maxSpeed, Real(1e-3));
    EXPECT_NEAR(world.position(box).x, 0, Real(2e-3));  // Gauss-Seidel order makes a landing slightly asymmetric
}

// A sphere rests at height r; a stack of spheres? No: a sphere on a box.
TEST(Resting, SphereRestsOnGroundAtItsRadius) {
    World world(noSleep());
    addGround(world);
    const BodyId ball = addSphere(world, {0, 1, 0}, Real(0.25));
    run(world, 180);
    EXPECT_NEAR(world.position(ball).y, Real(0.25), Real(0.005));
    EXPECT_LT(length(world.linearVelocity(ball)), Real(1e-3));
    // The contact report: normal from the ground (A, created first) up to the ball.
    const std::vector<ContactReport> contacts = world.contacts();
    ASSERT_EQ(contacts.size(), 1u);
    EXPECT_NEAR(contacts[0].normal.y, 1, Real(1e-4));
    EXPECT_LT(std::fabs(contacts[0].depth), Real(0.005));
}

// Momentum balance of resting contact: the ground's total normal impulse per
// step equals m g dt (Newton's third law), seen as zero vertical acceleration.
TEST(Resting, StackOfThreeBoxesHoldsWeight) {
    World world(noSleep());
    addGround(world);
    BodyId boxes[3];
    for (int i = 0; i < 3; ++i) boxes[i] = addBox(world, {0, Real(0.5) + static_cast<Real>(i), 0});
    run(world, 300);
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(world.position(boxes[i]).y, Real(0.5) + static_cast<Real>(i), Real(0.01)) << i;
        EXPECT_LT(length(world.linearVelocity(boxes[i])), Real(1e-3)) << i;
    }
}
