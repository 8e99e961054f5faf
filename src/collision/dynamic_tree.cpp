// Dynamic AABB tree: insertion by exact branch-and-bound SAH sibling search,
// area-reducing tree rotations, removal, fattened moves, binned-SAH rebuild
// and structural validation. See dynamic_tree.hpp for the design.
#include "collision/dynamic_tree.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstddef>
#include <limits>
#include <sstream>
#include <type_traits>

// The bulk build's binning in SSE lanes (partitionRange): float builds on x86.
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
#include <immintrin.h>
#define FULCRUM_TREE_SSE 1
#else
#define FULCRUM_TREE_SSE 0
#endif

namespace fulcrum {

namespace {

Real area(const AABB& b) { return b.surfaceArea(); }

std::int16_t heightAbove(std::int16_t a, std::int16_t b) {
    return static_cast<std::int16_t>(1 + (a > b ? a : b));
}

}  // namespace

DynamicTree::DynamicTree(const DynamicTreeConfig& config) : config_(config) {}

// ---- node pool ----------------------------------------------------------------

std::int32_t DynamicTree::allocateNode() {
    descentValid_ = false;
    if (freeList_ == kNullNode) {
        // Grow by doubling and thread the new nodes onto the free list in index
        // order, so allocation order (and thus ids) depends only on the history
        // of operations.
        const std::size_t oldSize = nodes_.size();
        const std::size_t newSize = oldSize == 0 ? 16 : 2 * oldSize;
        nodes_.resize(newSize);
        for (std::size_t i = oldSize; i < newSize; ++i) {
            nodes_[i].parent = i + 1 < newSize ? static_cast<std::int32_t>(i + 1) : kNullNode;
            nodes_[i].height = -1;
        }
        freeList_ = static_cast<std::int32_t>(oldSize);
    }
    const std::int32_t id = freeList_;
    TreeNode& n = node(id);
    freeList_ = n.parent;
    n = TreeNode{};
    n.height = 0;
    return id;
}

void DynamicTree::freeNode(std::int32_t id) {
    descentValid_ = false;
    TreeNode& n = node(id);
    n = TreeNode{};
    n.parent = freeList_;
    n.height = -1;
    freeList_ = id;
}

AABB DynamicTree::fatten(const AABB& tight, const Vec3& displacement) const {
    AABB fat = tight.fattened(config_.margin);
    const Vec3 d = displacement * config_.displacementScale;
    for (std::size_t i = 0; i < 3; ++i) {
        if (d[i] < Real(0)) {
            fat.min[i] += d[i];
        } else {
            fat.max[i] += d[i];
        }
    }
    return fat;
}

void DynamicTree::reserve(std::size_t proxies) {
    if (proxies > 0) nodes_.reserve(std::bit_ceil(2 * proxies));
}

// ---- proxies --------------------------------------------------------------------

std::int32_t DynamicTree::createProxy(const AABB& tightBox, std::uint32_t userValue, const Vec3& displacement) {
    assert(isFinite(tightBox.min) && isFinite(tightBox.max) && !tightBox.isEmpty());
    if (hasPending()) insertPending();
    const std::int32_t leaf = allocateNode();
    TreeNode& n = node(leaf);
    n.box = fatten(tightBox, displacement);
    n.userValue = userValue;
    n.height = 0;
    insertLeaf(leaf);
    ++proxyCount_;
    return leaf;
}

std::int32_t DynamicTree::createProxyDeferred(const AABB& tightBox, std::uint32_t userValue) {
    assert(isFinite(tightBox.min) && isFinite(tightBox.max) && !tightBox.isEmpty());
    const std::int32_t leaf = allocateNode();
    TreeNode& n = node(leaf);
    n.box = fatten(tightBox, Vec3::zero());
    n.userValue = userValue;
    n.height = 0;
    pending_.push_back(leaf);
    ++proxyCount_;
    return leaf;
}

void DynamicTree::insertPending() {
    if (pending_.empty()) return;
    const std::size_t inTree = static_cast<std::size_t>(proxyCount_) - pending_.size();
    if (pending_.size() >= kBulkMinLeaves && pending_.size() * kBulkShare >= inTree) {
        rebuild();  // takes every leaf, the waiting ones too, and clears pending_
        return;
    }
    for (const std::int32_t leaf : pending_) insertLeaf(leaf);
    pending_.clear();
}

void DynamicTree::destroyProxy(std::int32_t proxyId) {
    assert(isProxy(proxyId));
    if (hasPending()) insertPending();
    removeLeaf(proxyId);
    freeNode(proxyId);
    --proxyCount_;
}

bool DynamicTree::mustMove(std::int32_t proxyId, const AABB& tightBox, const Vec3& displacement) const {
    assert(isProxy(proxyId));
    assert(isFinite(tightBox.min) && isFinite(tightBox.max) && !tightBox.isEmpty());
    const AABB& stored = nodes_[static_cast<std::size_t>(proxyId)].box;
    if (!stored.contains(tightBox)) return true;
    // Still inside, but maybe far too large: a body that moved fast and then
    // slowed down keeps a long box and collects useless pairs. Shrink when
    // the stored box pokes out of a generous envelope around the tight box
    // (4 margins plus the predicted motion both ways; the idea is from
    // Box2D 2.4's MoveProxy). A steady mover never triggers this.
    const Vec3 reach = abs(displacement * config_.displacementScale) + Vec3::splat(4 * config_.margin);
    const AABB envelope{tightBox.min - reach, tightBox.max + reach};
    return !envelope.contains(stored);
}

bool DynamicTree::moveProxy(std::int32_t proxyId, const AABB& tightBox, const Vec3& displacement) {
    if (!mustMove(proxyId, tightBox, displacement)) return false;
    if (hasPending()) insertPending();  // before the box changes: the leaf goes in with the box it was created with
    node(proxyId).box = fatten(tightBox, displacement);
    reinsert(proxyId);
    return true;
}

// Where the new box fits in the box of its parent (or of an ancestor up to
// kInPlaceLevels above it), a removal and insertion would most likely put the
// leaf back in the same small subtree, after a greedy descent and rotations
// all the way up: the refit alone keeps the tree's quality close at a
// fraction of the cost. The boxes below the ancestor stay inside its box (a
// refit only merges children that lie in it), so a leaf that wanders off
// leaves it and is reinserted; the quality cannot drift without bound.
// Measured, levels 1 / 2 / 3 / 4 (the parent alone / up to the grandparent /
// ...): chain benchmark, 600 steps, callgrind (the links swinging at up to
// 40 m/s left their boxes a third of the steps): 1,137 M without the
// in-place update, 1,099 M with one level (same build otherwise); on a
// later build 1,082 / 1,068 / 1,053 / 1,044 M; bench_broadphase
// BM_StepBoxes (10,000 boxes at up to 4 m/s, default prediction), CPU per
// step 4.08 / 3.45 / 2.89 ms (same run), tree area vs a SAH rebuild 1.070 /
// 1.085 / 1.094. Three levels: most of the gain for 2 % more tree area.
// With several leaves given new boxes before their reinsertions (setFatBox),
// the ancestors' boxes may be stale; the test is then only a heuristic, and
// the refit, which merges the children's current boxes, keeps the tree exact:
// every stale ancestor lies on the path of a leaf still to be reinserted.
bool DynamicTree::updateInPlace(std::int32_t leaf) {
    descentValid_ = false;
    const std::int32_t parent = node(leaf).parent;
    if (parent == kNullNode) return true;  // the root: its box is the leaf's
    std::int32_t host = parent;
    for (int k = 1; k < kInPlaceLevels && node(host).parent != kNullNode; ++k) host = node(host).parent;
    if (!node(host).box.contains(node(leaf).box)) return false;
    for (std::int32_t i = parent; i != kNullNode; i = node(i).parent) {
        TreeNode& n = node(i);
        const AABB box = merge(node(n.child1).box, node(n.child2).box);
        if (box == n.box) break;
        n.box = box;
    }
    return true;
}

// ---- insertion ----------------------------------------------------------------

// Two searches for the sibling of a new leaf, measured with bench_broadphase
// (incremental tree area / binned-SAH rebuild of the same boxes; time):
//   inserting 10,000 random boxes: greedy 1.24, ~0.65 us per insert;
//                                  branch and bound 1.12, ~2.1 us per insert;
//   10,000 boxes after 2 s of motion (reinsertions keep refining the tree):
//                                  greedy 1.06-1.07, branch and bound 1.04-1.05,
//                                  with the whole step about 1.9x slower.
// So moving trees use the greedy search and the static tree (built once,
// queried every step) uses branch and bound, or better, rebuild().
//
// Branch and bound (Bittner et al. 2013). Making `s` the sibling of the new
// leaf L costs area(s ∪ L) for the new parent plus, for every ancestor a of s,
// the growth area(a ∪ L) - area(a) ("inherited cost"). Below a node, no
// sibling can cost less than area(L) + the node's inherited cost plus its own
// growth, so subtrees whose bound is no better than the best found are cut.
// Candidates are expanded cheapest-inherited-cost first.
std::int32_t DynamicTree::findBestSibling(const AABB& leafBox) {
    const Real leafArea = area(leafBox);
    std::int32_t best = root_;
    Real bestCost = area(merge(node(root_).box, leafBox));
    Real bestInherited = 0;

    const auto cheaperFirst = [](const Candidate& a, const Candidate& b) { return a.inheritedCost > b.inheritedCost; };
    candidates_.clear();
    candidates_.push_back({root_, Real(0)});
    while (!candidates_.empty()) {
        std::pop_heap(candidates_.begin(), candidates_.end(), cheaperFirst);
        const Candidate c = candidates_.back();
        candidates_.pop_back();
        if (c.inheritedCost + leafArea >= bestCost) continue;

        const TreeNode& n = node(c.node);
        const Real mergedArea = area(merge(n.box, leafBox));
        const Real cost = mergedArea + c.inheritedCost;
        if (cost < bestCost) {
            bestCost = cost;
            best = c.node;
            bestInherited = c.inheritedCost;
        }
        if (n.isLeaf()) continue;
        const Real childInherited = c.inheritedCost + (mergedArea - area(n.box));
        if (childInherited + leafArea < bestCost) {
            candidates_.push_back({n.child1, childInherited});
            std::push_heap(candidates_.begin(), candidates_.end(), cheaperFirst);
            candidates_.push_back({n.child2, childInherited});
            std::push_heap(candidates_.begin(), candidates_.end(), cheaperFirst);
        }
    }
    // Ties. Among siblings of equal cost the search keeps the highest one, which
    // for identical or nested boxes (all costs equal) would put every new leaf
    // next to the root and grow the height by one per insertion (measured:
    // height 45 for 1,024 identical boxes, even with height-aware rotations).
    // So descend while a child costs exactly as much, into the lower child.
    while (!node(best).isLeaf()) {
        const TreeNode& n = node(best);
        const Real childInherited = bestInherited + (area(merge(n.box, leafBox)) - area(n.box));
        const TreeNode& c1 = node(n.child1);
        const TreeNode& c2 = node(n.child2);
        const bool tie1 = area(merge(c1.box, leafBox)) + childInherited <= bestCost;
        const bool tie2 = area(merge(c2.box, leafBox)) + childInherited <= bestCost;
        if (!tie1 && !tie2) break;
        best = (tie1 && (!tie2 || c1.height <= c2.height)) ? n.child1 : n.child2;
        bestInherited = childInherited;
    }
    return best;
}

// Greedy descent (after Catto 2019): from the root, price both children -- a
// leaf exactly, an internal node by the lower bound of anything in its subtree
// -- and walk into the cheaper one while it can still beat the best sibling
// found. Exact costs of the children visited update the best. Ties (identical
// or nested boxes) descend too, into the lower child, so that equal boxes fill
// the tree breadth-first instead of stacking up at the root.
std::int32_t DynamicTree::findBestSiblingGreedy(const AABB& leafBox) const {
    const Real leafArea = area(leafBox);
    std::int32_t best = root_;
    Real bestCost = area(merge(node(root_).box, leafBox));
    Real inherited = 0;
    std::int32_t at = root_;
    while (!node(at).isLeaf()) {
        const TreeNode& n = node(at);
        const Real childInherited = inherited + (area(merge(n.box, leafBox)) - area(n.box));
        Real score[2];
        const std::int32_t child[2] = {n.child1, n.child2};
        for (int k = 0; k < 2; ++k) {
            const TreeNode& c = node(child[k]);
            const Real exact = area(merge(c.box, leafBox)) + childInherited;
            if (exact <= bestCost) {
                bestCost = exact;
                best = child[k];
            }
            const Real below = childInherited + (exact - childInherited - area(c.box)) + leafArea;
            score[k] = c.isLeaf() ? exact : std::min(exact, below);
        }
        const int pick = score[0] < score[1] ? 0
                         : score[1] < score[0] ? 1
                         : (node(child[0]).height <= node(child[1]).height ? 0 : 1);
        if (score[pick] > bestCost) break;
        at = child[pick];
        inherited = childInherited;
    }
    return best;
}

void DynamicTree::insertLeaf(std::int32_t leaf) {
    descentValid_ = false;
    if (root_ == kNullNode) {
        root_ = leaf;
        node(leaf).parent = kNullNode;
        return;
    }
    const AABB leafBox = node(leaf).box;
    const std::int32_t sibling = config_.search == DynamicTreeConfig::Search::Greedy ? findBestSiblingGreedy(leafBox)
                                                                                      : findBestSibling(leafBox);

    const std::int32_t newParent = allocateNode();  // may reallocate nodes_: indices only from here
    const std::int32_t oldParent = node(sibling).parent;
    {
        TreeNode& p = node(newParent);
        p.parent = oldParent;
        p.child1 = sibling;
        p.child2 = leaf;
        p.box = merge(leafBox, node(sibling).box);
        p.height = static_cast<std::int16_t>(node(sibling).height + 1);
    }
    if (oldParent == kNullNode) {
        root_ = newParent;
    } else if (node(oldParent).child1 == sibling) {
        node(oldParent).child1 = newParent;
    } else {
        node(oldParent).child2 = newParent;
    }
    node(sibling).parent = newParent;
    node(leaf).parent = newParent;

    for (std::int32_t i = newParent; i != kNullNode; i = node(i).parent) {
        refit(i);
        rotate(i);
    }
}

void DynamicTree::refit(std::int32_t i) {
    TreeNode& n = node(i);
    const TreeNode& a = node(n.child1);
    const TreeNode& b = node(n.child2);
    n.box = merge(a.box, b.box);
    n.height = heightAbove(a.height, b.height);
}

// Tree rotations (Catto, GDC 2019). Node A has children B and C; B has
// children D, E and C has F, G. Swapping B with F or G (or C with D or E)
// keeps A's box but changes C's (or B's) box; take the swap that shrinks it
// most. When no swap shrinks any area but one keeps the area and lowers A's
// height, take that one: this breaks ties among identical or nested boxes,
// which area alone cannot order and which would otherwise grow a list.
void DynamicTree::rotate(std::int32_t a) {
    TreeNode& A = node(a);
    if (A.height < 2) return;
    const std::int32_t b = A.child1, c = A.child2;
    const TreeNode& B = node(b);
    const TreeNode& C = node(c);

    enum Swap { None, BF, BG, CD, CE };
    Swap best = None;
    Real bestDiff = 0;
    Swap tallest = None;  // area-neutral swap that lowers A's height the most
    int bestHeight = A.height;

    const auto consider = [&](Swap s, Real diff, int newHeight) {
        if (diff < bestDiff) {
            bestDiff = diff;
            best = s;
        }
        if (diff <= Real(0) && newHeight < bestHeight) {
            bestHeight = newHeight;
            tallest = s;
        }
    };
    if (!C.isLeaf()) {
        const TreeNode& F = node(C.child1);
        const TreeNode& G = node(C.child2);
        const Real areaC = area(C.box);
        consider(BF, area(merge(B.box, G.box)) - areaC, 1 + std::max<int>(F.height, heightAbove(B.height, G.height)));
        consider(BG, area(merge(B.box, F.box)) - areaC, 1 + std::max<int>(G.height, heightAbove(B.height, F.height)));
    }
    if (!B.isLeaf()) {
        const TreeNode& D = node(B.child1);
        const TreeNode& E = node(B.child2);
        const Real areaB = area(B.box);
        consider(CD, area(merge(C.box, E.box)) - areaB, 1 + std::max<int>(D.height, heightAbove(C.height, E.height)));
        consider(CE, area(merge(C.box, D.box)) - areaB, 1 + std::max<int>(E.height, heightAbove(C.height, D.height)));
    }
    const Swap chosen = best != None ? best : tallest;
    if (chosen == None) return;

    // Swap `up` (a grandchild under `mid`) with `across` (A's other child).
    const auto swapUp = [&](std::int32_t across, std::int32_t mid, bool upIsFirst) {
        TreeNode& M = node(mid);
        const std::int32_t up = upIsFirst ? M.child1 : M.child2;
        if (upIsFirst) {
            M.child1 = across;
        } else {
            M.child2 = across;
        }
        node(across).parent = mid;
        TreeNode& An = node(a);
        if (An.child1 == across) {
            An.child1 = up;
        } else {
            An.child2 = up;
        }
        node(up).parent = a;
        refit(mid);
        refit(a);
    };
    switch (chosen) {
        case BF: swapUp(b, c, true); break;
        case BG: swapUp(b, c, false); break;
        case CD: swapUp(c, b, true); break;
        case CE: swapUp(c, b, false); break;
        case None: break;
    }
}

// ---- removal --------------------------------------------------------------------

void DynamicTree::removeLeaf(std::int32_t leaf) {
    descentValid_ = false;
    if (leaf == root_) {
        root_ = kNullNode;
        return;
    }
    const std::int32_t parent = node(leaf).parent;
    const std::int32_t grandParent = node(parent).parent;
    const std::int32_t sibling = node(parent).child1 == leaf ? node(parent).child2 : node(parent).child1;

    if (grandParent == kNullNode) {
        root_ = sibling;
        node(sibling).parent = kNullNode;
        freeNode(parent);
        return;
    }
    TreeNode& g = node(grandParent);
    if (g.child1 == parent) {
        g.child1 = sibling;
    } else {
        g.child2 = sibling;
    }
    node(sibling).parent = grandParent;
    freeNode(parent);
    // Refit only. Rotating here too was measured (bench BM_StepBoxes, 10,000
    // moving boxes): about 1% less tree area for about 15% more step time, so
    // rotations happen on insertion only, as in Box2D v3.
    for (std::int32_t i = grandParent; i != kNullNode; i = node(i).parent) refit(i);
}

// ---- rebuild (binned SAH) ---------------------------------------------------------

// Top-down build: split each range of leaves where the SAH estimate
// area(left) * count(left) + area(right) * count(right) is least, over 16
// centroid bins on the longest axis of the range's centres (Wald 2007, "On
// fast Construction of SAH-based Bounding Volume Hierarchies"); ranges of at
// most kSmallRange leaves at the middle of that axis. Ranges are processed
// with an explicit stack, so a skewed split cannot overflow the call stack.
//
// Cost: each level of the build reads every leaf twice, once to bin it
// and once to partition it (which also gathers the two
// halves' centroid boxes for the next level); the leaves' boxes and centres
// sit in one array that the partition permutes, and the internal nodes'
// boxes are merged bottom-up at the end; the split search sweeps only the
// non-empty bins. The bins, costs and splits are computed as before, so the
// trees are the same (checked against the former build on random, grid and
// identical boxes), for fewer instructions (callgrind): a million static
// boxes (large_world) 4.6 G before, 3.2 G now; 5000 random unit boxes (a
// jolt_high_speed moving tree) 30.6 M before, 16.1 M now. Then binning the
// longest axis only and splitting small ranges at the middle (the trees
// change, no result does): 10,000 static boxes (large_world(100)) 24.5 M to
// 16.4 M, with the queries of HighSpeed's moving tree costing the same.
void DynamicTree::rebuild() {
    descentValid_ = false;
    if (proxyCount_ < 2) {
        for (const std::int32_t leaf : pending_) insertLeaf(leaf);  // at most one
        pending_.clear();
        return;
    }
    pending_.clear();  // every leaf is taken below
    buildItems_.clear();
    buildItems_.reserve(static_cast<std::size_t>(proxyCount_));
    AABB centroidBox;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        if (nodes_[i].height == 0) {
            const Vec3 c = nodes_[i].box.center();
            buildItems_.push_back({nodes_[i].box, c, static_cast<std::int32_t>(i)});
            centroidBox.grow(c);
        }
    }
    // Free every internal node (highest index first, so that the rebuilt tree
    // takes the lowest free indices again: ids stay compact).
    for (std::size_t i = nodes_.size(); i-- > 0;) {
        if (nodes_[i].height > 0) freeNode(static_cast<std::int32_t>(i));
    }
    buildOrder_.clear();

