#pragma once
// DynamicTree: a bounding volume hierarchy of fattened AABBs that supports
// incremental insert, remove and move of proxies, overlap queries and ray casts.
//
// Layout. Nodes live in one contiguous array and refer to each other by index
// (never by pointer), so the array can grow by doubling and the whole tree can
// be copied or snapshotted as plain data. Free nodes form a singly linked list
// through `parent`. A proxy id is the index of its leaf node and stays valid
// while the proxy lives, including across moves and rebuild().
//
// Fattening. A leaf stores its tight box grown by `margin` on every side and
// extended along the caller's predicted displacement. moveProxy() touches the
// tree only when the new tight box leaves the stored box (or the stored box has
// become much larger than needed, e.g. after a fast body stopped), so the
// common small motions of resting and slowly moving bodies cost one box test.
//
// Balancing. Insertion chooses the sibling that minimises the total surface
// area of the internal nodes (the SAH cost of a BVH for random rays/queries,
// MacDonald & Booth 1990): either exactly, by branch and bound over a priority
// queue (Bittner, Hapala, Havran 2013, "Fast Insertion-Based Optimization of
// Bounding Volume Hierarchies"), or by a greedy descent guided by the same
// lower bound (Catto, GDC 2019 "Dynamic Bounding Volume Hierarchies"); on the
// way back up each ancestor tries the four child/grandchild swaps that reduce
// its area (Catto 2019). We chose this over AVL height balancing (Box2D 2.x):
// height balance says nothing about how much boxes overlap, while the query
// cost of a BVH is proportional to the area of the nodes a query enters.
// Measured in bench/broadphase.cpp (see docs/broad-phase.md): after motion,
// the incrementally maintained tree's internal area is within 4-7% of a
// binned-SAH top-down rebuild of the same boxes. To stay robust where area says
// nothing (many identical or nested boxes, where every choice costs the same),
// a rotation that leaves the area unchanged but lowers the height is taken, so
// such trees do not degenerate into lists.
//
// Threads. Queries and ray casts are const and allocate nothing (a stack on
// the call frame), so any number of threads may query one tree at once as long
// as nobody modifies it.
#include <array>
#include <cassert>
#include <cstdint>
#include <string>
#include <vector>

#include "fulcrum/math/aabb.hpp"
#include "math/large_array.hpp"

namespace fulcrum {

inline constexpr std::int32_t kNullNode = -1;

struct SnapshotAccess;  // src/world/snapshot.cpp: saves and restores private state

struct TreeNode {
    AABB box;                         // fattened for leaves; union of the children for internal nodes
    std::int32_t parent = kNullNode;  // next free node while on the free list
    std::int32_t child1 = kNullNode;  // kNullNode for leaves
    std::int32_t child2 = kNullNode;
    std::uint32_t userValue = 0;      // leaves only
    std::int16_t height = -1;         // 0 for leaves, -1 for free nodes

    bool isLeaf() const { return child1 == kNullNode; }
};

// A node of DynamicTree's depth-first copy (prepareSelfDescent): the first
// child follows its parent, the second is at `link`; a leaf's area is -1 and
// its `link` the user value. Half a cache line (single precision), so the
// descent of a large tree against itself walks memory mostly forward.
struct alignas(8 * sizeof(Real)) DescentNode {
    AABB box;
    Real area;           // box.surfaceArea() for internal nodes, -1 for leaves
    std::uint32_t link;  // internal: the second child's index in the copy; leaf: the user value

    bool isLeaf() const { return area < Real(0); }
};

// A segment p + t * translation, t in [0, maxFraction].
struct RayCastInput {
    Vec3 origin;
    Vec3 translation;
    Real maxFraction = 1;
};

struct DynamicTreeConfig {
    // Grown on every side of the tight box (metres). 0 for trees of things that never move.
    Real margin = Real(0.1);
    // The stored box also extends by displacementScale * displacement along the
    // motion, predicting the next step's motion so that a body moving at a steady
    // speed is reinserted only every few steps. 0 disables prediction.
    Real displacementScale = 1;
    // How insertion looks for the best sibling (see dynamic_tree.cpp for measurements).
    enum class Search : std::uint8_t {
        Greedy,          // one root-to-leaf descent by lower bound (Catto 2019): O(height)
        BranchAndBound,  // exact minimum-cost sibling (Bittner et al. 2013)
    };
    Search search = Search::Greedy;
};

// Precomputed segment data for the slab test, shared by tree traversal and the
// brute-force reference in the tests so both make the same decisions.
struct RaySlab {
    Vec3 origin;
    Vec3 invDirection;  // 1/d per axis; 0 where d is 0 (then `parallel` is set)
    bool parallel[3] = {false, false, false};

