#pragma once
// BroadPhase: finds the candidate pairs the narrow phase must test.
//
// Two dynamic AABB trees: the static tree holds static bodies' proxies (built
// once, rarely touched, optionally rebuilt with binned SAH); the moving tree
// holds dynamic and kinematic proxies (fattened, incrementally updated).
//
// ---- The pair contract --------------------------------------------------------
// The caller (the world's contact manager) owns the set S of persistent pairs;
// the broad phase keeps no pair set. Say two proxies "overlap" when their fat
// boxes (fatAABB) overlap, and a pair is "allowed" when the proxies are not
// both static, at least one is dynamic (unless config.requireDynamic is
// false, then kinematic-kinematic and kinematic-static are allowed too),
// shouldCollide() passes on their filters and the caller's canPair predicate
// accepts their user values.
//
// Each step:
//   1. moveProxy() for every proxy whose body moved (any type), with its new
//      tight box and the displacement over the step;
//   2. pairs = updatePairs(canPair): returns exactly the allowed pairs that
//      overlap now but did not overlap at the previous updatePairs() (or
//      involve a proxy created or refreshed since). Each unordered pair once,
//      as (a, b) with a < b, sorted by (a, b): the order depends only on the
//      proxy ids, never on tree shape, insertion history or thread timing.
//      Add them all to S;
//   3. remove from S every pair for which testOverlap(a, b) is false.
// If S held exactly the allowed overlapping pairs after the previous step, it
// does again after this one (tests/broadphase check it against brute force
// over thousands of proxies and hundreds of steps). Since a fat box contains
// its tight box, every allowed pair whose tight boxes overlap is in S.
//
// Why this works without a pair set: a fat box changes only when moveProxy()
// reinserts it, and then the proxy enters the move buffer together with its
// fat box as of the last update. Only moved proxies query the trees; a found
// pair is new exactly when the old boxes did not overlap. The old box of a
// created or refreshed proxy counts as empty. (Box2D v3 instead checks a
// hash set of existing pairs; comparing old boxes needs no shared state, so
// the queries can run in parallel without locks.)
//
// The caller must also:
//   - drop its pairs with a proxy before or when destroying it;
//   - call refreshProxy(id) after dropping all pairs of a proxy whose allowed
//     partners changed: a new filter (setFilter does this), a joint between two
//     bodies created or destroyed (canPair changed), a body type change (destroy
//     and create the proxy instead). The next update then reports all of its
//     allowed overlaps as new.
//
// ---- Threads ---------------------------------------------------------------------
// updatePairs(canPair, tasks) runs one tree query per entry of the move buffer
// as a parallel-for over the move buffer. The queries only read the trees, the
// proxy records and the move buffer, so they need no locks; each worker appends
// to its own buffer, the buffers are concatenated and the result is sorted by
// (a, b), so it is identical for any thread count and scheduler (no pair can
// be found twice: the rule "both moved: the smaller id reports" holds per
// query). The canPair predicate must therefore be thread-safe. Moves (tree
// updates) stay serial: they are cheap because most moves stay inside their
// fat box.
//
// No heap allocation in steady state: the move buffer, the pair buffer, the
// proxy records and the trees' node arrays are reused and grow by doubling.
#include <algorithm>
#include <cassert>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "collision/collision_filter.hpp"
#include "collision/dynamic_tree.hpp"
#include "fulcrum/body.hpp"
#include "fulcrum/task_system.hpp"

namespace fulcrum {

using ProxyId = std::int32_t;
inline constexpr ProxyId kNullProxy = -1;

// A candidate pair: a < b, with the proxies' user values.
struct ProxyPair {
    ProxyId a = kNullProxy, b = kNullProxy;
    std::uint32_t userA = 0, userB = 0;
    bool operator==(const ProxyPair&) const = default;
};

struct BroadPhaseConfig {
    // Moving proxies: 10 cm margin, one step of predicted motion, fast greedy
    // insertion (measurements in dynamic_tree.cpp and docs/broad-phase.md).
    DynamicTreeConfig movingTree{Real(0.1), Real(1), DynamicTreeConfig::Search::Greedy};
    // Static proxies: tight boxes (they rarely move, and a margin there would
    // only add pairs), exact best-sibling insertion for a better tree.
    DynamicTreeConfig staticTree{Real(0), Real(0), DynamicTreeConfig::Search::BranchAndBound};
    // Pairs need at least one dynamic proxy (kinematic-kinematic and
    // kinematic-static pairs produce no response). Set false to report them too,
    // e.g. for kinematic sensors.
    bool requireDynamic = true;
};

class BroadPhase {
public:
    explicit BroadPhase(const BroadPhaseConfig& config = {});