    std::vector<BuildTask>& tasks = buildTasks_;
    tasks.clear();
    tasks.push_back({0, buildItems_.size(), kNullNode, true, centroidBox});
    root_ = kNullNode;
    while (!tasks.empty()) {
        const BuildTask t = tasks.back();
        tasks.pop_back();
        std::int32_t self;
        if (t.end - t.begin == 1) {
            self = buildItems_[t.begin].leaf;
        } else {
            self = allocateNode();
            buildOrder_.push_back(self);
            AABB leftCentroids, rightCentroids;
            const std::size_t split = partitionRange(t.begin, t.end, t.centroidBox, leftCentroids, rightCentroids);
            node(self).height = 1;  // box and height fixed up below
            tasks.push_back({split, t.end, self, false, rightCentroids});
            tasks.push_back({t.begin, split, self, true, leftCentroids});
        }
        node(self).parent = t.parent;
        if (t.parent == kNullNode) {
            root_ = self;
        } else if (t.first) {
            node(t.parent).child1 = self;
        } else {
            node(t.parent).child2 = self;
        }
    }
    // Children were allocated after their parents: fix boxes and heights in reverse.
    for (std::size_t i = buildOrder_.size(); i-- > 0;) {
        TreeNode& n = node(buildOrder_[i]);
        const TreeNode& a = node(n.child1);
        const TreeNode& b = node(n.child2);
        n.box = merge(a.box, b.box);
        n.height = heightAbove(a.height, b.height);
    }
}