    explicit RaySlab(const RayCastInput& in) : origin(in.origin) {
        for (std::size_t i = 0; i < 3; ++i) {
            parallel[i] = in.translation[i] == Real(0);
            invDirection[i] = parallel[i] ? Real(0) : Real(1) / in.translation[i];
        }
    }
    // Entry fraction of the segment [0, maxFraction] into `b`, or -1 for a miss.
    // Monotone in the box (a larger box never gives a later entry), so pruning
    // by an ancestor's box never rejects a leaf the segment hits.
    Real entry(const AABB& b, Real maxFraction) const {
        Real tmin = 0, tmax = maxFraction;
        for (std::size_t i = 0; i < 3; ++i) {
            if (parallel[i]) {
                if (origin[i] < b.min[i] || origin[i] > b.max[i]) return -1;
                continue;
            }
            Real t1 = (b.min[i] - origin[i]) * invDirection[i];
            Real t2 = (b.max[i] - origin[i]) * invDirection[i];
            if (t1 > t2) { const Real t = t1; t1 = t2; t2 = t; }
            tmin = t1 > tmin ? t1 : tmin;
            tmax = t2 < tmax ? t2 : tmax;
            if (tmin > tmax) return -1;
        }
        return tmin;
    }
};

class DynamicTree {
public:
    explicit DynamicTree(const DynamicTreeConfig& config = {});

    const DynamicTreeConfig& config() const { return config_; }

    // Capacity for `proxies` leaves and their internal nodes (the node array
    // grows by doubling: the next power of two of twice that).
    void reserve(std::size_t proxies);

    // Inserts a proxy for `tightBox`; returns its id (a leaf index).
    std::int32_t createProxy(const AABB& tightBox, std::uint32_t userValue, const Vec3& displacement = Vec3::zero());
    // A proxy whose leaf waits outside the tree until insertPending() (for
    // trees that take many proxies at once: a scene's static bodies, made one
    // createBody at a time). Its id, box and user value are valid at once;
    // queries and ray casts do not see it until it is inserted. Every other
    // change to the tree (create, destroy, move, rebuild) inserts the waiting
    // leaves first, so the tree is the one immediate insertions would have
    // built, unless insertPending() builds it in bulk (see there).
    std::int32_t createProxyDeferred(const AABB& tightBox, std::uint32_t userValue);
    bool hasPending() const { return !pending_.empty(); }
    std::size_t pendingCount() const { return pending_.size(); }
    // Inserts the waiting leaves: one by one, in creation order, as
    // createProxy would have; or, when at least kBulkMinLeaves wait and they
    // are at least a kBulkShare-th of the tree, by a rebuild() of the whole
    // tree (O(n log n) for n leaves, against an exact sibling search per
    // leaf that grows with the tree). The tree's shape then differs from
    // the incremental one; results that depend only on which leaves overlap
    // what (pairs sorted by id, sorted query answers) do not.
    static constexpr std::size_t kBulkMinLeaves = 1024;
    static constexpr std::size_t kBulkShare = 4;
    void insertPending();
    void destroyProxy(std::int32_t proxyId);
    // Updates the proxy for a new tight box. Returns true when the stored fat box
    // changed (the leaf was reinserted), false when the old fat box still fits.
    bool moveProxy(std::int32_t proxyId, const AABB& tightBox, const Vec3& displacement);
    // Whether moveProxy would reinsert the leaf. Reads only the leaf's own box,
    // which moving other proxies never changes, so callers may test many
    // proxies in parallel and then move only those that need it, in order.
    bool mustMove(std::int32_t proxyId, const AABB& tightBox, const Vec3& displacement) const;
    // moveProxy in two halves, so the leaf's new fat box is final before the
    // tree is restructured: setFatBox writes the leaf's box only (the
    // ancestors are stale until reinsert), reinsert(proxyId) then removes and
    // re-inserts the leaf. Between the two, fatAABB() of every leaf is exact and
    // queries are not allowed. After every leaf given a new box is reinserted
    // (in any order) the tree is valid again. reinsert never reallocates the
    // node pool (removal frees the node insertion takes), so fatAABB() may be
    // read by other threads while it runs.
    void setFatBox(std::int32_t proxyId, const AABB& tightBox, const Vec3& displacement) {
        assert(!hasPending());  // trees with waiting leaves (the static tree) are not moved this way
        // Threads call this for different leaves at once, so it leaves
        // descentValid_ alone: reinsert and refitOrRebuild, which must follow
        // before the next query, clear it.
        node(proxyId).box = fatten(tightBox, displacement);
    }
    void reinsert(std::int32_t proxyId) {
        if (hasPending()) insertPending();
        if (updateInPlace(proxyId)) return;
        removeLeaf(proxyId);
        insertLeaf(proxyId);
    }

