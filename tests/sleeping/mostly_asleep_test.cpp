// A world that is mostly asleep: the contact solver then lists only the awake
// bodies' contacts (ContactManager::contactsOfAwakeBodies) instead of every
// contact. Those lists must hold every contact an awake body has, at either
// end and with static bodies too, or an awake body would fall through what it
// rests on.
#include <gtest/gtest.h>

#include <cmath>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// 40 boxes in two rows asleep on the floor, and a stack of three woken by a
// sideways push on its top box: fewer than half the bodies are awake. The
// stack has contacts with a static body (the floor, slot 0: the awake box is
// the contact's B end) and between awake boxes. It must stay up: each box
// ends within 5 mm of its rest height (0.5, 1.5, 2.5 m) and the push's
// momentum is taken by friction (the top box moves less than the free slide
// v^2 / (2 mu g) would allow), and the sleepers stay asleep and unmoved.
TEST(MostlyAsleep, AnAwakeStackAmongSleepersRestsOnItsContacts) {
    World world;
    addGround(world);
    std::vector<BodyId> sleepers;
    for (int i = 0; i < 40; ++i) {
        const Real x = Real(-20) + Real(i % 20) * Real(2), z = i < 20 ? Real(-6) : Real(6);
        sleepers.push_back(addBox(world, {x, Real(0.5), z}));
    }
    std::vector<BodyId> stack;
    for (int k = 0; k < 3; ++k) stack.push_back(addBox(world, {0, Real(0.5) + Real(k), 0}));
    for (int i = 0; i < 240 && world.isAwake(stack[0]); ++i) world.step(kDt);
    ASSERT_FALSE(world.isAwake(stack[0]));
    for (const BodyId b : sleepers) ASSERT_FALSE(world.isAwake(b));
    const Vec3 sleeperBefore = world.position(sleepers[7]);

    // A small push: the friction on the box below stops it within a few cm.
    const Real v0 = Real(0.3);
    world.setLinearVelocity(stack[2], {v0, 0, 0});
    const Vec3 topBefore = world.position(stack[2]);
    for (int i = 0; i < 60; ++i) {
        world.step(kDt);
        const StepProfile p = world.lastStepProfile();
        if (i == 0) {
            EXPECT_EQ(p.awakeBodies, 3u);  // the stack alone: the sparse list is the one in use
            EXPECT_EQ(p.contactConstraints, 3u);  // floor-box, box-box, box-box
        }
    }
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(world.position(stack[static_cast<std::size_t>(k)]).y, Real(0.5) + Real(k), Real(0.005));
    const Real slide = world.position(stack[2]).x - topBefore.x;
    const Real freeSlide = v0 * v0 / (2 * Real(0.6) * Real(9.81));  // the friction bound of the push alone
    EXPECT_GT(slide, 0);
    EXPECT_LT(slide, freeSlide * Real(1.5));
    EXPECT_FALSE(world.isAwake(sleepers[7]));
    EXPECT_EQ(world.position(sleepers[7]).x, sleeperBefore.x);
}

}  // namespace