// Refit or rebuild, for a moving tree whose leaves nearly all moved (Jolt's
// HighSpeed: 5000 bodies at up to 250 m/s, every fat box new each step).
// A rebuild costs ~3 us per leaf; a refit ~0.05 us per node, but keeps the
// shape chosen for where the leaves were, and the bodies drift apart from
// their tree neighbours, so the internal boxes loosen and each query visits
// more of the tree. Looseness: the internal nodes' total area over the
// leaves' (the SAH cost of a query, up to a constant, per unit of leaf
// area, so that boxes growing or shrinking with their bodies' speed do not
// count). Refit while it stays within kRefitSlack of the looseness right
// after the last rebuild, else rebuild. (The idea of keeping a tree's shape
// while its boxes move and rebuilding only when it has degraded is the
// usual one for moving BVHs; Box3D and Jolt both update their trees
// incrementally and rebuild in part or in the background.) Measured on
// HighSpeed: see docs/broad-phase.md.
//
// Measured (callgrind, HighSpeed's steps 101-120, bench_high_speed_probe;
// the slack against the whole step's instructions): a rebuild every step
// before; slack 1.3, a rebuild every ~5 steps; 2.0, every ~10 steps, 2 %
// fewer instructions than 1.3 (the queries cost 16 % more, the rebuilds a
// third); 3.0, 2 % more than 2.0 (the queries' growth wins).
namespace {
constexpr double kRefitSlack = 2.0;
}  // namespace

