// DynamicTree::rebuild (the bulk build of a million static boxes, the moving
// tree's rebuilds) against an exact reference: the binned-SAH build written
// plainly here, as the tree built it before its binning was made cheaper
// (branch `bigworld`). Same leaves in, the same tree out: the same split of
// every range, the same child order, leaf for leaf. The tree's shape reaches
// the particle coupling's candidate order and an over-the-limit pair update's
// share, so a cheaper build must not change it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "collision/dynamic_tree.hpp"

namespace fulcrum {
namespace {

struct Item {
    AABB box;
    Vec3 centroid;
    std::uint32_t value;
};

// The reference partition: the longest axis of the centres, 16 bins, the
// cheapest split between non-empty bins, two leaves ordered by the first
// axis they differ on, up to 6 leaves halved at the axis's middle.
std::size_t referencePartition(std::vector<Item>& items, std::size_t begin, std::size_t end, const AABB& centroidBox,
                               AABB& leftCentroids, AABB& rightCentroids) {
    constexpr int kBins = 16;
    const Vec3 extent = centroidBox.max - centroidBox.min;
    leftCentroids = AABB{};
    rightCentroids = AABB{};
    if (end - begin == 2) {
        for (std::size_t axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > Real(0))) continue;
            if (items[begin + 1].centroid[axis] < items[begin].centroid[axis]) std::swap(items[begin], items[begin + 1]);
            break;
        }
        leftCentroids.grow(items[begin].centroid);
        rightCentroids.grow(items[begin + 1].centroid);
        return begin + 1;
    }
    std::size_t axis = 0;
    if (extent.y > extent[axis]) axis = 1;
    if (extent.z > extent[axis]) axis = 2;
    if (end - begin <= 6) {
        std::size_t left = begin;
        if (extent[axis] > Real(0)) {
            const Real mid = Real(0.5) * (centroidBox.min[axis] + centroidBox.max[axis]);
            std::size_t right = end;
            while (left < right) {
                if (items[left].centroid[axis] <= mid) {
                    ++left;
                } else {
                    std::swap(items[left], items[--right]);
                }
            }
        }
        if (left == begin || left == end) left = begin + (end - begin) / 2;
        for (std::size_t i = begin; i < left; ++i) leftCentroids.grow(items[i].centroid);
        for (std::size_t i = left; i < end; ++i) rightCentroids.grow(items[i].centroid);
        return left;
    }
    if (!(extent[axis] > Real(0))) {
        leftCentroids = rightCentroids = centroidBox;
        return begin + (end - begin) / 2;
    }
    AABB binBox[kBins];
    std::uint32_t binCount[kBins] = {};
    const Real scale = Real(kBins) / extent[axis];
    const Real origin = centroidBox.min[axis];
    // NaN and values past int's range to bin 0 (as x86's truncation to
    // INT_MIN and the clamp did), without the undefined conversion.
    const auto binOf = [&](const Vec3& c) {
        const Real t = (c[axis] - origin) * scale;
        return t >= 0 && t < Real(2147483648.0) ? std::min(static_cast<int>(t), kBins - 1) : 0;
    };
    for (std::size_t i = begin; i < end; ++i) {
        const int k = binOf(items[i].centroid);
        if (binCount[k]++ == 0) {
            binBox[k] = items[i].box;
        } else {
            binBox[k].grow(items[i].box);
        }
    }
    Real bestCost = std::numeric_limits<Real>::max();
    int bestSplit = -1;
    for (int split = 0; split + 1 < kBins; ++split) {  // every split, empty bins included: the first best wins
        AABB a, b;
        std::size_t na = 0, nb = 0;
        for (int k = 0; k < kBins; ++k) {
            if (binCount[k] == 0) continue;
            if (k <= split) {
                a.grow(binBox[k]);
                na += binCount[k];
            } else {
                b.grow(binBox[k]);
                nb += binCount[k];
            }
        }
        if (na == 0 || nb == 0) continue;
        const Real cost = a.surfaceArea() * static_cast<Real>(na) + b.surfaceArea() * static_cast<Real>(nb);
        if (cost < bestCost) {
            bestCost = cost;
            bestSplit = split;
        }
    }
    int usedBins = 0, firstUsed = 0;
    for (int k = kBins - 1; k >= 0; --k) {
        if (binCount[k] != 0) {
            ++usedBins;
            firstUsed = k;
        }
    }
    // No cost below the float maximum (infinite areas): the first used bin
    // goes left, as the tree's sweep leaves it.
    if (bestSplit < 0 && usedBins >= 2) bestSplit = firstUsed;
    if (usedBins < 2) {  // one bin used (a scale or offsets not finite): halved (branch `lw9`)
        const std::size_t mid = begin + (end - begin) / 2;
        for (std::size_t i = begin; i < mid; ++i) leftCentroids.grow(items[i].centroid);
        for (std::size_t i = mid; i < end; ++i) rightCentroids.grow(items[i].centroid);
        return mid;
    }
    std::size_t left = begin, right = end;
    while (left < right) {
        if (binOf(items[left].centroid) <= bestSplit) {
            leftCentroids.grow(items[left].centroid);
            ++left;
        } else {
            --right;
            rightCentroids.grow(items[left].centroid);
            std::swap(items[left], items[right]);
        }
    }
    return left;
}

