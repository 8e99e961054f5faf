// The broad phase's update as the threaded step runs it (docs/threading.md):
// the moved proxies get their new fat boxes first, then one parallelFor
// re-inserts them into the tree at index 0 while its other ranges run the
// narrow phase. Whatever order the scheduler runs the ranges in, after every
// step the tree must be valid (every internal box the union of its children,
// parents and heights consistent: BroadPhase::validate) and every awake body's
// tight box at the step's start (where the update saw it) must lie inside its
// proxy's fat box -- the broad phase's contract, without which a pair could be
// missed. Checked on a collapsing sphere pile
// (many proxies leave their fat boxes each step) under the inline task
// system, the pool at 2 threads and a reverse-order user scheduler (index 0,
// the re-insertions, runs last there, after every narrow-phase range).
#include <gtest/gtest.h>

#include <string>

#include "fulcrum/world.hpp"
#include "ground.hpp"
#include "reverse_scheduler.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;

namespace {

World buildSpherePile() {
    WorldDef def;
    def.parallelMinBodies = 0;  // the pool on every step, however many are awake
    World world(def);
    test::addGroundSlab(world);
    for (int y = 0; y < 6; ++y) {
        for (int z = 0; z < 10; ++z) {
            for (int x = 0; x < 10; ++x) {
                BodyDef d;
                d.shape = Shape::sphere(Real(0.5));
                d.mass = 1;
                d.position = {Real(1.05) * static_cast<Real>(x) + Real(0.3) * static_cast<Real>(y % 2),
                              Real(0.5) + Real(1.1) * static_cast<Real>(y),
                              Real(1.05) * static_cast<Real>(z) + Real(0.2) * static_cast<Real>(y % 3)};
                world.createBody(d);
            }
        }
    }
    return world;
}

void expectValidBroadPhase(const World& world, const std::string& config, int step) {
    const WorldImpl& w = detail::implOf(world);
    const detail::ContactManager& manager = w.contactManager;
    ASSERT_EQ(manager.broadPhase().validate(), "") << config << ", step " << step;
    for (const std::uint32_t d : w.awakeBodies) {
        // The boxes were made from the step's start transforms (w.previous).
        const AABB tight = w.cold[d].shape.bounds(w.previous[d]);
        const AABB& fat = manager.broadPhase().fatAABB(manager.proxyOfSlot(w.denseToSlot[d]));
        ASSERT_TRUE(fat.contains(tight)) << config << ", step " << step << ": body " << d
                                         << " is outside its fat box";
    }
}

}  // namespace

TEST(ThreadedBroadPhase, TreeStaysValidWhileReinsertionsRunBesideTheNarrowPhase) {
    test::ReverseScheduler reverse;
    struct Config {
        const char* name;
        int threads;
        TaskSystem* user;
    };
    const Config configs[] = {{"threads=1", 1, nullptr}, {"pool threads=2", 2, nullptr}, {"ReverseScheduler", 1, &reverse}};
    for (const Config& config : configs) {
        World world = buildSpherePile();
        world.setThreadCount(config.threads);
        world.setTaskSystem(config.user);
        for (int s = 1; s <= 40; ++s) {
            world.step(Real(1) / 60);
            expectValidBroadPhase(world, config.name, s);
        }
        // The pile did collapse: bodies moved well beyond the fat margins.
        EXPECT_GT(detail::implOf(world).awakeBodies.size(), 0u) << config.name;
    }
    EXPECT_GT(reverse.calls, 0u);
}