    const BroadPhaseConfig& config() const { return config_; }

    // Creates a proxy for a tight box; it counts as moved (all its overlaps are
    // reported as new by the next updatePairs).
    ProxyId createProxy(const AABB& tightBox, BodyType type, const CollisionFilter& filter, std::uint32_t userValue);
    // Destroys a proxy; the caller drops its pairs. The id may be reused.
    void destroyProxy(ProxyId id);
    // New tight box and the displacement over the step. Returns true when the
    // fat box changed (the proxy joins the move buffer), false when it still fits.
    bool moveProxy(ProxyId id, const AABB& tightBox, const Vec3& displacement);
    // Whether moveProxy would change the fat box (const: safe to call for many
    // proxies in parallel before the moves, DynamicTree::mustMove).
    bool proxyMustMove(ProxyId id, const AABB& tightBox, const Vec3& displacement) const {
        const ProxyRecord& r = record(id);
        return treeOf(r.type).mustMove(r.leaf, tightBox, displacement);
    }
    // moveProxy in two halves (DynamicTree::setFatBox / reinsert), for a proxy
    // proxyMustMove said must move: setFatBox gives it its new fat box and its
    // move-buffer entry at once; reinsertProxy, called for each such proxy
    // before the next updatePairs, restructures the tree. In between,
    // testOverlap and fatAABB are exact and may run on other threads while
    // the reinsertions run on one.
    void setFatBox(ProxyId id, const AABB& tightBox, const Vec3& displacement) {
        ProxyRecord& r = record(id);
        const AABB before = treeOf(r.type).fatAABB(r.leaf);
        treeOf(r.type).setFatBox(r.leaf, tightBox, displacement);
        markMoved(id, before, false);
    }
    // setFatBox split again, for many proxies at once: writeFatBox may run on
    // any thread for distinct proxies (it writes that leaf's box only and
    // returns the box it replaced); noteMoved then gives each, in a
    // deterministic order, its move-buffer entry. Together: setFatBox.
    AABB writeFatBox(ProxyId id, const AABB& tightBox, const Vec3& displacement) {
        const ProxyRecord& r = record(id);
        DynamicTree& tree = treeOf(r.type);
        const AABB before = tree.fatAABB(r.leaf);
        tree.setFatBox(r.leaf, tightBox, displacement);
        return before;
    }
    void noteMoved(ProxyId id, const AABB& before) { markMoved(id, before, false); }
    void reinsertProxy(ProxyId id) {
        const ProxyRecord& r = record(id);
        treeOf(r.type).reinsert(r.leaf);
    }
    // Sets the filter and refreshes the proxy (see the contract above).
    void setFilter(ProxyId id, const CollisionFilter& filter);
    // Forget the proxy's pairs: the next update reports all its allowed overlaps.
    void refreshProxy(ProxyId id);

    // Reports the new pairs (see the contract above). The span stays valid until
    // the next call that modifies the broad phase.
    template <PairPredicate Predicate>
    std::span<const ProxyPair> updatePairs(const Predicate& canPair);
    std::span<const ProxyPair> updatePairs() { return updatePairs(AcceptAllPairs{}); }
    // The same, with the queries run in parallel on `tasks` (same result).
    template <PairPredicate Predicate>
    std::span<const ProxyPair> updatePairs(const Predicate& canPair, TaskSystem& tasks);

    // Grows the new-pair buffer so updatePairs() need not allocate (the world
    // calls it when bodies are created).
    void reservePairs(std::size_t count) {
        if (pairs_.capacity() < count) pairs_.reserve(count);
        for (WorkerPairs& wp : workerPairs_)
            if (wp.pairs.capacity() < count) wp.pairs.reserve(count);
    }

    // Whether two proxies' fat boxes overlap: the caller ends a pair when false.
    bool testOverlap(ProxyId a, ProxyId b) const { return overlaps(fatAABB(a), fatAABB(b)); }

    // ---- accessors
    bool isProxy(ProxyId id) const {
        return id >= 0 && static_cast<std::size_t>(id) < records_.size() && record(id).alive;
    }
    const AABB& fatAABB(ProxyId id) const { return treeOf(record(id).type).fatAABB(record(id).leaf); }
    std::uint32_t userValue(ProxyId id) const { return record(id).userValue; }
    BodyType type(ProxyId id) const { return record(id).type; }
    const CollisionFilter& filter(ProxyId id) const { return record(id).filter; }
    std::int32_t proxyCount() const { return staticTree_.proxyCount() + movingTree_.proxyCount(); }
    std::size_t moveCount() const { return moveBuffer_.size(); }  // entries waiting for updatePairs
    const DynamicTree& staticTree() const { return staticTree_; }
    const DynamicTree& movingTree() const { return movingTree_; }