bool DynamicTree::refitOrRebuild() {
    descentValid_ = false;
    if (hasPending()) insertPending();
    if (rebuiltLooseness_ > 0 && root_ != kNullNode && !node(root_).isLeaf()) {
        double leafArea = 0, internalArea = 0;
        if (proxyCount_ >= kBranchFreeDescentLeaves) {
            // Every node in pre-order (each after its ancestors) into the
            // depth-first copy (prepareSelfDescent), then the internal nodes
            // merged in reverse, children before parents, from the copy's
            // boxes (a node's children lie next to it there) into both. The
            // same merges and sums in the same order as below.
            const std::size_t count = 2 * static_cast<std::size_t>(proxyCount_) - 1;
            if (descent_.size() < count) descent_.resize(count);
            descentIndexValid_ = false;  // left to prepareDescentIndex (a whole-tree descent needs none)
            buildOrder_.clear();       // the internal nodes in pre-order: their pool indices,
            descentInternal_.clear();  // and theirs in the copy
            DescentNode* copy = descent_.data();
            std::int32_t next = 0;
            detail::NodePairStack stack;  // (pool node, its parent's index in the copy when a second child, else -1)
            stack.push(root_, -1);
            while (!stack.empty()) {
                std::int32_t i, secondOf;
                stack.pop(i, secondOf);
                const TreeNode& n = node(i);
                const std::int32_t k = next++;
                if (secondOf >= 0) copy[secondOf].link = static_cast<std::uint32_t>(k);
                DescentNode& d = copy[k];
                if (n.isLeaf()) {
                    leafArea += static_cast<double>(area(n.box));
                    d.box = n.box;
                    d.area = Real(-1);
                    d.link = n.userValue;
                    continue;
                }
                buildOrder_.push_back(i);
                descentInternal_.push_back(k);
                stack.push(n.child2, k);
                stack.push(n.child1, -1);
            }
            assert(static_cast<std::size_t>(next) == count);
            for (std::size_t j = buildOrder_.size(); j-- > 0;) {
                const auto k = static_cast<std::size_t>(descentInternal_[j]);
                DescentNode& d = copy[k];
                d.box = merge(copy[k + 1].box, copy[d.link].box);
                d.area = area(d.box);
                node(buildOrder_[j]).box = d.box;
                internalArea += static_cast<double>(d.area);
            }
        } else {
            // Internal nodes in pre-order (each after its ancestors), then merged
            // in reverse: children before parents.
            buildOrder_.clear();
            std::vector<BuildTask>& stack = buildTasks_;  // only .parent used: the nodes still to visit
            stack.clear();
            stack.push_back({0, 0, root_, false, AABB{}});
            while (!stack.empty()) {
                const std::int32_t i = stack.back().parent;
                stack.pop_back();
                const TreeNode& n = node(i);
                if (n.isLeaf()) {
                    leafArea += static_cast<double>(area(n.box));
                    continue;
                }
                buildOrder_.push_back(i);
                stack.push_back({0, 0, n.child2, false, AABB{}});
                stack.push_back({0, 0, n.child1, false, AABB{}});
            }
            for (std::size_t k = buildOrder_.size(); k-- > 0;) {
                TreeNode& n = node(buildOrder_[k]);
                n.box = merge(node(n.child1).box, node(n.child2).box);
                internalArea += static_cast<double>(area(n.box));
            }
        }
        if (leafArea > 0 && internalArea <= kRefitSlack * rebuiltLooseness_ * leafArea) {
            descentValid_ = proxyCount_ >= kBranchFreeDescentLeaves;
            return false;
        }
    }
    rebuild();
    double internalArea = 0, leafArea = 0;
    for (const TreeNode& n : nodes_) {
        if (n.height > 0) internalArea += static_cast<double>(area(n.box));
        if (n.height == 0) leafArea += static_cast<double>(area(n.box));
    }
    rebuiltLooseness_ = leafArea > 0 ? internalArea / leafArea : 0;
    return true;
}