    const AABB& fatAABB(std::int32_t proxyId) const { return nodes_[static_cast<std::size_t>(proxyId)].box; }
    std::uint32_t userValue(std::int32_t proxyId) const { return nodes_[static_cast<std::size_t>(proxyId)].userValue; }
    bool isProxy(std::int32_t proxyId) const {
        return proxyId >= 0 && static_cast<std::size_t>(proxyId) < nodes_.size() &&
               nodes_[static_cast<std::size_t>(proxyId)].height == 0;
    }

    // Calls callback(proxyId, userValue) for every leaf whose fat box overlaps
    // `box`, in tree order; the callback returns false to stop the query.
    // Returns false when the callback stopped it, true when it ran to the end.
    template <typename Callback>
    bool query(const AABB& box, Callback&& callback) const;

    // Calls callback(input, proxyId, userValue) -> Real for every leaf whose fat
    // box the segment enters before the current maxFraction. The callback returns
    //   < 0   to ignore this proxy and go on,
    //   0     to stop,
    //   f > 0 to clip the segment to f (closest-hit queries return their hit fraction),
    // so returning input.maxFraction goes on unchanged. Returns the final
    // maxFraction (0 when the callback stopped the cast).
    template <typename Callback>
    Real rayCast(const RayCastInput& input, Callback&& callback) const;

    // Calls callback(userValueA, userValueB) for every pair of leaves whose
    // fat boxes overlap, one in the subtree at `a` of this tree and one in
    // the subtree at `b` of `other`; with other == *this and a == b, every
    // unordered pair of distinct leaves of that subtree once (a self-test:
    // each internal node's two children are tested against each other).
    // One simultaneous descent of both subtrees tests far fewer node boxes
    // than a query per leaf, which walks down from the root each time and
    // finds every pair twice. The callback returns false to stop; returns
    // false when it stopped. Order: tree order (callers sort).
    template <typename Callback>
    bool overlapPairs(std::int32_t a, const DynamicTree& other, std::int32_t b, Callback&& callback) const;
    // From this many leaves, a tree's descent against itself pushes its
    // pairs without branching on the box tests (see overlapPairs; measured
    // on this project's 2-core machine: slower at 2000 moving boxes, 9-18 %
    // faster from 3000 on, where the tree no longer stays in the caches).
    static constexpr std::int32_t kBranchFreeDescentLeaves = 2500;
    // One level of that descent, for splitting it into independent parts
    // (parallel work): calls part(a', b') for the sub-pairs whose
    // overlapPairs together equal overlapPairs(a, other, b) and returns
    // true, or returns false when (a, b) does not split (a leaf pair).
    // Pairs of disjoint boxes are dropped (they have no overlap pairs).
    template <typename Part>
    bool splitPairs(std::int32_t a, const DynamicTree& other, std::int32_t b, Part&& part) const;
    // For a tree of kBranchFreeDescentLeaves leaves or more: writes a
    // depth-first copy of the tree (DescentNode), which overlapPairs of the
    // tree against itself then walks instead of the node pool (the same
    // steps in the same order, so the same pairs in the same order) until
    // the tree next changes. In the pool a node's children lie anywhere, and
    // a large tree's descent waited on the caches; in the copy a subtree is
    // one stretch of memory. One pass over the tree, single-threaded: call it
    // before the descents (BroadPhase does, when it descends). Does nothing
    // for a smaller tree or when the copy is current.
    void prepareSelfDescent();
    bool selfDescentPrepared() const { return descentValid_; }
    // Each pool node's index in the depth-first copy, for descents that start
    // below the root (the broad phase's parts on several threads, tests):
    // the copy's writers leave it out, since a descent of the whole tree
    // starts at the copy's first node (writing it, at random places in pool
    // order, was most of the refit's new write misses on HighSpeed: the
    // `hstree` block). Until it is written, a descent that starts below the
    // root walks the node pool (the same pairs in the same order). Does
    // nothing without a current copy or when the index is written.
    void prepareDescentIndex();
    bool descentIndexPrepared() const { return descentValid_ && descentIndexValid_; }