    // ---- queries over both trees (moving tree first), on fat boxes
    // callback(proxyId, userValue) -> bool (false stops).
    template <typename Callback>
    void query(const AABB& box, Callback&& callback) const;
    // The same over the static bodies' proxies only.
    template <typename Callback>
    void queryStatic(const AABB& box, Callback&& callback) const;
    // callback(input, proxyId, userValue) -> Real, as DynamicTree::rayCast; the
    // clipped fraction carries over from the moving tree to the static tree.
    template <typename Callback>
    void rayCast(const RayCastInput& input, Callback&& callback) const;

    // Rebuilds the static tree top-down (binned SAH); call after adding many
    // static proxies, e.g. after loading a scene. Ids and pairs are unaffected.
    void rebuildStaticTree() { staticTree_.rebuild(); }

    // Both trees' invariants plus the proxy records and the move buffer.
    // Empty when valid, otherwise the first violation found.
    std::string validate() const;

private:
    friend struct fulcrum::SnapshotAccess;
    struct ProxyRecord {
        std::int32_t leaf = kNullNode;      // proxy id in its tree
        std::int32_t moveIndex = -1;        // entry in moveBuffer_, or -1
        std::int32_t nextFree = kNullProxy; // free-list link while dead
        std::uint32_t userValue = 0;
        CollisionFilter filter;
        BodyType type = BodyType::Static;
        bool alive = false;
    };
    struct MoveEntry {
        ProxyId proxy = kNullProxy;  // kNullProxy once destroyed
        bool fresh = false;          // created or refreshed: every overlap is new
        AABB oldFat;                 // fat box at the last updatePairs (unless fresh)
    };

    const ProxyRecord& record(ProxyId id) const { return records_[static_cast<std::size_t>(id)]; }
    ProxyRecord& record(ProxyId id) { return records_[static_cast<std::size_t>(id)]; }
    const DynamicTree& treeOf(BodyType type) const { return type == BodyType::Static ? staticTree_ : movingTree_; }
    DynamicTree& treeOf(BodyType type) { return type == BodyType::Static ? staticTree_ : movingTree_; }
    void markMoved(ProxyId id, const AABB& oldFat, bool fresh);
    bool typesPair(BodyType a, BodyType b) const {
        if (a == BodyType::Static && b == BodyType::Static) return false;
        return !config_.requireDynamic || a == BodyType::Dynamic || b == BodyType::Dynamic;
    }
    template <typename Predicate>
    void findNewPairs(const MoveEntry& entry, const Predicate& canPair, std::vector<ProxyPair>& out) const;
    void finishUpdate();  // sorts pairs_ and empties the move buffer

