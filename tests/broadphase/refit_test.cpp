// DynamicTree::refitOrRebuild: the bulk update of a moving tree whose leaves
// nearly all got new boxes (Jolt's HighSpeed). A refit keeps the tree's shape
// and must leave it exact (every internal box the union of its children's)
// and answering every query as brute force does; once the bodies have
// scattered far from their tree neighbours it must rebuild instead.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "collision/dynamic_tree.hpp"

namespace fulcrum {
namespace {

struct Body {
    Vec3 position, velocity;
    std::int32_t proxy = kNullNode;
};

AABB tightBox(const Body& b) { return AABB::fromCenterHalf(b.position, Vec3::splat(Real(0.5))); }

void expectQueriesMatchBruteForce(const DynamicTree& tree, const std::vector<Body>& bodies, std::mt19937& rng) {
    std::uniform_real_distribution<float> at(-60, 60), size(1, 10);
    for (int q = 0; q < 40; ++q) {
        const Vec3 c{Real(at(rng)), Real(at(rng)), Real(at(rng))};
        const AABB box = AABB::fromCenterHalf(c, Vec3::splat(Real(size(rng))));
        std::vector<std::int32_t> found, expected;
        tree.query(box, [&](std::int32_t id, std::uint32_t) { return found.push_back(id), true; });
        for (const Body& b : bodies) {
            if (overlaps(tree.fatAABB(b.proxy), box)) expected.push_back(b.proxy);
        }
        std::sort(found.begin(), found.end());
        std::sort(expected.begin(), expected.end());
        ASSERT_EQ(found, expected) << "query " << q;
    }
}

TEST(DynamicTreeRefit, EveryLeafMovedEachStepStaysExactAndRebuildsOnlyWhenLoose) {
    DynamicTree tree;  // the moving tree's settings: margin, one step of predicted motion
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> at(-45, 45), dir(-1, 1);
    std::vector<Body> bodies(2000);
    const Real dt = Real(1) / 60;
    for (Body& b : bodies) {
        b.position = {Real(at(rng)), Real(at(rng)), Real(at(rng))};
        b.velocity = Vec3{Real(dir(rng)), Real(dir(rng)), Real(dir(rng))} * Real(20);
        b.proxy = tree.createProxy(tightBox(b), 0, b.velocity * dt);
    }
    int rebuilds = 0, refits = 0;
    for (int step = 0; step < 60; ++step) {
        for (Body& b : bodies) {
            b.position += b.velocity * dt;
            // Bounce inside the 100 m box, as HighSpeed's bodies do.
            for (std::size_t k = 0; k < 3; ++k) {
                if (std::abs(b.position[k]) > Real(49)) b.velocity[k] = -b.velocity[k];
            }
            if (tree.mustMove(b.proxy, tightBox(b), b.velocity * dt)) tree.setFatBox(b.proxy, tightBox(b), b.velocity * dt);
        }
        (tree.refitOrRebuild() ? rebuilds : refits) += 1;
        ASSERT_EQ(tree.validate(), "") << "step " << step;
        expectQueriesMatchBruteForce(tree, bodies, rng);
        if (::testing::Test::HasFatalFailure()) return;
    }
    // The first update rebuilds (nothing to compare a refit with); then the
    // tree is refitted for a while and rebuilt when its boxes have loosened.
    EXPECT_GT(refits, 30);
    EXPECT_GT(rebuilds, 1);
    // A refitted tree stays within reach of a fresh build of the same boxes.
    DynamicTree fresh;
    for (const Body& b : bodies) fresh.createProxy(tree.fatAABB(b.proxy), 0);
    fresh.rebuild();
    EXPECT_LT(tree.internalSurfaceArea() / fresh.internalSurfaceArea(), 2.5);
}

TEST(DynamicTreeRefit, AStillTreeIsRefittedNotRebuilt) {
    DynamicTree tree;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> at(-45, 45);
    std::vector<std::int32_t> ids;
    for (int i = 0; i < 500; ++i) {
        ids.push_back(tree.createProxy(AABB::fromCenterHalf({Real(at(rng)), Real(at(rng)), Real(at(rng))}, Vec3::splat(1)), 0));
    }
    EXPECT_TRUE(tree.refitOrRebuild());  // the first: a rebuild
    const std::vector<TreeNode> built(tree.nodes().begin(), tree.nodes().end());
    EXPECT_FALSE(tree.refitOrRebuild());  // nothing moved: a refit, which changes nothing
    ASSERT_EQ(tree.nodes().size(), built.size());
    for (std::size_t i = 0; i < built.size(); ++i) {
        EXPECT_EQ(tree.nodes()[i].box, built[i].box);
        EXPECT_EQ(tree.nodes()[i].parent, built[i].parent);
    }
    EXPECT_EQ(tree.validate(), "");
}

}  // namespace
}  // namespace fulcrum