// Pre-order: a leaf as its user value, an internal node as -1.
void referenceBuild(std::vector<Item>& items, std::size_t begin, std::size_t end, const AABB& centroidBox,
                    std::vector<std::int64_t>& out) {
    if (end - begin == 1) {
        out.push_back(items[begin].value);
        return;
    }
    out.push_back(-1);
    AABB leftCentroids, rightCentroids;
    const std::size_t split = referencePartition(items, begin, end, centroidBox, leftCentroids, rightCentroids);
    referenceBuild(items, begin, split, leftCentroids, out);
    referenceBuild(items, split, end, rightCentroids, out);
}

void shapeOf(const DynamicTree& tree, std::int32_t id, std::vector<std::int64_t>& out) {
    const TreeNode& n = tree.nodes()[static_cast<std::size_t>(id)];
    if (n.isLeaf()) {
        out.push_back(n.userValue);
        return;
    }
    out.push_back(-1);
    shapeOf(tree, n.child1, out);
    shapeOf(tree, n.child2, out);
}

// Builds `boxes` with DynamicTree::rebuild and with the reference; the two
// pre-order shapes must be equal.
void expectReferenceShape(const std::vector<AABB>& boxes, const char* what) {
    DynamicTree tree({0, 0, DynamicTreeConfig::Search::BranchAndBound});
    for (std::size_t i = 0; i < boxes.size(); ++i) tree.createProxyDeferred(boxes[i], static_cast<std::uint32_t>(i));
    tree.rebuild();
    ASSERT_EQ(tree.validate(), "") << what;
    std::vector<std::int64_t> built;
    shapeOf(tree, tree.root(), built);

    // The tree takes its leaves in node order, which for proxies made on an
    // empty tree is creation order.
    std::vector<Item> items;
    AABB centroidBox;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        const AABB fat = tree.fatAABB(static_cast<std::int32_t>(i));
        items.push_back({fat, fat.center(), tree.userValue(static_cast<std::int32_t>(i))});
        centroidBox.grow(fat.center());
    }
    std::vector<std::int64_t> reference;
    referenceBuild(items, 0, items.size(), centroidBox, reference);
    EXPECT_EQ(built, reference) << what << ": " << boxes.size() << " leaves";
}

