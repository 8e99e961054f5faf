// DynamicTree: a leaf whose new fat box still fits in the box of its parent
// or of a close ancestor (DynamicTree::kInPlaceLevels) is
// refitted in place instead of removed and re-inserted (updateInPlace). These
// tests drive a swinging chain, the motion that made the chain benchmark
// re-insert a third of its links every step, through both ways the world moves
// proxies: moveProxy one at a time, and setFatBox for every mover followed by
// reinsert for each (the contact manager's batched order, in which parents'
// boxes are stale while the reinsertions run). After every step the tree
// must be exact (every internal box the union of its children: validate()),
// every fat box must hold its tight box, overlap queries must equal brute
// force, and the tree must stay close in quality to a top-down SAH build.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "collision/dynamic_tree.hpp"

namespace fulcrum {
namespace {

// 100 capsule links (length 1, radius 0.1) hanging from the origin, each
// swinging relative to the previous one in the x-y plane with its own
// frequency and a slow twist out of the plane: the free end moves at ~30 m/s,
// direction changing all the time, as in the chain benchmark.
struct SwingingChain {
    static constexpr int kLinks = 100;
    std::vector<AABB> tight = std::vector<AABB>(kLinks);
    std::vector<Vec3> centre = std::vector<Vec3>(kLinks);

    void pose(double t) {
        Vec3 joint{0, 0, 0};
        double angle = 0;
        for (int i = 0; i < kLinks; ++i) {
            angle += 0.25 * std::sin(1.7 * t + 0.37 * i) + 0.02 * i * std::cos(0.9 * t);
            const double tilt = 0.3 * std::sin(0.5 * t + 0.11 * i);
            const Vec3 dir{static_cast<Real>(std::sin(angle) * std::cos(tilt)), static_cast<Real>(-std::cos(angle) * std::cos(tilt)),
                           static_cast<Real>(std::sin(tilt))};
            const Vec3 end = joint + dir;
            const auto k = static_cast<std::size_t>(i);
            tight[k] = AABB{min(joint, end) - Vec3::splat(Real(0.1)), max(joint, end) + Vec3::splat(Real(0.1))};
            centre[k] = (joint + end) * Real(0.5);
            joint = end;
        }
    }
};

void expectQueriesMatchBruteForce(const DynamicTree& tree, const std::vector<std::int32_t>& ids) {
    for (const std::int32_t self : ids) {
        const AABB& box = tree.fatAABB(self);
        std::vector<std::int32_t> found, expected;
        tree.query(box, [&](std::int32_t id, std::uint32_t) {
            found.push_back(id);
            return true;
        });
        for (const std::int32_t other : ids)
            if (overlaps(tree.fatAABB(other), box)) expected.push_back(other);
        std::sort(found.begin(), found.end());
        std::sort(expected.begin(), expected.end());
        ASSERT_EQ(found, expected) << "query of leaf " << self;
    }
}

void runChain(bool batched) {
    DynamicTree tree;  // the moving tree's defaults: 10 cm margin, one step of prediction, greedy
    SwingingChain chain;
    const double dt = 1.0 / 60;
    chain.pose(0);
    std::vector<std::int32_t> ids;
    for (std::uint32_t i = 0; i < SwingingChain::kLinks; ++i) ids.push_back(tree.createProxy(chain.tight[i], i));
    std::vector<Vec3> previous = chain.centre;
    int movers = 0;
    for (int step = 1; step <= 600; ++step) {
        chain.pose(step * dt);
        std::vector<std::int32_t> moved;
        for (std::size_t i = 0; i < ids.size(); ++i) {
            // The displacement of the coming step, predicted from the last one (v dt).
            const Vec3 displacement = chain.centre[i] - previous[i];
            if (!batched) {
                movers += tree.moveProxy(ids[i], chain.tight[i], displacement) ? 1 : 0;
            } else if (tree.mustMove(ids[i], chain.tight[i], displacement)) {
                tree.setFatBox(ids[i], chain.tight[i], displacement);
                moved.push_back(ids[i]);
            }
        }
        for (const std::int32_t id : moved) tree.reinsert(id);
        movers += static_cast<int>(moved.size());
        previous = chain.centre;
        const std::string why = tree.validate();
        ASSERT_EQ(why, "") << "step " << step;
        for (std::size_t i = 0; i < ids.size(); ++i) {
            ASSERT_TRUE(tree.fatAABB(ids[i]).contains(chain.tight[i])) << "step " << step << ", link " << i;
        }
        if (step % 20 == 0) expectQueriesMatchBruteForce(tree, ids);
        if (::testing::Test::HasFatalFailure()) return;
    }
    // The motion is fast enough that many boxes moved (else the test proves nothing).
    EXPECT_GT(movers, 600 * SwingingChain::kLinks / 10);
    // Quality: a tree whose leaves mostly stayed in place must not drift far
    // from a top-down SAH build of the same boxes (the random-insertion test
    // bounds greedy insertion at 1.4).
    DynamicTree rebuilt;
    for (std::size_t i = 0; i < ids.size(); ++i) rebuilt.createProxy(tree.fatAABB(ids[i]), 0);
    rebuilt.rebuild();
    const double ratio = tree.internalSurfaceArea() / rebuilt.internalSurfaceArea();
    EXPECT_LT(ratio, 1.5) << "incremental / rebuilt internal area";
}

TEST(DynamicTreeInPlace, SwingingChainMovedOneByOneStaysExact) { runChain(false); }

TEST(DynamicTreeInPlace, SwingingChainMovedInABatchStaysExact) { runChain(true); }

// A leaf that moves only inside its parent's box keeps its place: its
// ancestors' boxes shrink or grow to the exact union, nothing else changes.
TEST(DynamicTreeInPlace, AMoveInsideTheParentsBoxRefitsTheAncestors) {
    DynamicTreeConfig config;
    config.margin = 0;
    config.displacementScale = 0;
    DynamicTree tree(config);
    const std::int32_t a = tree.createProxy(AABB{{0, 0, 0}, {1, 1, 1}}, 0);
    const std::int32_t b = tree.createProxy(AABB{{4, 0, 0}, {5, 1, 1}}, 1);
    const std::int32_t c = tree.createProxy(AABB{{40, 0, 0}, {41, 1, 1}}, 2);
    ASSERT_EQ(tree.validate(), "");
    // Shrink a inside its parent's box (a and b share a parent: the closest pair).
    EXPECT_TRUE(tree.moveProxy(a, AABB{{2, 0, 0}, {3, 1, 1}}, Vec3::zero()));
    EXPECT_EQ(tree.validate(), "");
    EXPECT_EQ(tree.fatAABB(a), (AABB{{2, 0, 0}, {3, 1, 1}}));
    // The root's box is the exact union: x from 2 (a) to 41 (c).
    int hits = 0;
    tree.query(AABB{{1, 0, 0}, {1.5f, 1, 1}}, [&](std::int32_t, std::uint32_t) { return ++hits, true; });
    EXPECT_EQ(hits, 0) << "no box covers x in [1, 1.5] any more";
    tree.query(AABB{{2.5f, 0, 0}, {4.5f, 1, 1}}, [&](std::int32_t, std::uint32_t) { return ++hits, true; });
    EXPECT_EQ(hits, 2);
    (void)b;
    (void)c;
}

}  // namespace
}  // namespace fulcrum
