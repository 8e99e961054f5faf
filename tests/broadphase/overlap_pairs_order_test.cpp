// DynamicTree::overlapPairs, for a tree of kBranchFreeDescentLeaves or more
// against itself, runs its own loop (its box tests push without a branch on
// their outcome, a leaf is never pushed against itself) where it used to pop
// pairs through splitPairs. It must call back the same pairs in
// the same order as the splitPairs descent (the unchanged path, written out
// below), stop where it stopped, and find exactly the overlapping leaf pairs
// of brute force: on random trees made by inserts, removals, moves, a
// rebuild and refits, for a tree against itself, against another tree, on
// subtrees (the parts the broad phase hands its workers) and on leaves.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "collision/dynamic_tree.hpp"

namespace fulcrum {
namespace {

using Calls = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

// The descent as it was: pop a pair, split it by splitPairs, call back a leaf pair.
Calls referenceDescent(const DynamicTree& tree, std::int32_t a, const DynamicTree& other, std::int32_t b,
                       std::size_t stopAfter, bool& ran) {
    Calls calls;
    ran = true;
    if (a == kNullNode || b == kNullNode) return calls;
    if (!(&other == &tree && a == b) && !overlaps(tree.nodes()[static_cast<std::size_t>(a)].box,
                                                  other.nodes()[static_cast<std::size_t>(b)].box))
        return calls;
    std::vector<std::pair<std::int32_t, std::int32_t>> stack{{a, b}};
    while (!stack.empty()) {
        const auto [x, y] = stack.back();
        stack.pop_back();
        const bool split =
            tree.splitPairs(x, other, y, [&](std::int32_t p, std::int32_t q) { stack.emplace_back(p, q); });
        if (!split) {
            calls.emplace_back(tree.userValue(x), other.userValue(y));
            if (calls.size() == stopAfter) {
                ran = false;
                return calls;
            }
        }
    }
    return calls;
}

Calls newDescent(const DynamicTree& tree, std::int32_t a, const DynamicTree& other, std::int32_t b, std::size_t stopAfter,
                 bool& ran) {
    Calls calls;
    ran = tree.overlapPairs(a, other, b, [&](std::uint32_t x, std::uint32_t y) {
        calls.emplace_back(x, y);
        return calls.size() != stopAfter;
    });
    return calls;
}

struct Forest {
    DynamicTree tree;
    std::vector<std::int32_t> ids;
    std::vector<AABB> tight;
};

// Boxes of every size in a 60 m cube, some elongated along their motion as
// HighSpeed's are; then removals, moves, and (when `bulk`) a rebuild and refits.
void grow(Forest& f, std::mt19937& rng, int count, std::uint32_t firstValue, bool bulk) {
    std::uniform_real_distribution<float> pos(-30, 30), half(0.05f, 2.5f), step(-5, 5);
    for (int i = 0; i < count; ++i) {
        const Vec3 c{pos(rng), pos(rng), pos(rng)};
        const AABB b = AABB::fromCenterHalf(c, Vec3{half(rng), half(rng), half(rng)});
        f.ids.push_back(f.tree.createProxy(b, firstValue + static_cast<std::uint32_t>(i), Vec3{step(rng), 0, step(rng)}));
        f.tight.push_back(b);
    }
    for (int i = 0; i < count / 10; ++i) {  // removals
        const std::size_t k = rng() % f.ids.size();
        f.tree.destroyProxy(f.ids[k]);
        f.ids.erase(f.ids.begin() + static_cast<std::ptrdiff_t>(k));
        f.tight.erase(f.tight.begin() + static_cast<std::ptrdiff_t>(k));
    }
    for (std::size_t k = 0; k < f.ids.size(); k += 3) {  // moves by reinsertion
        const Vec3 d{step(rng), step(rng), step(rng)};
        f.tight[k] = AABB{f.tight[k].min + d, f.tight[k].max + d};
        f.tree.moveProxy(f.ids[k], f.tight[k], d);
    }
    if (!bulk) return;
    f.tree.rebuild();
    for (int round = 0; round < 3; ++round) {  // every leaf moves: refits (and rebuilds when loose)
        for (std::size_t k = 0; k < f.ids.size(); ++k) {
            const Vec3 d{step(rng), step(rng), step(rng)};
            f.tight[k] = AABB{f.tight[k].min + d, f.tight[k].max + d};
            f.tree.setFatBox(f.ids[k], f.tight[k], d);
        }
        f.tree.refitOrRebuild();
    }
}

std::set<std::pair<std::uint32_t, std::uint32_t>> bruteForce(const Forest& a, const Forest& b, bool self) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (const std::int32_t x : a.ids) {
        for (const std::int32_t y : b.ids) {
            if (self && x == y) continue;
            if (!overlaps(a.tree.fatAABB(x), b.tree.fatAABB(y))) continue;
            std::uint32_t u = a.tree.userValue(x), v = b.tree.userValue(y);
            if (self && u > v) std::swap(u, v);
            pairs.insert({u, v});
        }
    }
    return pairs;
}

void expectSameDescent(const DynamicTree& tree, std::int32_t a, const DynamicTree& other, std::int32_t b,
                       std::size_t stopAfter, const char* what) {
    bool refRan = false, newRan = false;
    const Calls expected = referenceDescent(tree, a, other, b, stopAfter, refRan);
    const Calls got = newDescent(tree, a, other, b, stopAfter, newRan);
    EXPECT_EQ(got, expected) << what << ": nodes " << a << ", " << b << ", stop after " << stopAfter;
    EXPECT_EQ(newRan, refRan) << what << ": nodes " << a << ", " << b << ", stop after " << stopAfter;
}

TEST(OverlapPairsOrder, SameCallsInTheSameOrderAsTheSplitPairsDescentAndBruteForce) {
    for (std::uint32_t seed = 1; seed <= 2; ++seed) {
        std::mt19937 rng(seed);
        Forest moving, fixed;
        grow(moving, rng, 3000, 0, seed % 2 == 1);
        grow(fixed, rng, 150, 100000, seed % 2 == 0);
        // The moving tree takes the branch-free loop against itself, the small one the splitPairs loop.
        ASSERT_GE(moving.tree.proxyCount(), DynamicTree::kBranchFreeDescentLeaves);
        ASSERT_LT(fixed.tree.proxyCount(), DynamicTree::kBranchFreeDescentLeaves);
        ASSERT_EQ(moving.tree.validate(), "");
        ASSERT_EQ(fixed.tree.validate(), "");

        // Whole trees: against itself and against the other, run to the end.
        bool ran = false;
        const Calls selfCalls = newDescent(moving.tree, moving.tree.root(), moving.tree, moving.tree.root(), 0, ran);
        EXPECT_TRUE(ran);
        std::set<std::pair<std::uint32_t, std::uint32_t>> selfSet;
        for (auto [u, v] : selfCalls) {
            EXPECT_TRUE(selfSet.insert({std::min(u, v), std::max(u, v)}).second) << "pair reported twice";
        }
        EXPECT_EQ(selfSet, bruteForce(moving, moving, true)) << "seed " << seed;
        EXPECT_GT(selfSet.size(), 500u);  // the trees overlap enough to test something
        const Calls crossCalls = newDescent(moving.tree, moving.tree.root(), fixed.tree, fixed.tree.root(), 0, ran);
        const std::set<std::pair<std::uint32_t, std::uint32_t>> crossSet(crossCalls.begin(), crossCalls.end());
        EXPECT_EQ(crossSet.size(), crossCalls.size());
        EXPECT_EQ(crossSet, bruteForce(moving, fixed, false)) << "seed " << seed;
        EXPECT_GT(crossSet.size(), 20u);

        // The order and the stops, against the unchanged path: whole trees,
        // every node against itself and against the other tree's root, pairs
        // of nodes at random (leaves included), and stops after 1, 7 and 40 pairs.
        for (const std::size_t stop : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{40}}) {
            expectSameDescent(moving.tree, moving.tree.root(), moving.tree, moving.tree.root(), stop, "self");
            expectSameDescent(moving.tree, moving.tree.root(), fixed.tree, fixed.tree.root(), stop, "cross");
            expectSameDescent(fixed.tree, fixed.tree.root(), moving.tree, moving.tree.root(), stop, "cross reversed");
            expectSameDescent(fixed.tree, fixed.tree.root(), fixed.tree, fixed.tree.root(), stop, "small tree, self");
        }
        const auto& nodes = moving.tree.nodes();
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            if (nodes[i].height < 0) continue;  // free
            const auto n = static_cast<std::int32_t>(i);
            expectSameDescent(moving.tree, n, moving.tree, n, 0, "node against itself");
            expectSameDescent(moving.tree, n, fixed.tree, fixed.tree.root(), 0, "node against the other tree");
        }
        std::uniform_int_distribution<std::size_t> pick(0, nodes.size() - 1);
        for (int k = 0; k < 2000; ++k) {
            const std::size_t i = pick(rng), j = pick(rng);
            if (nodes[i].height < 0 || nodes[j].height < 0) continue;
            expectSameDescent(moving.tree, static_cast<std::int32_t>(i), moving.tree, static_cast<std::int32_t>(j),
                              k % 3 == 0 ? 2 : 0, "two nodes");
        }
        expectSameDescent(moving.tree, kNullNode, moving.tree, moving.tree.root(), 0, "null node");
    }
}

