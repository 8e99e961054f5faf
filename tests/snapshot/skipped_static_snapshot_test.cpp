// Static bodies made before any moving one get no move-buffer entry
// (broad_phase.hpp, "Static proxies created beside an empty moving tree");
// a snapshot written before the first step puts the entries back where they
// would be. Three copies of a crowd over its pair limit (where the entries'
// order decides which pairs are kept) must then step bit for bit alike: one
// never saved (its first update puts the entries back), one saved before its
// first step and the world loaded from that snapshot.
#include <gtest/gtest.h>

#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum {
namespace {

constexpr Real kDt = Real(1) / 60;

// 400 static tiles first, then 300 spheres falling on them, under a limit of 1,500 pairs.
World tiles() {
    WorldDef def;
    def.maxContactPairs = 1500;
    World world(def);
    BodyDef tile;
    tile.type = BodyType::Static;
    tile.shape = Shape::box({Real(0.5), Real(0.25), Real(0.5)});
    for (int i = 0; i < 20; ++i) {
        for (int k = 0; k < 20; ++k) {
            tile.position = {Real(i) - 10, Real(-0.25), Real(k) - 10};
            world.createBody(tile);
        }
    }
    for (int i = 0; i < 300; ++i) {
        BodyDef d;
        d.shape = Shape::sphere(Real(0.5));
        d.mass = 1;
        d.position = {Real(i % 5) * Real(0.3) - Real(0.6), Real(0.6) + Real(i / 5) * Real(0.05), Real(i % 7) * Real(0.2) - Real(0.6)};
        world.createBody(d);
    }
    return world;
}

TEST(SkippedStaticSnapshot, SavedBeforeTheFirstStepResumesAsTheWorldNeverSaved) {
    World neverSaved = tiles();
    World saved = tiles();
    World resumed = loadSnapshotFromMemory(saveSnapshotToMemory(saved));
    bool overLimit = false;
    for (int i = 0; i < 30; ++i) {
        neverSaved.step(kDt);
        saved.step(kDt);
        resumed.step(kDt);
        overLimit = overLimit || neverSaved.lastStepProfile().bodiesOverPairLimit > 0;
        ASSERT_EQ(test::stateHash(saved), test::stateHash(neverSaved)) << "step " << i + 1;
        ASSERT_EQ(test::stateHash(resumed), test::stateHash(neverSaved)) << "step " << i + 1;
        ASSERT_EQ(resumed.lastStepProfile().contactPairs, neverSaved.lastStepProfile().contactPairs);
    }
    EXPECT_TRUE(overLimit) << "the crowd must go over its pair limit";
}

}  // namespace
}  // namespace fulcrum