    // Replaces the internal nodes by a top-down binned-SAH build over the
    // current leaves (for trees built once, like the static tree). Proxy ids
    // stay valid. Reuses scratch buffers; allocates only if they must grow.
    void rebuild();
    // For a tree most of whose leaves just got new boxes (setFatBox), in
    // place of reinserting them or rebuild(): refits every internal node's
    // box to its children's, keeping the tree's shape, and rebuilds only
    // when the refitted tree has become too loose for its leaves (see
    // dynamic_tree.cpp). Proxy ids stay valid; the pool is not reallocated
    // (fatAABB may be read by other threads meanwhile). Returns whether it
    // rebuilt.
    bool refitOrRebuild();

    // ---- statistics and checks
    std::int32_t root() const { return root_; }
    int height() const { return root_ == kNullNode ? 0 : nodes_[static_cast<std::size_t>(root_)].height; }
    std::int32_t proxyCount() const { return proxyCount_; }
    std::size_t capacity() const { return nodes_.size(); }
    const detail::LargeArray<TreeNode>& nodes() const { return nodes_; }
    // Sum of the surface areas of the internal nodes (root included): the SAH
    // cost a query pays up to a constant, the usual measure of tree quality.
    double internalSurfaceArea() const;
    // Checks every structural invariant (parent links, child counts, heights,
    // boxes containing their children, free list, counts). Returns an empty
    // string when valid, otherwise a description of the first violation.
    std::string validate() const;

private:
    friend struct fulcrum::SnapshotAccess;
    std::int32_t allocateNode();
    void freeNode(std::int32_t node);
    AABB fatten(const AABB& tight, const Vec3& displacement) const;
    void insertLeaf(std::int32_t leaf);
    void removeLeaf(std::int32_t leaf);
    std::int32_t findBestSibling(const AABB& leafBox);
    std::int32_t findBestSiblingGreedy(const AABB& leafBox) const;
    void rotate(std::int32_t node);
    void refit(std::int32_t node);
    // A leaf whose new box still lies inside the box of its parent or of an
    // ancestor up to kInPlaceLevels above keeps its place: only its ancestors'
    // boxes are refitted, up to the first one that does not change. Returns
    // false (nothing done) when the box left that ancestor's.
    static constexpr int kInPlaceLevels = 3;
    bool updateInPlace(std::int32_t leaf);
    // Splits buildItems_[begin, end) (centres in centroidBox) in two, returns
    // where the second half starts and each half's centroid box: binned SAH
    // along the centres' longest axis, or for at most kSmallRange leaves
    // the middle of that axis.
    static constexpr std::size_t kSmallRange = 6;
    std::size_t partitionRange(std::size_t begin, std::size_t end, const AABB& centroidBox, AABB& leftCentroids,
                               AABB& rightCentroids);

    TreeNode& node(std::int32_t i) { return nodes_[static_cast<std::size_t>(i)]; }
    const TreeNode& node(std::int32_t i) const { return nodes_[static_cast<std::size_t>(i)]; }

    DynamicTreeConfig config_;
    detail::LargeArray<TreeNode> nodes_;
    std::int32_t root_ = kNullNode;
    std::int32_t freeList_ = kNullNode;
    std::int32_t proxyCount_ = 0;
    detail::LargeArray<std::int32_t> pending_;  // leaves made by createProxyDeferred, not in the tree yet