// The descent over the depth-first copy (prepareSelfDescent, or written by
// a refit) against the pool's splitPairs descent, exactly: the whole tree,
// every node against itself (when `everyNode`), random node pairs, stops.
void expectCopyDescentIsThePools(Forest& f, std::mt19937& rng, const char* what, bool everyNode) {
    ASSERT_TRUE(f.tree.selfDescentPrepared()) << what;
    // The copy's writers leave out the pool-to-copy index: a whole-tree
    // descent starts at the copy's first node, and one below the root walks
    // the pool until the index is written (the same calls either way).
    EXPECT_FALSE(f.tree.descentIndexPrepared()) << what;
    {
        std::uniform_int_distribution<std::size_t> pick(0, f.tree.nodes().size() - 1);
        for (int k = 0; k < 50; ++k) {
            const std::size_t i = pick(rng), j = pick(rng);
            if (f.tree.nodes()[i].height < 0 || f.tree.nodes()[j].height < 0) continue;
            expectSameDescent(f.tree, static_cast<std::int32_t>(i), f.tree, static_cast<std::int32_t>(j), 0, what);
        }
    }
    f.tree.prepareDescentIndex();
    EXPECT_TRUE(f.tree.descentIndexPrepared()) << what;
    const DynamicTree& t = f.tree;
    for (const std::size_t stop : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{40}}) {
        expectSameDescent(t, t.root(), t, t.root(), stop, what);
    }
    bool ran = false;
    const Calls calls = newDescent(t, t.root(), t, t.root(), 0, ran);
    std::set<std::pair<std::uint32_t, std::uint32_t>> found;
    for (auto [u, v] : calls) found.insert({std::min(u, v), std::max(u, v)});
    EXPECT_EQ(found.size(), calls.size()) << what << ": a pair reported twice";
    EXPECT_EQ(found, bruteForce(f, f, true)) << what;
    const auto& nodes = t.nodes();
    for (std::size_t i = 0; everyNode && i < nodes.size(); ++i) {
        if (nodes[i].height < 0) continue;
        expectSameDescent(t, static_cast<std::int32_t>(i), t, static_cast<std::int32_t>(i), 0, what);
    }
    std::uniform_int_distribution<std::size_t> pick(0, nodes.size() - 1);
    for (int k = 0; k < 500; ++k) {
        const std::size_t i = pick(rng), j = pick(rng);
        if (nodes[i].height < 0 || nodes[j].height < 0) continue;
        expectSameDescent(t, static_cast<std::int32_t>(i), t, static_cast<std::int32_t>(j), k % 3 == 0 ? 2 : 0, what);
    }
    ASSERT_TRUE(f.tree.selfDescentPrepared()) << what << ": a const descent changed nothing";
}

