// The sleep test's shortcut (SleepManager::update): when every awake body
// fails the test by itself (faster than any island lets a body be, or not
// allowed to sleep), no timer can reach timeToSleep, so the islands are not
// built. A world with the shortcut and one without must then move the same
// bits and put the same bodies to sleep at the same steps, at any thread
// count: bodies thrown fast at a floor (every update takes the shortcut
// while all of them fly), then landing, sliding and falling asleep (the
// islands built again, and used).
#include <gtest/gtest.h>

#include <vector>

#include "contacts/helpers.hpp"
#include "support/same_motion.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// 40 spheres and boxes 2-7 m above a floor, each thrown at 6-15 m/s (down,
// sideways, some up), spinning: all fast for the first steps, then meeting
// the floor and each other and coming to rest.
std::vector<BodyId> buildScene(World& world) {
    addGround(world);
    std::vector<BodyId> bodies;
    for (int i = 0; i < 40; ++i) {
        const Real x = Real(-10) + Real(i % 8) * Real(2.5), z = Real(-5) + Real(i / 8) * Real(2.5);
        const Real y = Real(2) + Real(i % 5);
        const BodyId b = (i % 2) == 0 ? addSphere(world, {x, y, z}, Real(0.4)) : addBox(world, {x, y, z}, Vec3::splat(Real(0.35)));
        const Real speed = Real(6) + Real(i % 10);
        world.setLinearVelocity(b, {(i % 3 == 0 ? 1 : -1) * speed * Real(0.3), (i % 4 == 0 ? 1 : -1) * speed, Real(0.2) * speed});
        world.setAngularVelocity(b, {Real(0.5), Real(i % 7), Real(-1)});
        bodies.push_back(b);
    }
    return bodies;
}

void runPair(int threads) {
    WorldDef def;
    def.threads = threads;
    World shortcut(def), islands(def);
    shortcut.setParallelMinBodies(1);
    islands.setParallelMinBodies(1);
    detail::implOf(islands).sleepManager.setIslandShortcut(false);
    const std::vector<BodyId> a = buildScene(shortcut), b = buildScene(islands);
    int sleptSteps = 0;
    for (int step = 0; step < 600; ++step) {
        shortcut.step(kDt);
        islands.step(kDt);
        bool anyAsleep = false;
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_TRUE(sameMotion(shortcut, a[i], islands, b[i])) << "threads " << threads << ", body " << i << ", step " << step;
            ASSERT_EQ(shortcut.isAwake(a[i]), islands.isAwake(b[i])) << "threads " << threads << ", body " << i << ", step " << step;
            anyAsleep = anyAsleep || !shortcut.isAwake(a[i]);
        }
        if (anyAsleep) ++sleptSteps;
    }
    const std::uint64_t skipped = detail::implOf(shortcut).sleepManager.islandsSkippedCount();
    EXPECT_GE(skipped, 10u);   // the flight: every body fast
    EXPECT_LT(skipped, 590u);  // and the landing: the islands built
    EXPECT_EQ(detail::implOf(islands).sleepManager.islandsSkippedCount(), 0u);
    EXPECT_GT(sleptSteps, 50);  // bodies fell asleep, by the islands' test
}

TEST(SleepIslandShortcut, SameBitsAndSleepAsBuildingTheIslandsOneThread) { runPair(1); }
TEST(SleepIslandShortcut, SameBitsAndSleepAsBuildingTheIslandsThreeThreads) { runPair(3); }

}  // namespace