void DynamicTree::prepareSelfDescent() {
    if (descentValid_ || hasPending() || root_ == kNullNode || proxyCount_ < kBranchFreeDescentLeaves) return;
    // Pre-order: a node, its first subtree, then its second; the second
    // child's index is known when it is reached and written into its parent.
    const std::size_t count = 2 * static_cast<std::size_t>(proxyCount_) - 1;
    if (descent_.size() < count) descent_.resize(count);
    descentIndexValid_ = false;  // left to prepareDescentIndex (a whole-tree descent needs none)
    DescentNode* out = descent_.data();
    std::int32_t next = 0;
    detail::NodePairStack stack;  // (pool node, its parent's index in the copy when it is a second child, else -1)
    stack.push(root_, -1);
    while (!stack.empty()) {
        std::int32_t i, secondOf;
        stack.pop(i, secondOf);
        const TreeNode& n = node(i);
        const std::int32_t k = next++;
        if (secondOf >= 0) out[secondOf].link = static_cast<std::uint32_t>(k);
        DescentNode& d = out[k];
        d.box = n.box;
        if (n.isLeaf()) {
            d.area = Real(-1);
            d.link = n.userValue;
            continue;
        }
        d.area = n.box.surfaceArea();
        stack.push(n.child2, k);
        stack.push(n.child1, -1);
    }
    assert(static_cast<std::size_t>(next) == count);
    descentValid_ = true;
}