TEST(BulkBuild, RandomBoxesGiveTheReferenceTree) {
    std::mt19937 rng(11);
    for (const std::size_t count : {3u, 7u, 8u, 17u, 100u, 5000u}) {
        std::uniform_real_distribution<float> at(-50, 50), half(0.05f, 4);
        std::vector<AABB> boxes;
        for (std::size_t i = 0; i < count; ++i) {
            boxes.push_back(AABB::fromCenterHalf({at(rng), at(rng), at(rng)}, {half(rng), half(rng), half(rng)}));
        }
        expectReferenceShape(boxes, "random boxes");
    }
}

TEST(BulkBuild, GridsWithTiesAndCoincidentCentresGiveTheReferenceTree) {
    // large_world's ground: equal boxes on a grid (every split ties with its
    // mirror image); a grid with every box twice (coincident centres); and a
    // flat, thin cluster (the longest axis changes from level to level).
    std::vector<AABB> grid, doubled, flat;
    for (int i = 0; i < 60; ++i) {
        for (int j = 0; j < 70; ++j) {
            const AABB b = AABB::fromCenterHalf({Real(i) - 30, Real(-0.5), Real(j) - 35}, {Real(0.5), Real(0.5), Real(0.5)});
            grid.push_back(b);
            doubled.push_back(b);
            doubled.push_back(b);
            flat.push_back(AABB::fromCenterHalf({Real(i) * Real(0.37), Real(j % 3) * Real(0.01), Real(j) * Real(0.05)},
                                                {Real(0.2), Real(0.01), Real(0.03)}));
        }
    }
    expectReferenceShape(grid, "grid");
    expectReferenceShape(doubled, "doubled grid");
    expectReferenceShape(flat, "flat cluster");
    expectReferenceShape(std::vector<AABB>(40, AABB({0, 0, 0}, {1, 1, 1})), "one box forty times");
}

TEST(BulkBuild, CentresAtTheFloatRangesEndsGiveTheReferenceTree) {
    // The binning clamps a leaf's bin only at the top when the centres'
    // extent and the scale 16 / extent are finite (branch `lw9`); here they
    // may not be: centres near the float range's ends (an extent near
    // FLT_MAX; infinite centres, whose extent is infinite and offsets NaN),
    // and centres a few subnormals apart (an infinite scale). The last two
    // put every leaf in one bin, where the build looped for ever before
    // `lw9`; such a range is halved now.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> at(-50, 50), half(0.05f, 4);
    const auto ordinary = [&](std::vector<AABB>& boxes, int count) {
        for (int i = 0; i < count; ++i) {
            boxes.push_back(AABB::fromCenterHalf({at(rng), at(rng), at(rng)}, {half(rng), half(rng), half(rng)}));
        }
    };
    std::vector<AABB> far, infinite, subnormal;
    for (const float x : {-1.8e38f, -1.0e38f, 1.0e38f, 1.8e38f, 1.7e38f, -1.7e38f}) {
        far.push_back(AABB({x, 0, 0}, {x, 1, 1}));  // centre x (+-1.7e38: an extent near FLT_MAX), or +-inf (2x overflows)
        infinite.push_back(AABB::fromCenterHalf({x, 0, 0}, {1, 1, 1}));
        infinite.push_back(AABB({x, 0, 0}, {std::numeric_limits<float>::max(), 1, 1}));  // centre +inf
    }
    ordinary(far, 40);
    ordinary(infinite, 40);
    const float tiny = std::numeric_limits<float>::denorm_min();
    for (int k = 0; k < 40; ++k) {
        const Vec3 c{static_cast<float>(k % 19) * tiny, static_cast<float>(k % 7) * tiny, 0};
        subnormal.push_back(AABB(c, c));  // centre c exactly: the extents are subnormal
    }
    expectReferenceShape(far, "centres near the float range's ends");
    expectReferenceShape(infinite, "infinite centres");
    expectReferenceShape(subnormal, "centres a few subnormals apart");
    ordinary(subnormal, 40);
    expectReferenceShape(subnormal, "subnormal centres among ordinary boxes");
}

}  // namespace
}  // namespace fulcrum
