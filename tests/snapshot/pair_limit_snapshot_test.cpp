// Snapshot format version 4: WorldDef::maxContactPairs. A world over its
// contact pair limit (bodies waiting for pairs in the broad phase's move
// buffer) resumes bit for bit; a version-3 file loads with the automatic limit.
#include <gtest/gtest.h>

#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"
#include "world/snapshot_versions.hpp"

namespace fulcrum {
namespace {

constexpr Real kDt = Real(1) / 60;

// 300 spheres at one spot over a ground box, under a limit of 2,000 pairs (44,850 overlap).
World crowd() {
    WorldDef def;
    def.maxContactPairs = 2000;
    World world(def);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({20, Real(0.5), 20});
    ground.position = {0, Real(-0.5), 0};
    world.createBody(ground);
    for (int i = 0; i < 300; ++i) {
        BodyDef d;
        d.shape = Shape::sphere(Real(0.5));
        d.mass = 1;
        d.position = {0, 2, 0};
        world.createBody(d);
    }
    return world;
}

TEST(PairLimitSnapshot, AWorldOverItsLimitResumesBitForBit) {
    World original = crowd();
    for (int i = 0; i < 10; ++i) original.step(kDt);
    ASSERT_GT(original.lastStepProfile().bodiesOverPairLimit, 0u) << "the snapshot must hold bodies waiting for pairs";
    World resumed = loadSnapshotFromMemory(saveSnapshotToMemory(original));
    EXPECT_EQ(resumed.settings().maxContactPairs, 2000);
    for (int i = 0; i < 30; ++i) {
        original.step(kDt);
        resumed.step(kDt);
        ASSERT_EQ(test::stateHash(resumed), test::stateHash(original)) << "diverged at step " << i + 1;
        ASSERT_EQ(resumed.lastStepProfile().contactPairs, original.lastStepProfile().contactPairs);
    }
}

TEST(PairLimitSnapshot, VersionThreeLoadsWithTheAutomaticLimit) {
    World world = crowd();
    world.step(kDt);
    const std::vector<std::uint8_t> v3 = detail::saveSnapshotAsVersion(world, 3);
    const std::vector<std::uint8_t> v4 = detail::saveSnapshotAsVersion(world, 4);
    EXPECT_EQ(v3[8], 3);
    EXPECT_EQ(v4[8], 4);
    EXPECT_EQ(v4.size() - v3.size(), sizeof(std::int64_t));  // the one field version 4 added
    EXPECT_EQ(loadSnapshotFromMemory(v3).settings().maxContactPairs, 0);
    EXPECT_EQ(loadSnapshotFromMemory(v4).settings().maxContactPairs, 2000);
}

}  // namespace
}  // namespace fulcrum