void DynamicTree::prepareDescentIndex() {
    if (!descentValid_ || descentIndexValid_) return;
    // The copy's pre-order (prepareSelfDescent's walk): node k of the copy is
    // the k-th node this walk reaches.
    if (descentIndex_.size() < nodes_.size()) descentIndex_.resize(nodes_.size());
    std::int32_t next = 0;
    detail::NodePairStack stack;  // (pool node, unused)
    stack.push(root_, -1);
    while (!stack.empty()) {
        std::int32_t i, unused;
        stack.pop(i, unused);
        descentIndex_[static_cast<std::size_t>(i)] = next++;
        const TreeNode& n = node(i);
        if (n.isLeaf()) continue;
        stack.push(n.child2, -1);
        stack.push(n.child1, -1);
    }
    assert(static_cast<std::size_t>(next) == 2 * static_cast<std::size_t>(proxyCount_) - 1);
    descentIndexValid_ = true;
}

std::size_t DynamicTree::partitionRange(std::size_t begin, std::size_t end, const AABB& centroidBox, AABB& leftCentroids,
                                        AABB& rightCentroids) {
    constexpr int kBins = 16;
    BuildItem* items = buildItems_.data();
    const Vec3 extent = centroidBox.max - centroidBox.min;

    if (end - begin == 2) {
        // Two leaves: every split costs the same, so the binned search below
        // keeps the first axis on which the centres differ and puts the
        // lower centre first (or, all centres equal, keeps the order).
        for (std::size_t axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > Real(0))) continue;
            if (items[begin + 1].centroid[axis] < items[begin].centroid[axis]) std::swap(items[begin], items[begin + 1]);
            break;
        }
        leftCentroids = AABB{};
        leftCentroids.grow(items[begin].centroid);
        rightCentroids = AABB{};
        rightCentroids.grow(items[begin + 1].centroid);
        return begin + 1;
    }

    if (end - begin <= kSmallRange) {
        // A few leaves: halve the longest axis of their centres. Binning
        // them (the bins' set-up and sweeps cost the same for 3 leaves as
        // for 3,000) was most of a build's instructions, in ranges where a
        // better split saves little.
        std::size_t axis = 0;
        if (extent.y > extent[axis]) axis = 1;
        if (extent.z > extent[axis]) axis = 2;
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
        leftCentroids = AABB{};
        rightCentroids = AABB{};
        for (std::size_t i = begin; i < left; ++i) leftCentroids.grow(items[i].centroid);
        for (std::size_t i = left; i < end; ++i) rightCentroids.grow(items[i].centroid);
        return left;
    }
    // The longest axis of the centres alone is binned: the split is most
    // often there (the SAH picks another axis mainly for flat or thin
    // clusters), and binning all three was two thirds of a build's
    // binning; HighSpeed's queries cost the same on the trees built so,
    // and a million static boxes build in a third fewer instructions.
    std::size_t axis = 0;
    if (extent.y > extent[axis]) axis = 1;
    if (extent.z > extent[axis]) axis = 2;
    leftCentroids = AABB{};
    rightCentroids = AABB{};
    if (!(extent[axis] > Real(0))) {  // all centroids coincide: any split is as good
        leftCentroids = rightCentroids = centroidBox;
        return begin + (end - begin) / 2;
    }
    // The bins' boxes and counts; each leaf's bin is kept (bins_, beside
    // the items) for the partition below. A bin starts as the empty box,
    // whose min and max any box replaces exactly. (Computing the bin once,
    // the boxes in locals and no first-leaf branch: a million static boxes'
    // build in about half the instructions; the same splits, so the same
    // tree.)
    std::uint32_t binCount[kBins] = {};
    const Real scale = Real(kBins) / extent[axis];
    // A leaf's bin from its scaled offset t, clamped to [0, kBins - 1]
    // without converting a NaN or an out-of-range t to int (undefined
    // behaviour): those go to bin 0, where x86's truncating conversion
    // (INT_MIN) and the clamp put them before, so the tree is the same.
    const auto clampedBin = [](Real t) {
        return t >= 0 && t < Real(2147483648.0) ? std::min(static_cast<int>(t), kBins - 1) : 0;
    };
    const Real origin = centroidBox.min[axis];
    if (bins_.size() < end) bins_.resize(buildItems_.size());
    std::uint8_t* bins = bins_.data();
    // The candidate splits lie between two non-empty bins; a split between
    // empty bins separates the same leaves as the split just after the last
    // non-empty bin on its left, which is the one the sweep keeps (costs are
    // compared strictly, lowest split first). Sweeping the non-empty bins
    // alone keeps the smaller ranges cheap. The centres span the axis, so
    // its first and last bins are used: there are two at least (with a
    // finite scale and offsets; else see halveRange).
    int used[kBins];
    int m = 0;
    // rightArea[j], rightCount[j]: the bins used[j..m).
    Real rightArea[kBins];
    std::size_t rightCount[kBins];
    Real bestCost = std::numeric_limits<Real>::max();
    int bestSplit = 0;
    // One bin used: only when the scale or the offsets are not finite (a
    // subnormal or an infinite extent puts every leaf in bin 0), where no
    // split separates anything and the build looped for ever. The range is
    // halved instead, as for coincident centres.
    const auto halveRange = [&] {
        const std::size_t mid = begin + (end - begin) / 2;
        for (std::size_t i = begin; i < mid; ++i) leftCentroids.grow(items[i].centroid);
        for (std::size_t i = mid; i < end; ++i) rightCentroids.grow(items[i].centroid);
        return mid;
    };