    BroadPhaseConfig config_;
    DynamicTree staticTree_;
    DynamicTree movingTree_;
    std::vector<ProxyRecord> records_;
    ProxyId freeRecord_ = kNullProxy;
    std::vector<MoveEntry> moveBuffer_;
    std::vector<ProxyPair> pairs_;
    // Per-worker outputs of the parallel queries (one cache line apart: their
    // size fields change on every push). Reserved like pairs_ once a worker
    // count is known, so steady-state steps allocate nothing.
    struct alignas(64) WorkerPairs {
        std::vector<ProxyPair> pairs;
    };
    std::vector<WorkerPairs> workerPairs_;
};

// ---- templates ------------------------------------------------------------------

template <typename Predicate>
void BroadPhase::findNewPairs(const MoveEntry& entry, const Predicate& canPair, std::vector<ProxyPair>& out) const {
    const ProxyId self = entry.proxy;
    const ProxyRecord& me = record(self);
    const AABB& box = fatAABB(self);
    const auto visit = [&](std::int32_t, std::uint32_t otherValue) {
        const auto other = static_cast<ProxyId>(otherValue);
        if (other == self) return true;
        const ProxyRecord& them = record(other);
        // Both moved: the query of the smaller id reports the pair (it finds
        // the larger one too, since overlap is symmetric and the type rule
        // sends each proxy's query to every tree holding allowed partners).
        const bool themMoved = them.moveIndex >= 0;
        if (themMoved && other < self) return true;
        if (!typesPair(me.type, them.type)) return true;
        // New only if the boxes as of the last update did not overlap.
        if (!entry.fresh) {
            const MoveEntry* theirs = themMoved ? &moveBuffer_[static_cast<std::size_t>(them.moveIndex)] : nullptr;
            if (theirs == nullptr || !theirs->fresh) {
                const AABB& theirOld = theirs != nullptr ? theirs->oldFat : fatAABB(other);
                if (overlaps(entry.oldFat, theirOld)) return true;
            }
        }
        if (!shouldCollide(me.filter, them.filter)) return true;
        const bool selfFirst = self < other;
        const ProxyRecord& first = selfFirst ? me : them;
        const ProxyRecord& second = selfFirst ? them : me;
        if (!canPair(first.userValue, second.userValue)) return true;
        out.push_back({selfFirst ? self : other, selfFirst ? other : self, first.userValue, second.userValue});
        return true;
    };
    movingTree_.query(box, visit);
    // Static proxies only pair with moving ones; kinematic proxies pair with
    // static ones only when non-dynamic pairs are wanted.
    if (me.type == BodyType::Dynamic || (me.type == BodyType::Kinematic && !config_.requireDynamic)) {
        staticTree_.query(box, visit);
    }
}

template <PairPredicate Predicate>
std::span<const ProxyPair> BroadPhase::updatePairs(const Predicate& canPair) {
    pairs_.clear();
    for (const MoveEntry& entry : moveBuffer_) {
        if (entry.proxy != kNullProxy) findNewPairs(entry, canPair, pairs_);
    }
    finishUpdate();
    return pairs_;
}

template <PairPredicate Predicate>
std::span<const ProxyPair> BroadPhase::updatePairs(const Predicate& canPair, TaskSystem& tasks) {
    const std::uint32_t workers = tasks.workerCount();
    if (workers <= 1) return updatePairs(canPair);
    if (workerPairs_.size() < workers) {
        workerPairs_.resize(workers);
        for (WorkerPairs& wp : workerPairs_) wp.pairs.reserve(pairs_.capacity());
    }
    for (WorkerPairs& wp : workerPairs_) wp.pairs.clear();
    // A query costs ~0.3-1 us; 32 of them amortise a range's scheduling.
    const auto count = static_cast<std::uint32_t>(moveBuffer_.size());
    tasks.parallelFor(count, 32, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
        std::vector<ProxyPair>& out = workerPairs_[worker].pairs;
        for (std::uint32_t i = begin; i < end; ++i) {
            const MoveEntry& entry = moveBuffer_[i];
            if (entry.proxy != kNullProxy) findNewPairs(entry, canPair, out);
        }
    });
    // Concatenated in worker order, which depends on timing; the sort in
    // finishUpdate() makes the result a function of the pairs alone.
    pairs_.clear();
    for (const WorkerPairs& wp : workerPairs_) pairs_.insert(pairs_.end(), wp.pairs.begin(), wp.pairs.end());
    finishUpdate();
    return pairs_;
}

inline void BroadPhase::finishUpdate() {
    std::sort(pairs_.begin(), pairs_.end(),
              [](const ProxyPair& l, const ProxyPair& r) { return l.a != r.a ? l.a < r.a : l.b < r.b; });
    for (const MoveEntry& entry : moveBuffer_) {
        if (entry.proxy != kNullProxy) record(entry.proxy).moveIndex = -1;
    }
    moveBuffer_.clear();
}

template <typename Callback>
void BroadPhase::query(const AABB& box, Callback&& callback) const {
    const auto forward = [&](std::int32_t, std::uint32_t proxy) {
        return static_cast<bool>(callback(static_cast<ProxyId>(proxy), record(static_cast<ProxyId>(proxy)).userValue));
    };
    if (!movingTree_.query(box, forward)) return;
    staticTree_.query(box, forward);
}

template <typename Callback>
void BroadPhase::queryStatic(const AABB& box, Callback&& callback) const {
    staticTree_.query(box, [&](std::int32_t, std::uint32_t proxy) {
        return static_cast<bool>(callback(static_cast<ProxyId>(proxy), record(static_cast<ProxyId>(proxy)).userValue));
    });
}

template <typename Callback>
void BroadPhase::rayCast(const RayCastInput& input, Callback&& callback) const {
    const auto forward = [&](const RayCastInput& in, std::int32_t, std::uint32_t proxy) {
        return static_cast<Real>(callback(in, static_cast<ProxyId>(proxy), record(static_cast<ProxyId>(proxy)).userValue));
    };
    RayCastInput rest = input;
    rest.maxFraction = movingTree_.rayCast(input, forward);
    if (rest.maxFraction <= Real(0)) return;
    staticTree_.rayCast(rest, forward);
}

}  // namespace fulcrum
