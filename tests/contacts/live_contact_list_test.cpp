// The contact solver's candidates with most bodies awake and few live
// contacts (ContactManager::contactsOfAwakeBodies): the live contacts from
// the alive bitmap instead of every contact slot. A dead slot gives no
// constraint, so the worlds must move the same bits either way, at any
// thread count.
#include <gtest/gtest.h>

#include <vector>

#include "contacts/helpers.hpp"
#include "support/same_motion.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// 96 bodies (spheres and boxes) over a floor, in pairs thrown at each other
// and falling: they meet, bounce, land and roll, all awake, with a few dozen
// live contacts among the 4-per-body slots the world reserves.
std::vector<BodyId> buildScene(World& world) {
    addGround(world);
    std::vector<BodyId> bodies;
    for (int i = 0; i < 48; ++i) {
        const Real x = Real(-18) + Real(i % 12) * Real(3), z = Real(-9) + Real(i / 12) * Real(6);
        const Real y = Real(0.6) + Real(i % 3) * Real(0.7);
        const BodyId a = (i % 2) == 0 ? addSphere(world, {x - 1, y, z}, Real(0.4)) : addBox(world, {x - 1, y, z}, Vec3::splat(Real(0.35)));
        const BodyId b = (i % 3) == 0 ? addSphere(world, {x + 1, y + Real(0.2), z}, Real(0.3)) : addBox(world, {x + 1, y + Real(0.2), z});
        world.setLinearVelocity(a, {Real(4), 0, Real(0.3)});
        world.setLinearVelocity(b, {Real(-4), 0, Real(-0.2)});
        world.setAngularVelocity(b, {0, Real(1.5), Real(0.5)});
        bodies.push_back(a);
        bodies.push_back(b);
    }
    return bodies;
}

void runPair(int threads) {
    WorldDef def;
    def.threads = threads;
    World listed(def), walked(def);
    listed.setParallelMinBodies(1);
    walked.setParallelMinBodies(1);
    detail::implOf(walked).contactManager.setLiveContactList(false);
    const std::vector<BodyId> a = buildScene(listed), b = buildScene(walked);
    int listedSteps = 0, constraints = 0;
    for (int step = 0; step < 150; ++step) {
        const detail::ContactManager& m = detail::implOf(listed).contactManager;
        listed.step(kDt);
        walked.step(kDt);
        const StepProfile p = listed.lastStepProfile();
        // The list was the one in use: most bodies awake, live contacts under half the slots.
        if (2 * p.awakeBodies >= a.size() + 1 && 2 * std::size_t{m.liveContactCount()} < m.contacts().size()) ++listedSteps;
        constraints += static_cast<int>(p.contactConstraints);
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_TRUE(sameMotion(listed, a[i], walked, b[i])) << "threads " << threads << ", body " << i << ", step " << step;
        }
    }
    EXPECT_GT(listedSteps, 50);  // 98 of the 150 (the rest: most of them asleep)
    EXPECT_GT(constraints, 2000);  // contacts were solved, not only listed
}

TEST(LiveContactList, SameBitsAsWalkingEverySlotOneThread) { runPair(1); }
TEST(LiveContactList, SameBitsAsWalkingEverySlotThreeThreads) { runPair(3); }

}  // namespace