#if FULCRUM_TREE_SSE
    // The same minima and maxima in four lanes: the box's min in lanes 0-2
    // of one load, its max in lanes 1-3 of another (the areas below read
    // them; a zero's sign, the one thing min and max may order differently,
    // changes no area).
    static_assert(sizeof(AABB) == 6 * sizeof(float) && offsetof(AABB, max) == 3 * sizeof(float));
    __m128 binLo[kBins], binHi[kBins];
    for (int k = 0; k < kBins; ++k) {
        binLo[k] = _mm_set1_ps(std::numeric_limits<float>::max());
        binHi[k] = _mm_set1_ps(-std::numeric_limits<float>::max());
    }
    // A leaf's bin: its centre is at or above the origin (the centres' box
    // is their exact minimum and maximum, and rounding is monotonic), so
    // (c - origin) * scale is never negative when the extent and the scale
    // are finite, and only the top needs clamping (the last centre may land
    // on kBins). An infinite extent (centres near the float range's ends:
    // scale 0) or scale (a subnormal extent) can make the product NaN or
    // infinite: clampedBin, as ever.
    // (The lower clamp was 54 M of a million static boxes' 1,147 M.)
    const auto binLeaves = [&](auto bothEnds) {
        for (std::size_t i = begin; i < end; ++i) {
            const BuildItem& item = items[i];
            const Real t = (item.centroid[axis] - origin) * scale;
            const int k = decltype(bothEnds)::value ? clampedBin(t) : std::min(static_cast<int>(t), kBins - 1);
            bins[i] = static_cast<std::uint8_t>(k);
            ++binCount[k];
            const float* b = &item.box.min.x;
            binLo[k] = _mm_min_ps(binLo[k], _mm_loadu_ps(b));
            binHi[k] = _mm_max_ps(binHi[k], _mm_loadu_ps(b + 2));
        }
    };
    if (extent[axis] <= std::numeric_limits<Real>::max() && scale <= std::numeric_limits<Real>::max()) {
        binLeaves(std::false_type{});
    } else {
        binLeaves(std::true_type{});
    }
    for (int k = 0; k < kBins; ++k) {
        if (binCount[k] != 0) used[m++] = k;
    }
    if (m < 2) return halveRange();
    // The sweeps grow a box bin by bin in the lanes, as AABB::grow would
    // (min(a, b) is a < b ? a : b in both), and take its area as
    // AABB::surfaceArea does: d = max - min, 2 (dx dy + dy dz + dz dx), the
    // same operations in the same order (no contraction: -ffp-contract=off).
    // Storing the bins' boxes back into Vec3s for a scalar sweep was about
    // 170 instructions a range, the scalar sweep twice as many as this.
    const auto laneArea = [](__m128 lo, __m128 hi) {
        const __m128 d = _mm_sub_ps(_mm_shuffle_ps(hi, hi, _MM_SHUFFLE(3, 3, 2, 1)), lo);  // dx, dy, dz, -
        const __m128 p = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));     // dx dy, dy dz, dz dx, -
        const __m128 s = _mm_add_ss(_mm_add_ss(p, _mm_shuffle_ps(p, p, _MM_SHUFFLE(1, 1, 1, 1))), _mm_movehl_ps(p, p));
        return 2 * _mm_cvtss_f32(s);
    };
    {
        __m128 accLo = _mm_set1_ps(std::numeric_limits<float>::max());
        __m128 accHi = _mm_set1_ps(-std::numeric_limits<float>::max());
        std::size_t count = 0;
        for (int j = m - 1; j > 0; --j) {
            accLo = _mm_min_ps(accLo, binLo[used[j]]);
            accHi = _mm_max_ps(accHi, binHi[used[j]]);
            count += binCount[used[j]];
            rightArea[j] = laneArea(accLo, accHi);
            rightCount[j] = count;
        }
        accLo = _mm_set1_ps(std::numeric_limits<float>::max());
        accHi = _mm_set1_ps(-std::numeric_limits<float>::max());
        count = 0;
        bestSplit = used[0];
        for (int j = 0; j + 1 < m; ++j) {
            accLo = _mm_min_ps(accLo, binLo[used[j]]);
            accHi = _mm_max_ps(accHi, binHi[used[j]]);
            count += binCount[used[j]];
            const Real cost =
                laneArea(accLo, accHi) * static_cast<Real>(count) + rightArea[j + 1] * static_cast<Real>(rightCount[j + 1]);
            if (cost < bestCost) {
                bestCost = cost;
                bestSplit = used[j];
            }
        }
    }
#else
    Vec3 binMin[kBins], binMax[kBins];
    for (int k = 0; k < kBins; ++k) {
        binMin[k] = AABB{}.min;
        binMax[k] = AABB{}.max;
    }
    for (std::size_t i = begin; i < end; ++i) {
        const BuildItem& item = items[i];
        const int k = clampedBin((item.centroid[axis] - origin) * scale);
        bins[i] = static_cast<std::uint8_t>(k);
        ++binCount[k];
        binMin[k] = min(binMin[k], item.box.min);
        binMax[k] = max(binMax[k], item.box.max);
    }
    for (int k = 0; k < kBins; ++k) {
        if (binCount[k] != 0) used[m++] = k;
    }
    if (m < 2) return halveRange();
    AABB acc;
    std::size_t count = 0;
    for (int j = m - 1; j > 0; --j) {
        acc.grow(AABB{binMin[used[j]], binMax[used[j]]});
        count += binCount[used[j]];
        rightArea[j] = area(acc);
        rightCount[j] = count;
    }
    acc = AABB{};
    count = 0;
    bestSplit = used[0];
    for (int j = 0; j + 1 < m; ++j) {
        acc.grow(AABB{binMin[used[j]], binMax[used[j]]});
        count += binCount[used[j]];
        const Real cost = area(acc) * static_cast<Real>(count) + rightArea[j + 1] * static_cast<Real>(rightCount[j + 1]);
        if (cost < bestCost) {
            bestCost = cost;
            bestSplit = used[j];
        }
    }
#endif
    // The same exchanges as ever (the order of the leaves inside each half
    // decides later middle splits), the bins moving with their leaves. The
    // halves' centre boxes are min and max, exact in any order.
    std::size_t left = begin, right = end;