TEST(OverlapPairsOrder, TheDepthFirstCopyDescendsAsThePool) {
    std::uniform_real_distribution<float> step(-3, 3);
    for (const int count : {2500, 2800, 3400}) {
        std::mt19937 rng(static_cast<std::uint32_t>(count));
        Forest f;
        grow(f, rng, count, 7, false);  // reinsertions only: no copy until asked
        ASSERT_GE(f.tree.proxyCount(), DynamicTree::kBranchFreeDescentLeaves - 250);
        if (f.tree.proxyCount() < DynamicTree::kBranchFreeDescentLeaves) {
            f.tree.prepareSelfDescent();  // too small: no copy, the pool's loops
            EXPECT_FALSE(f.tree.selfDescentPrepared());
            // Grown past the threshold by inserts, it gets one.
            while (f.tree.proxyCount() < DynamicTree::kBranchFreeDescentLeaves) {
                const AABB b = AABB::fromCenterHalf(Vec3{step(rng), step(rng), step(rng)} * 10, Vec3::splat(Real(0.5)));
                f.ids.push_back(f.tree.createProxy(b, 900000u + static_cast<std::uint32_t>(f.ids.size()), Vec3::zero()));
                f.tight.push_back(b);
            }
        }
        EXPECT_FALSE(f.tree.selfDescentPrepared());
        f.tree.prepareSelfDescent();
        expectCopyDescentIsThePools(f, rng, "copy after reinsertions", true);

        // Every change to the tree puts the copy out of use; the pool's
        // descent then still finds exactly brute force's pairs.
        const auto expectStaleUnused = [&](const char* what) {
            EXPECT_FALSE(f.tree.selfDescentPrepared()) << what;
            expectSameDescent(f.tree, f.tree.root(), f.tree, f.tree.root(), 0, what);
            f.tree.prepareSelfDescent();
            expectSameDescent(f.tree, f.tree.root(), f.tree, f.tree.root(), 0, what);
        };
        const Vec3 d{5, -4, 3};
        f.tight[5] = AABB{f.tight[5].min + d, f.tight[5].max + d};
        f.tree.moveProxy(f.ids[5], f.tight[5], d);
        expectStaleUnused("after a move");
        f.tree.setFatBox(f.ids[9], f.tight[9], Vec3{6, 0, 0});
        f.tree.reinsert(f.ids[9]);
        expectStaleUnused("after setFatBox and reinsert");
        f.tree.destroyProxy(f.ids.back());
        f.ids.pop_back();
        f.tight.pop_back();
        expectStaleUnused("after a removal");
        const AABB b = AABB::fromCenterHalf(Vec3{1, 2, 3}, Vec3::splat(2));
        f.ids.push_back(f.tree.createProxy(b, 800000u, Vec3::zero()));
        f.tight.push_back(b);
        expectStaleUnused("after an insertion");
        f.tree.rebuild();
        expectStaleUnused("after a rebuild");
        EXPECT_EQ(f.tree.validate(), "");

        // Bulk motion: the refit writes the copy itself (a rebuild leaves it
        // to prepareSelfDescent); either way the same calls as the pool's.
        int refits = 0;
        for (int round = 0; round < 5; ++round) {
            for (std::size_t k = 0; k < f.ids.size(); ++k) {
                const Vec3 m{step(rng), step(rng), step(rng)};
                f.tight[k] = AABB{f.tight[k].min + m, f.tight[k].max + m};
                f.tree.setFatBox(f.ids[k], f.tight[k], m);
            }
            if (!f.tree.refitOrRebuild()) {
                ++refits;
                EXPECT_TRUE(f.tree.selfDescentPrepared());
            } else {
                EXPECT_FALSE(f.tree.selfDescentPrepared());
                f.tree.prepareSelfDescent();
            }
            ASSERT_EQ(f.tree.validate(), "");
            expectCopyDescentIsThePools(f, rng, "copy after a bulk update", round == 0);
        }
        EXPECT_GT(refits, 0);
    }
}

TEST(OverlapPairsOrder, OneLeafTreesAndEmptyTrees) {
    DynamicTree one, two, empty;
    const std::int32_t a = one.createProxy(AABB{Vec3::splat(0), Vec3::splat(1)}, 7);
    const std::int32_t b = two.createProxy(AABB{Vec3::splat(Real(0.5)), Vec3::splat(2)}, 9);
    bool ran = false;
    EXPECT_TRUE(newDescent(one, a, one, a, 0, ran).empty());  // a leaf holds no pair
    EXPECT_TRUE(ran);
    EXPECT_EQ(newDescent(one, a, two, b, 0, ran), (Calls{{7, 9}}));
    EXPECT_TRUE(ran);
    EXPECT_EQ(newDescent(one, a, two, b, 1, ran), (Calls{{7, 9}}));
    EXPECT_FALSE(ran);  // the callback stopped it
    EXPECT_TRUE(newDescent(one, a, empty, empty.root(), 0, ran).empty());
    EXPECT_TRUE(ran);
}

}  // namespace
}  // namespace fulcrum
