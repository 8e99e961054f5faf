// Static proxies wait outside the static tree until the first query, pair
// update or tree change (DynamicTree::createProxyDeferred, BroadPhase::
// settleStaticTree): a few go in one by one and give the tree immediate
// insertion gives; many at once are built in bulk, a tree of another shape
// that must find the same pairs, overlaps and ray hits. And whoever asks
// first, a query made right after the creations sees them.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "collision/broad_phase.hpp"
#include "fulcrum/fulcrum.hpp"

namespace fulcrum {
namespace {

AABB randomBox(std::mt19937& rng, float extent, float minHalf, float maxHalf) {
    std::uniform_real_distribution<float> at(-extent, extent), half(minHalf, maxHalf);
    const Vec3 c{at(rng), at(rng), at(rng)};
    return AABB::fromCenterHalf(c, {half(rng), half(rng), half(rng)});
}

// The leaves' user values and boxes in traversal order: equal for two trees of the same shape.
std::vector<std::pair<std::uint32_t, AABB>> shapeOf(const DynamicTree& t) {
    std::vector<std::pair<std::uint32_t, AABB>> out;
    t.query(AABB::fromCenterHalf(Vec3::zero(), Vec3::splat(1e6f)), [&](std::int32_t id, std::uint32_t value) {
        out.push_back({value, t.fatAABB(id)});
        return true;
    });
    return out;
}

std::set<std::uint32_t> overlapsOf(const DynamicTree& t, const AABB& box) {
    std::set<std::uint32_t> out;
    t.query(box, [&](std::int32_t, std::uint32_t value) {
        out.insert(value);
        return true;
    });
    return out;
}

std::set<std::uint32_t> rayHitsOf(const DynamicTree& t, const RayCastInput& ray) {
    std::set<std::uint32_t> out;
    t.rayCast(ray, [&](const RayCastInput& in, std::int32_t, std::uint32_t value) {
        out.insert(value);
        return in.maxFraction;  // every box the segment enters
    });
    return out;
}

TEST(DeferredStatics, FewWaitingLeavesGiveTheTreeImmediateInsertionGives) {
    std::mt19937 rng(7);
    DynamicTree immediate({0, 0, DynamicTreeConfig::Search::BranchAndBound});
    DynamicTree deferred({0, 0, DynamicTreeConfig::Search::BranchAndBound});
    for (std::uint32_t i = 0; i < 700; ++i) {
        const AABB b = randomBox(rng, 50, 0.1f, 3);
        immediate.createProxy(b, i);
        deferred.createProxyDeferred(b, i);
        ASSERT_EQ(deferred.validate(), "");
        // Settled now and then, in batches below the bulk size: one insertion each, in order.
        if (i % 97 == 0) deferred.insertPending();
    }
    EXPECT_TRUE(deferred.hasPending());
    deferred.insertPending();
    EXPECT_FALSE(deferred.hasPending());
    ASSERT_EQ(deferred.validate(), "");
    EXPECT_EQ(shapeOf(deferred), shapeOf(immediate));
    EXPECT_EQ(deferred.height(), immediate.height());
}

TEST(DeferredStatics, ABulkBuiltTreeFindsTheSameOverlapsAndRayHitsAsIncrementalInsertion) {
    for (const std::uint32_t seed : {1u, 2u, 3u}) {
        std::mt19937 rng(seed);
        DynamicTree incremental({0, 0, DynamicTreeConfig::Search::BranchAndBound});
        DynamicTree bulk({0, 0, DynamicTreeConfig::Search::BranchAndBound});
        const std::uint32_t count = 3000;  // past DynamicTree::kBulkMinLeaves: one rebuild
        std::vector<std::int32_t> bulkIds;
        for (std::uint32_t i = 0; i < count; ++i) {
            // Half random boxes, half a grid of touching tiles (large_world's kind of floor).
            const AABB b = i % 2 == 0 ? randomBox(rng, 60, 0.05f, 4)
                                      : AABB::fromCenterHalf({float(i % 40) * 2 - 40, -1, float(i / 80) * 2 - 40}, {1, 0.25f, 1});
            incremental.createProxy(b, i);
            bulkIds.push_back(bulk.createProxyDeferred(b, i));
        }
        bulk.insertPending();
        ASSERT_EQ(bulk.validate(), "");
        ASSERT_EQ(bulk.proxyCount(), incremental.proxyCount());
        for (std::uint32_t i = 0; i < count; ++i) EXPECT_EQ(bulk.userValue(bulkIds[i]), i);
        for (int q = 0; q < 300; ++q) {
            const AABB box = randomBox(rng, 70, 0.1f, 12);
            EXPECT_EQ(overlapsOf(bulk, box), overlapsOf(incremental, box)) << "seed " << seed << " query " << q;
            std::uniform_real_distribution<float> at(-80, 80);
            const RayCastInput ray{{at(rng), at(rng), at(rng)}, {at(rng), at(rng) * 0.25f, at(rng)}, 1};
            EXPECT_EQ(rayHitsOf(bulk, ray), rayHitsOf(incremental, ray)) << "seed " << seed << " ray " << q;
        }
        // Changes after the bulk build keep it valid and equal in answers.
        for (std::uint32_t i = 0; i < 200; ++i) {
            const AABB b = randomBox(rng, 60, 0.05f, 4);
            incremental.createProxy(b, count + i);
            bulk.createProxyDeferred(b, count + i);
        }
        bulk.destroyProxy(bulkIds[5]);  // inserts the waiting ones first
        ASSERT_EQ(bulk.validate(), "");
        EXPECT_FALSE(bulk.hasPending());
        const AABB everything = AABB::fromCenterHalf(Vec3::zero(), Vec3::splat(1000));
        std::set<std::uint32_t> expected = overlapsOf(incremental, everything);
        expected.erase(5);
        EXPECT_EQ(overlapsOf(bulk, everything), expected);
    }
}

// Pairs over random steps: the same lists whether the static tree was built
// in bulk at the first update or one insertion at a time (a query after
// every creation settles it each time).
TEST(DeferredStatics, PairsAreTheSameWithABulkBuiltOrAnIncrementalStaticTree) {
    std::mt19937 rng(11);
    BroadPhase bulk, incremental;
    std::vector<AABB> statics;
    for (int i = 0; i < 2500; ++i) statics.push_back(randomBox(rng, 25, 0.2f, 2.5f));
    const AABB probe = AABB::fromCenterHalf(Vec3::zero(), Vec3::splat(1));
    for (std::size_t i = 0; i < statics.size(); ++i) {
        bulk.createProxy(statics[i], BodyType::Static, {}, static_cast<std::uint32_t>(i));
        incremental.createProxy(statics[i], BodyType::Static, {}, static_cast<std::uint32_t>(i));
        incremental.query(probe, [](ProxyId, std::uint32_t) { return true; });  // inserts it now
    }
    std::vector<AABB> moving;
    std::vector<ProxyId> movingIds;
    for (int i = 0; i < 300; ++i) {
        moving.push_back(randomBox(rng, 25, 0.2f, 1.5f));
        const auto value = static_cast<std::uint32_t>(statics.size() + i);
        movingIds.push_back(bulk.createProxy(moving.back(), BodyType::Dynamic, {}, value));
        EXPECT_EQ(incremental.createProxy(moving.back(), BodyType::Dynamic, {}, value), movingIds.back());
    }
    std::uniform_real_distribution<float> step(-0.6f, 0.6f);
    for (int s = 0; s < 40; ++s) {
        const std::span<const ProxyPair> a = bulk.updatePairs();
        const std::vector<ProxyPair> fromBulk(a.begin(), a.end());
        const std::span<const ProxyPair> b = incremental.updatePairs();
        const std::vector<ProxyPair> fromIncremental(b.begin(), b.end());
        ASSERT_EQ(fromBulk, fromIncremental) << "step " << s;
        if (s == 0) {
            EXPECT_GT(fromBulk.size(), 100u);
        }
        for (std::size_t i = 0; i < moving.size(); ++i) {
            const Vec3 d{step(rng), step(rng), step(rng)};
            moving[i] = {moving[i].min + d, moving[i].max + d};
            bulk.moveProxy(movingIds[i], moving[i], d);
            incremental.moveProxy(movingIds[i], moving[i], d);
        }
    }
    EXPECT_EQ(bulk.validate(), "");
    EXPECT_EQ(incremental.validate(), "");
}

// The world: queries made right after creating static bodies (before any
// step) see them, whether they went in one by one or in bulk, and a step
// after them finds their contacts.
TEST(DeferredStatics, WorldQueriesRightAfterCreationSeeTheNewStaticBodies) {
    for (const int side : {3, 40}) {  // 9 bodies: one insertion each; 1600: one bulk build
        World world;
        const Shape tile = Shape::box({0.5f, 0.25f, 0.5f});
        std::vector<BodyId> tiles;
        for (int i = 0; i < side; ++i) {
            for (int k = 0; k < side; ++k) {
                BodyDef d;
                d.type = BodyType::Static;
                d.shape = tile;
                d.position = {float(i), 0, float(k)};
                tiles.push_back(world.createBody(d));
            }
        }
        const int mid = side / 2;
        const BodyId below = tiles[static_cast<std::size_t>(mid * side + mid)];
        const std::optional<RayCastHit> hit = world.castRay({{float(mid), 5, float(mid)}, {0, -10, 0}});
        ASSERT_TRUE(hit.has_value()) << side;
        EXPECT_EQ(hit->body, below);
        EXPECT_NEAR(hit->point.y, 0.25f, 1e-5f);
        const std::vector<BodyId> near = world.overlapAABB(AABB::fromCenterHalf({float(mid), 0, float(mid)}, {0.6f, 0.1f, 0.1f}));
        EXPECT_EQ(near.size(), 3u) << side;  // the tile and its two neighbours along x

        // One more after the first query, then a dynamic ball dropped on it.
        BodyDef extra;
        extra.type = BodyType::Static;
        extra.shape = tile;
        extra.position = {-5, 0, -5};
        const BodyId lone = world.createBody(extra);
        const std::optional<RayCastHit> lonely = world.castRay({{-5, 5, -5}, {0, -10, 0}});
        ASSERT_TRUE(lonely.has_value());
        EXPECT_EQ(lonely->body, lone);
        BodyDef ball;
        ball.shape = Shape::sphere(0.25f);
        ball.position = {-5, 0.6f, -5};
        const BodyId b = world.createBody(ball);
        for (int s = 0; s < 90; ++s) world.step(1.0f / 60);
        EXPECT_NEAR(world.position(b).y, 0.5f, 0.02f) << side;  // resting on the tile's top
    }
}

// World::reserveBodies makes room and nothing else: the same bodies, the
// same bits; an impossible count is a clear error.
TEST(DeferredStatics, ReservingBodiesChangesNothingButCapacity) {
    const auto run = [](bool reserve) {
        World world;
        if (reserve) world.reserveBodies(3000);
        EXPECT_EQ(world.bodyCount(), 0u);
        BodyDef tile;
        tile.type = BodyType::Static;
        tile.shape = Shape::box({0.5f, 0.25f, 0.5f});
        for (int i = 0; i < 2500; ++i) {
            tile.position = {float(i % 50), 0, float(i / 50)};
            world.createBody(tile);
        }
        BodyDef ball;
        ball.shape = Shape::sphere(0.3f);
        std::vector<BodyId> balls;
        for (int i = 0; i < 20; ++i) {
            ball.position = {float(i) * 2.1f + 0.3f, 1.5f, float(i) * 1.7f + 0.2f};
            balls.push_back(world.createBody(ball));
        }
        for (int s = 0; s < 60; ++s) world.step(1.0f / 60);
        std::vector<Vec3> out;
        for (const BodyId b : balls) out.push_back(world.position(b));
        return out;
    };
    const std::vector<Vec3> plain = run(false), reserved = run(true);
    ASSERT_EQ(plain.size(), reserved.size());
    for (std::size_t i = 0; i < plain.size(); ++i) {
        EXPECT_EQ(plain[i].x, reserved[i].x);
        EXPECT_EQ(plain[i].y, reserved[i].y);
        EXPECT_EQ(plain[i].z, reserved[i].z);
        EXPECT_NEAR(plain[i].y, 0.55f, 0.02f);  // resting on the tiles
    }
    World world;
    try {
        world.reserveBodies(std::size_t{1} << 40);
        FAIL() << "an impossible count was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("reserveBodies"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace fulcrum