#if FULCRUM_TREE_SSE
    // The centre and the leaf id after it load as four lanes; lane 3 is not read.
    static_assert(offsetof(BuildItem, leaf) == offsetof(BuildItem, centroid) + 3 * sizeof(float));
    __m128 leftLo = _mm_set1_ps(std::numeric_limits<float>::max()), leftHi = _mm_set1_ps(-std::numeric_limits<float>::max());
    __m128 rightLo = leftLo, rightHi = leftHi;
    while (left < right) {
        const __m128 c = _mm_loadu_ps(&items[left].centroid.x);
        if (bins[left] <= bestSplit) {
            leftLo = _mm_min_ps(leftLo, c);
            leftHi = _mm_max_ps(leftHi, c);
            ++left;
        } else {
            --right;
            rightLo = _mm_min_ps(rightLo, c);
            rightHi = _mm_max_ps(rightHi, c);
            std::swap(items[left], items[right]);
            bins[left] = bins[right];
        }
    }
    const auto toVec3 = [](__m128 v) {
        alignas(16) float f[4];
        _mm_store_ps(f, v);
        return Vec3{f[0], f[1], f[2]};
    };
    leftCentroids = AABB{toVec3(leftLo), toVec3(leftHi)};
    rightCentroids = AABB{toVec3(rightLo), toVec3(rightHi)};
#else
    Vec3 leftMin = AABB{}.min, leftMax = AABB{}.max, rightMin = AABB{}.min, rightMax = AABB{}.max;
    while (left < right) {
        const Vec3 c = items[left].centroid;
        if (bins[left] <= bestSplit) {
            leftMin = min(leftMin, c);
            leftMax = max(leftMax, c);
            ++left;
        } else {
            --right;
            rightMin = min(rightMin, c);
            rightMax = max(rightMax, c);
            std::swap(items[left], items[right]);
            bins[left] = bins[right];
        }
    }
    leftCentroids = AABB{leftMin, leftMax};
    rightCentroids = AABB{rightMin, rightMax};
#endif
    return left;
}

// ---- statistics and validation ----------------------------------------------------

double DynamicTree::internalSurfaceArea() const {
    double sum = 0;
    for (const TreeNode& n : nodes_) {
        if (n.height > 0) sum += static_cast<double>(area(n.box));
    }
    return sum;
}

std::string DynamicTree::validate() const {
    std::ostringstream why;
    const auto count = static_cast<std::int32_t>(nodes_.size());
    const auto valid = [&](std::int32_t i) { return i >= 0 && i < count; };
    std::vector<char> seen(nodes_.size(), 0);
    std::int32_t reachable = 0, leaves = 0;

    if (root_ != kNullNode) {
        if (!valid(root_)) return "root index out of range";
        if (node(root_).parent != kNullNode) return "root has a parent";
        std::vector<std::int32_t> stack{root_};
        while (!stack.empty()) {
            const std::int32_t i = stack.back();
            stack.pop_back();
            if (seen[static_cast<std::size_t>(i)]) {
                why << "node " << i << " reached twice (cycle or shared child)";
                return why.str();
            }
            seen[static_cast<std::size_t>(i)] = 1;
            ++reachable;
            const TreeNode& n = node(i);
            if (n.isLeaf()) {
                ++leaves;
                if (n.child2 != kNullNode || n.height != 0) {
                    why << "leaf " << i << " has child2 " << n.child2 << " and height " << n.height;
                    return why.str();
                }
                if (n.box.isEmpty()) {
                    why << "leaf " << i << " has an empty box";
                    return why.str();
                }
                continue;
            }
            if (!valid(n.child1) || !valid(n.child2)) {
                why << "internal node " << i << " has child indices " << n.child1 << ", " << n.child2;
                return why.str();
            }
            const TreeNode& a = node(n.child1);
            const TreeNode& b = node(n.child2);
            if (a.parent != i || b.parent != i) {
                why << "children of node " << i << " name parents " << a.parent << " and " << b.parent;
                return why.str();
            }
            if (n.height != heightAbove(a.height, b.height)) {
                why << "node " << i << " has height " << n.height << ", children " << a.height << " and " << b.height;
                return why.str();
            }
            if (!(n.box == merge(a.box, b.box))) {
                why << "box of node " << i << " is not the union of its children's boxes";
                return why.str();
            }
            stack.push_back(n.child1);
            stack.push_back(n.child2);
        }
    }
    for (const std::int32_t i : pending_) {
        if (!valid(i) || seen[static_cast<std::size_t>(i)]) {
            why << "waiting leaf " << i << " is out of range, in the tree or listed twice";
            return why.str();
        }
        if (!node(i).isLeaf() || node(i).height != 0 || node(i).parent != kNullNode || node(i).box.isEmpty()) {
            why << "waiting leaf " << i << " is not a lone leaf";
            return why.str();
        }
        seen[static_cast<std::size_t>(i)] = 1;
        ++reachable;
        ++leaves;
    }
    if (leaves != proxyCount_) {
        why << "tree holds " << leaves << " leaves but counts " << proxyCount_ << " proxies";
        return why.str();
    }
    std::int32_t freeCount = 0;
    for (std::int32_t i = freeList_; i != kNullNode; i = node(i).parent) {
        if (!valid(i) || freeCount > count) return "free list leaves the node array or loops";
        if (seen[static_cast<std::size_t>(i)]) {
            why << "node " << i << " is both in the tree and on the free list";
            return why.str();
        }
        if (node(i).height != -1) {
            why << "free node " << i << " has height " << node(i).height;
            return why.str();
        }
        seen[static_cast<std::size_t>(i)] = 1;
        ++freeCount;
    }
    if (reachable + freeCount != count) {
        why << reachable << " reachable + " << freeCount << " free nodes != capacity " << count;
        return why.str();
    }
    return {};
}

}  // namespace fulcrum