    // Scratch buffers reused across calls (no allocation in steady state).
    struct Candidate {
        std::int32_t node;
        Real inheritedCost;
    };
    std::vector<Candidate> candidates_;          // branch-and-bound priority queue
    struct BuildItem {
        AABB box;
        Vec3 centroid;
        std::int32_t leaf;
    };
    detail::LargeArray<BuildItem> buildItems_;          // rebuild(): the leaves being partitioned
    detail::LargeArray<std::uint8_t> bins_;             // rebuild(): each item's bin in partitionRange
    detail::LargeArray<std::int32_t> buildOrder_;       // rebuild(): internal nodes in creation order
    struct BuildTask {
        std::size_t begin, end;
        std::int32_t parent;
        bool first;
        AABB centroidBox;  // of the range's leaves
    };
    std::vector<BuildTask> buildTasks_;          // rebuild(): ranges still to split
    // refitOrRebuild(): the internal nodes' total area over the leaves' right
    // after the last rebuild() (0: no rebuild yet). A heuristic's reference
    // only: not part of the tree's state (snapshots leave it out; a restored
    // tree rebuilds at its first bulk update, which changes its shape but no
    // result: pairs are reported sorted by id).
    double rebuiltLooseness_ = 0;
    // prepareSelfDescent(): the copy, each pool node's index in it (valid
    // while descentValid_ and descentIndexValid_: prepareDescentIndex), and
    // whether it matches the tree. Every change to
    // the tree's nodes clears descentValid_; derived data, not state
    // (snapshots leave it out, a restored tree has none).
    std::vector<DescentNode> descent_;
    std::vector<std::int32_t> descentIndex_;
    std::vector<std::int32_t> descentInternal_;  // refitOrRebuild(): the internal nodes' indices in the copy
    bool descentValid_ = false;
    bool descentIndexValid_ = false;  // descentIndex_ is that of the current copy (cleared when the copy is written)
};

// ---- traversal templates ----------------------------------------------------

namespace detail {
// Traversal stack on the call frame; spills to the heap only for trees deeper
// than any balanced tree of 2^60 leaves could be (a safety net, not a path).
class NodeStack {
public:
    void push(std::int32_t n) {
        if (size_ < kInline) {
            inline_[size_++] = n;
        } else {
            spill_.push_back(n);
            ++size_;
        }
    }
    std::int32_t pop() {
        --size_;
        if (size_ < kInline) return inline_[size_];
        const std::int32_t n = spill_.back();
        spill_.pop_back();
        return n;
    }
    bool empty() const { return size_ == 0; }

private:
    static constexpr std::size_t kInline = 128;
    std::int32_t inline_[kInline];
    std::size_t size_ = 0;
    std::vector<std::int32_t> spill_;
};

// The same for pairs of nodes (the descent of two subtrees). It holds at
// most about 2 x (the two subtrees' heights) pairs, far below kInline for
// any tree a step meets, so steady-state steps allocate nothing.
class NodePairStack {
public:
    void push(std::int32_t a, std::int32_t b) {
        if (size_ < kInline) {
            inline_[size_][0] = a;
            inline_[size_][1] = b;
            ++size_;
        } else {
            pushSpill(a, b);
        }
    }
    // Pushes (a, b) when `keep`, without a branch on it: the pair is written
    // in any case and the size grows by keep (for box tests whose outcomes a
    // branch predictor cannot learn: DynamicTree::overlapPairs on one tree).
    // Always inlined: where GCC chose a call instead (its estimate moves with
    // unrelated changes to the callers' headers), HighSpeed's steps 101-110
    // took 1.3 % more instructions (docs/benchmarks.md, branch `hs13`).
    [[gnu::always_inline]] void pushIf(std::int32_t a, std::int32_t b, bool keep) {
        if (size_ < kInline) {
            inline_[size_][0] = a;
            inline_[size_][1] = b;
            size_ += static_cast<std::size_t>(keep);
        } else if (keep) {
            pushSpill(a, b);
        }
    }
    void pop(std::int32_t& a, std::int32_t& b) {
        --size_;
        if (size_ < kInline) {
            a = inline_[size_][0];
            b = inline_[size_][1];
            return;
        }
        a = spill_.back()[0];
        b = spill_.back()[1];
        spill_.pop_back();
    }
    bool empty() const { return size_ == 0; }

private:
    [[gnu::noinline]] void pushSpill(std::int32_t a, std::int32_t b) {
        spill_.push_back({a, b});
        ++size_;
    }
    static constexpr std::size_t kInline = 512;
    std::int32_t inline_[kInline][2];
    std::size_t size_ = 0;
    std::vector<std::array<std::int32_t, 2>> spill_;
};
// overlaps() with all six comparisons made and joined by bitwise and: the
// same answer, no branch on it (a descent's box tests go either way at random).
inline bool overlapsNoBranch(const AABB& a, const AABB& b) {
    return static_cast<bool>(static_cast<int>(a.min.x <= b.max.x) & static_cast<int>(a.max.x >= b.min.x) &
                             static_cast<int>(a.min.y <= b.max.y) & static_cast<int>(a.max.y >= b.min.y) &
                             static_cast<int>(a.min.z <= b.max.z) & static_cast<int>(a.max.z >= b.min.z));
}
}  // namespace detail

template <typename Callback>
bool DynamicTree::query(const AABB& box, Callback&& callback) const {
    if (root_ == kNullNode) return true;
    detail::NodeStack stack;
    stack.push(root_);
    while (!stack.empty()) {
        const TreeNode& n = node(stack.pop());
        if (!overlaps(n.box, box)) continue;
        if (n.isLeaf()) {
            const auto id = static_cast<std::int32_t>(&n - nodes_.data());
            if (!callback(id, n.userValue)) return false;
        } else {
            stack.push(n.child2);
            stack.push(n.child1);
        }
    }
    return true;
}

template <typename Callback>
Real DynamicTree::rayCast(const RayCastInput& input, Callback&& callback) const {
    if (root_ == kNullNode) return input.maxFraction;
    RayCastInput current = input;
    const RaySlab slab(input);
    detail::NodeStack stack;
    stack.push(root_);
    while (!stack.empty()) {
        const TreeNode& n = node(stack.pop());
        if (slab.entry(n.box, current.maxFraction) < 0) continue;
        if (n.isLeaf()) {
            const auto id = static_cast<std::int32_t>(&n - nodes_.data());
            const Real value = callback(static_cast<const RayCastInput&>(current), id, n.userValue);
            if (value == Real(0)) return Real(0);
            if (value > Real(0) && value < current.maxFraction) current.maxFraction = value;
        } else {
            stack.push(n.child2);
            stack.push(n.child1);
        }
    }
    return current.maxFraction;
}

template <typename Part>
bool DynamicTree::splitPairs(std::int32_t a, const DynamicTree& other, std::int32_t b, Part&& part) const {
    const TreeNode& na = node(a);
    const TreeNode& nb = other.node(b);
    if (&other == this && a == b) {
        if (na.isLeaf()) return true;  // no pair within one leaf
        part(na.child1, na.child1);
        part(na.child2, na.child2);
        if (overlaps(node(na.child1).box, node(na.child2).box)) part(na.child1, na.child2);
        return true;
    }
    if (na.isLeaf() && nb.isLeaf()) return false;
    // Descend the larger box (or the one that is not a leaf): the smaller
    // box then prunes more of the other's subtree.
    if (nb.isLeaf() || (!na.isLeaf() && na.box.surfaceArea() >= nb.box.surfaceArea())) {
        if (overlaps(node(na.child1).box, nb.box)) part(na.child1, b);
        if (overlaps(node(na.child2).box, nb.box)) part(na.child2, b);
    } else {
        if (overlaps(na.box, other.node(nb.child1).box)) part(a, nb.child1);
        if (overlaps(na.box, other.node(nb.child2).box)) part(a, nb.child2);
    }
    return true;
}

template <typename Callback>
bool DynamicTree::overlapPairs(std::int32_t a, const DynamicTree& other, std::int32_t b, Callback&& callback) const {
    if (a == kNullNode || b == kNullNode) return true;
    if (&other != this || proxyCount_ < kBranchFreeDescentLeaves) {
        // Two trees (the moving tree against the static one), or a small
        // tree: pop pairs through splitPairs. The box tests against a few
        // large static boxes mostly go one way, which a predictor learns,
        // and a small tree stays in the caches, where a predicted branch
        // runs ahead: the branch-free pushes below were twice as slow on
        // HighSpeed's walls and a third slower on 2000 moving boxes.
        if (!(&other == this && a == b) && !overlaps(node(a).box, other.node(b).box)) return true;
        detail::NodePairStack stack;
        stack.push(a, b);
        const auto push = [&](std::int32_t x, std::int32_t y) { stack.push(x, y); };
        while (!stack.empty()) {
            std::int32_t x, y;
            stack.pop(x, y);
            if (!splitPairs(x, other, y, push)) {
                if (!callback(node(x).userValue, other.node(y).userValue)) return false;
            }
        }
        return true;
    }
    if (a == b) {
        if (node(a).isLeaf()) return true;  // no pair within one leaf
    } else if (!overlaps(node(a).box, node(b).box)) {
        return true;
    }
    // A large tree against itself (or two of its subtrees): the same steps as
    // splitPairs, in the same order, so the callback sees the same pairs in
    // the same order; but a leaf is not pushed against itself (it holds no
    // pair), and a box test pushes its pair without a branch on its outcome
    // (NodePairStack::pushIf): in a tree of moving bodies the outcomes go
    // either way at random, and their mispredicted branches were a third of
    // HighSpeed's (docs/benchmarks.md, branch hsfull).
    if (descentValid_ && (descentIndexValid_ || (a == root_ && b == root_))) {
        // The same loop over the depth-first copy (prepareSelfDescent): a
        // node's first child is the next node, its area is stored. The root
        // is the copy's node 0; a node below it needs the index
        // (prepareDescentIndex).
        const DescentNode* nodes = descent_.data();
        detail::NodePairStack stack;
        if (descentIndexValid_) {
            stack.push(descentIndex_[static_cast<std::size_t>(a)], descentIndex_[static_cast<std::size_t>(b)]);
        } else {
            stack.push(0, 0);
        }
        while (!stack.empty()) {
            std::int32_t x, y;
            stack.pop(x, y);
            const DescentNode& nx = nodes[x];
            if (x == y) {
                if (nx.isLeaf()) continue;
                const std::int32_t c1 = x + 1, c2 = static_cast<std::int32_t>(nx.link);
                const DescentNode& n1 = nodes[c1];
                const DescentNode& n2 = nodes[c2];
                stack.pushIf(c1, c1, !n1.isLeaf());
                stack.pushIf(c2, c2, !n2.isLeaf());
                stack.pushIf(c1, c2, detail::overlapsNoBranch(n1.box, n2.box));
                continue;
            }
            const DescentNode& ny = nodes[y];
            const bool xLeaf = nx.isLeaf(), yLeaf = ny.isLeaf();
            if (xLeaf && yLeaf) {
                if (!callback(nx.link, ny.link)) return false;
                continue;
            }
            if (yLeaf || (!xLeaf && nx.area >= ny.area)) {
                const std::int32_t c1 = x + 1, c2 = static_cast<std::int32_t>(nx.link);
                stack.pushIf(c1, y, detail::overlapsNoBranch(nodes[c1].box, ny.box));
                stack.pushIf(c2, y, detail::overlapsNoBranch(nodes[c2].box, ny.box));
            } else {
                const std::int32_t c1 = y + 1, c2 = static_cast<std::int32_t>(ny.link);
                stack.pushIf(x, c1, detail::overlapsNoBranch(nx.box, nodes[c1].box));
                stack.pushIf(x, c2, detail::overlapsNoBranch(nx.box, nodes[c2].box));
            }
        }
        return true;
    }
    const TreeNode* nodes = nodes_.data();
    detail::NodePairStack stack;
    stack.push(a, b);
    while (!stack.empty()) {
        std::int32_t x, y;
        stack.pop(x, y);
        const TreeNode& nx = nodes[x];
        if (x == y) {
            // Only internal nodes are pushed against themselves, but a pair
            // of a node and its own descendant reaches the descendant's leaves.
            if (nx.isLeaf()) continue;
            const TreeNode& c1 = nodes[nx.child1];
            const TreeNode& c2 = nodes[nx.child2];
            stack.pushIf(nx.child1, nx.child1, !c1.isLeaf());
            stack.pushIf(nx.child2, nx.child2, !c2.isLeaf());
            stack.pushIf(nx.child1, nx.child2, detail::overlapsNoBranch(c1.box, c2.box));
            continue;
        }
        const TreeNode& ny = nodes[y];
        const bool xLeaf = nx.isLeaf(), yLeaf = ny.isLeaf();
        if (xLeaf && yLeaf) {
            if (!callback(nx.userValue, ny.userValue)) return false;
            continue;
        }
        // Descend the larger box (or the one that is not a leaf), as splitPairs.
        if (yLeaf || (!xLeaf && nx.box.surfaceArea() >= ny.box.surfaceArea())) {
            stack.pushIf(nx.child1, y, detail::overlapsNoBranch(nodes[nx.child1].box, ny.box));
            stack.pushIf(nx.child2, y, detail::overlapsNoBranch(nodes[nx.child2].box, ny.box));
        } else {
            stack.pushIf(x, ny.child1, detail::overlapsNoBranch(nx.box, nodes[ny.child1].box));
            stack.pushIf(x, ny.child2, detail::overlapsNoBranch(nx.box, nodes[ny.child2].box));
        }
    }
    return true;
}

}  // namespace fulcrum
