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
// ---- A limit on new pairs (docs/broad-phase.md, "The pair limit") -------------
// updatePairs(canPair, partners, tasks, maxNewPairs) returns at most
// maxNewPairs pairs (the room the caller has left under its own limit on S).
// N bodies created at one spot overlap in N^2/2 pairs: without a limit the
// pair buffer alone grew to gigabytes. Under the limit the result is the same
// as above (the first search stops as soon as it finds more than that).
// Over it:
//   - with no room, no entry queries; else the first
//     max(kMinEntriesPerUpdate, maxNewPairs / kMinShare) entries of the move
//     buffer query the trees again (the work of a step stays bounded too),
//     each reporting at most its share, maxNewPairs / (entries queried), at
//     least 1: its static partners first (the ground keeps a body in the
//     world), then its moving ones in tree order. Every body then gets some
//     of the room, not the lowest ids all of it. What is left over the limit
//     after that (only when maxNewPairs < kMinEntriesPerUpdate) is cut from
//     the end of the sorted list;
//   - every entry that did not query, stopped at its share or had a reported
//     pair cut stays in the move buffer as "fresh" (all its overlaps count as
//     new), behind the others, so the next updates take turns through them;
//   - the kept pairs are a function of the broad phase's state and the limit
//     alone, never of the thread count (a function of each entry's own query,
//     then the sorted list), so results stay bit-identical.
// S then holds allowed overlapping pairs only, and every allowed overlapping
// pair missing from S has a proxy in the move buffer. A fresh entry may have
// pairs in S already; `partners(proxy, visit)` names them (visit(partnerId)
// for each pair of S holding `proxy`), and they are not reported again. The
// caller's contact lists give them (src/contacts/contact_manager.cpp); an
// update with no limit and no deferred entries never asks. lastUpdate() says
// how many pairs were left out and how many entries wait.
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
// query). The canPair predicate and `partners` must therefore be thread-safe. Moves (tree
// updates) stay serial: they are cheap because most moves stay inside their
// fat box.
//
// ---- Many moved proxies: one descent instead of a query each -----------------
// When at least a kTreePairsShare-th of the moving proxies moved (HighSpeed:
// nearly all of them), the pairs come from one descent of the moving tree
// against itself and one of the moving tree against the static tree
// (DynamicTree::overlapPairs), each overlapping pair seen once, keeping those
// with a moved proxy and the same rules; fresh entries still query on their
// own (their pairs may be in S already, which the `partners` check needs per
// proxy) and the descent leaves their pairs to them. The pairs found are the
// same set as the queries' and sorted the same way, so the choice changes no
// result, only the work (tests/broadphase/pair_descent_test.cpp compares both
// with brute force). With few moved proxies the queries stay: a descent
// would visit every resting overlap too.
//
// ---- Static proxies created beside an empty moving tree ----------------------
// A static proxy's query looks only for moving partners. When it is created
// while the moving tree is empty, every moving proxy at the next update was
// created after it, so is fresh in the move buffer, and that proxy's own
// query finds the pair (static partners are never "moved" there, and a fresh
// entry counts every overlap as new): the static proxy's query would find
// nothing those do not. Such a proxy gets no move-buffer entry; a run
// (position in the buffer, first id, count) remembers where it would be.
// While the new pairs fit (always without a limit) the pairs are the same
// set, sorted the same way. Over the limit, before a destroy, move or refresh
// of such a proxy, and before a snapshot is written, restoreSkippedMoves()
// puts the entries back where they would have been, so every result and
// every snapshot's bytes are those of the entries made at creation. A
// million static boxes (Box3D's large_world) saved 32 MB of entries and a
// million empty queries in the first step (docs/benchmarks.md, `lw8`).
//
// No heap allocation in steady state: the move buffer, the pair buffer, the
// proxy records and the trees' node arrays are reused and grow by doubling.
#include <algorithm>
#include <atomic>
#include <cassert>
#include <cstdint>
#include <mutex>
#include <span>
#include <string>
#include <type_traits>
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

// updatePairs without a limit on the new pairs.
inline constexpr std::uint32_t kNoPairLimit = UINT32_MAX;

// The caller's pairs of a proxy, for a caller that keeps none apart from the
// broad phase's reports (tests, benchmarks): a fresh proxy has no pair yet.
struct NoKnownPairs {
    template <typename Visit>
    void operator()(ProxyId, Visit&&) const {}
};

// What the last updatePairs() left for later (all zero without a limit).
struct PairUpdateStats {
    // New pairs found but not reported: those cut from the sorted list, plus
    // one for each entry stopped at its share (it had at least one more). A
    // lower bound: entries that did not query are not counted.
    std::uint32_t leftOut = 0;
    // Entries left in the move buffer because their new pairs may be
    // incomplete (each is a proxy whose overlaps are searched again).
    std::uint32_t deferred = 0;
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
    // How updatePairs finds the new pairs (see "Many moved proxies"): Auto
    // picks by the share of moved proxies; the others force one way (tests
    // compare them; every way gives the same pairs).
    enum class PairSearch : std::uint8_t { Auto, Queries, Descents };
    PairSearch pairSearch = PairSearch::Auto;
    // Static proxies created while the moving tree is empty get no
    // move-buffer entry (see "Static proxies created beside an empty moving
    // tree"); false gives each its entry at creation (tests compare both: the
    // same pairs, bit for bit).
    bool skipNewStaticEntries = true;
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
    std::span<const ProxyPair> updatePairs(const Predicate& canPair) {
        return updatePairs(canPair, NoKnownPairs{}, nullptr, kNoPairLimit);
    }
    std::span<const ProxyPair> updatePairs() { return updatePairs(AcceptAllPairs{}); }
    // The same, with the queries run in parallel on `tasks` (same result).
    template <PairPredicate Predicate>
    std::span<const ProxyPair> updatePairs(const Predicate& canPair, TaskSystem& tasks) {
        return updatePairs(canPair, NoKnownPairs{}, &tasks, kNoPairLimit);
    }
    // At most maxNewPairs of them (kNoPairLimit: all), on `tasks` (nullptr:
    // this thread); `partners` names the caller's pairs of a proxy (see "A
    // limit on new pairs" above). The same result for any thread count.
    template <PairPredicate Predicate, typename Partners>
    std::span<const ProxyPair> updatePairs(const Predicate& canPair, const Partners& partners, TaskSystem* tasks,
                                           std::uint32_t maxNewPairs);
    // The last update's pairs left for later (zeros when everything fit).
    const PairUpdateStats& lastUpdate() const { return lastUpdate_; }
    // Over the limit, the entries that query get a share of at least
    // kMinShare pairs each, but at least kMinEntriesPerUpdate entries query
    // (a share of 1 or more), so a long queue of waiting entries drains even
    // while little room frees up. A query of a body in a crowd visits the
    // whole crowd, so these bound the work of an update over the limit:
    // 10,000 spheres at one spot, at most 7,000 queries in the first step
    // (225,552 pairs of room) and a few hundred in the next ones.
    static constexpr std::size_t kMinEntriesPerUpdate = 256;
    static constexpr std::size_t kMinShare = 32;

    // Capacity for `count` proxies in all (records, and either tree's nodes:
    // memory reserved, touched only when used).
    void reserveProxies(std::size_t count) {
        records_.reserve(count);
        staticTree_.reserve(count);
        movingTree_.reserve(count);
    }

    // Grows the new-pair buffer so updatePairs() need not allocate (the world
    // calls it when bodies are created).
    void reservePairs(std::size_t count) {
        if (pairs_.capacity() < count) pairs_.reserve(count);
        for (QueryScratch& wp : workerPairs_)
            if (wp.pairs.capacity() < count) wp.pairs.reserve(count);
    }

    // Whether two proxies' fat boxes overlap: the caller ends a pair when false.
    bool testOverlap(ProxyId a, ProxyId b) const { return overlaps(fatAABB(a), fatAABB(b)); }
    // Hints for a caller about to run testOverlap over many scattered pairs
    // (the contact manager's end test): load a proxy's record, then, once
    // that has arrived, its leaf's box. No effect on any result.
    void prefetchRecord(ProxyId id) const {
#if defined(__GNUC__) || defined(__clang__)
        __builtin_prefetch(&record(id));
#else
        (void)id;
#endif
    }
    void prefetchFatBox(ProxyId id) const {
#if defined(__GNUC__) || defined(__clang__)
        __builtin_prefetch(&fatAABB(id));
#else
        (void)id;
#endif
    }

    // ---- accessors
    bool isProxy(ProxyId id) const {
        return id >= 0 && static_cast<std::size_t>(id) < records_.size() && record(id).alive;
    }
    const AABB& fatAABB(ProxyId id) const { return treeOf(record(id).type).fatAABB(record(id).leaf); }
    std::uint32_t userValue(ProxyId id) const { return record(id).userValue; }
    BodyType type(ProxyId id) const { return record(id).type; }
    const CollisionFilter& filter(ProxyId id) const { return record(id).filter; }
    std::int32_t proxyCount() const { return staticTree_.proxyCount() + movingTree_.proxyCount(); }
    std::int32_t staticProxyCount() const { return staticTree_.proxyCount(); }  // the waiting ones too
    // Entries waiting for updatePairs (the skipped static ones counted).
    std::size_t moveCount() const { return moveBuffer_.size() + skippedCount_; }
    // Puts the skipped static proxies' entries (see "Static proxies created
    // beside an empty moving tree") back in the move buffer where they would
    // be. Changes no result; snapshots call it before writing the buffer.
    void restoreSkippedMoves() {
        if (!skippedRuns_.empty()) restoreSkippedMovesSlow();
    }
    // The static tree with every static proxy in it (see settleStaticTree).
    const DynamicTree& staticTree() const {
        settleStaticTree();
        return staticTree_;
    }
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
    void rebuildStaticTree() {
        settleStaticTree();
        staticTree_.rebuild();
    }
    // Static proxies wait outside the static tree when created
    // (DynamicTree::createProxyDeferred) and go in at the first query, ray
    // cast, pair update or change of the static tree after them: one
    // insertion each as before, or one bulk build when many came at once (a
    // scene of a million static bodies, created one by one: 1.8 s of exact
    // sibling searches before). Const, so that the world's const queries see
    // every body created before them; guarded like the world's stray-body
    // list (src/world/stray_bodies.hpp): queries may run concurrently with
    // each other, never with changes, and the first one settles the tree.
    void settleStaticTree() const {
        if (staticWaiting_.flag.load(std::memory_order_acquire)) settleStaticTreeSlow();
    }
    // Rebuilds the moving tree the same way: after setFatBox for most of its
    // proxies, instead of reinsertProxy for each (the leaves keep their ids
    // and boxes; the pool is not reallocated, so fatAABB and testOverlap may
    // run on other threads meanwhile, as with the reinsertions).
    void rebuildMovingTree() { movingTree_.rebuild(); }
    // The same, but refitting the tree's boxes in place while its shape is
    // still good enough (DynamicTree::refitOrRebuild); the same guarantees.
    void refitMovingTree() { movingTree_.refitOrRebuild(); }

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
        bool skipped = false;  // static, created beside an empty moving tree: its entry is in skippedRuns_
    };
    // Skipped entries: `count` proxies from `first` on (consecutive ids) whose
    // entries would stand before moveBuffer_[position].
    struct SkippedRun {
        std::uint32_t position = 0;
        ProxyId first = kNullProxy;
        std::uint32_t count = 0;
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
    void restoreSkippedMovesSlow();
    // After an update that used the skipped entries' pairs: they are done.
    void dropSkippedMoves();
    bool typesPair(BodyType a, BodyType b) const {
        if (a == BodyType::Static && b == BodyType::Static) return false;
        return !config_.requireDynamic || a == BodyType::Dynamic || b == BodyType::Dynamic;
    }
    // Per-worker state of the pair queries (one cache line apart: their size
    // fields change on every push). Reserved like pairs_ once a worker count
    // is known, so steady-state steps allocate nothing.
    struct alignas(64) QueryScratch {
        std::vector<ProxyPair> pairs;
        // The caller's partners of the querying proxy (see `partners`):
        // stamp[id] == epoch marks a pair already in S. Indexed by proxy id.
        std::vector<std::uint32_t> stamp;
        std::uint32_t epoch = 0;
        template <typename Partners>
        void stampPartners(ProxyId self, const Partners& partners);
    };
    static constexpr std::uint32_t kNoEntryCap = UINT32_MAX;
    // One query: appends the new pairs of `entry` to `out`, at most entryCap
    // of them and while out holds fewer than outCap. Returns false when it
    // stopped with a pair unreported.
    // With descended (the descents found the pairs of non-fresh entries),
    // a fresh entry leaves to a partner only pairs the partner's own query
    // reports: those with a fresh partner of a smaller id.
    template <typename Predicate, typename Partners>
    bool findNewPairs(const MoveEntry& entry, const Predicate& canPair, const Partners& partners, std::uint32_t entryCap,
                      std::size_t outCap, QueryScratch& scratch, std::vector<ProxyPair>& out,
                      bool descended = false) const;
    // The queries of the first `count` entries into pairs_, on `tasks` (or this
    // thread); with recordCuts, entryCut_[i] says whether entry i stopped early.
    template <typename Predicate, typename Partners>
    void runQueries(std::size_t count, std::uint32_t entryCap, std::size_t outCap, bool recordCuts,
                    const Predicate& canPair, const Partners& partners, TaskSystem* tasks);
    void prepareQueries(std::uint32_t workers);  // sizes the per-worker scratch and the cut flags
    // Whether every new pair is better found by the descents (see "Many moved
    // proxies" above): the non-fresh entries are at least a
    // kTreePairsShare-th of the moving proxies, and there are enough of them.
    static constexpr std::size_t kTreePairsShare = 4;
    static constexpr std::size_t kTreePairsMinEntries = 64;
    bool preferDescent() const;
    // All the new pairs (up to outCap per buffer, as runQueries) by the
    // descents plus the fresh entries' queries, into pairs_.
    template <typename Predicate, typename Partners>
    void runDescents(std::size_t outCap, const Predicate& canPair, const Partners& partners, TaskSystem* tasks);
    // The descents' callback for one overlapping pair of proxies: appends it
    // to `out` when it is new, allowed and neither proxy is fresh. Returns
    // false when out was full.
    template <typename Predicate>
    bool considerPair(ProxyId x, ProxyId y, const Predicate& canPair, std::size_t outCap,
                      std::vector<ProxyPair>& out) const;
    // Parts of the descents for the workers (splitDescents fills it).
    struct DescentPart {
        std::int32_t moving = kNullNode;  // a node of the moving tree
        std::int32_t other = kNullNode;   // a node of the moving tree, or with withStatic of the static tree
        bool withStatic = false;
    };
    void splitDescents(std::size_t target);
    // Sorts pairs_, cuts it to maxNewPairs, and rebuilds the move buffer from
    // the entries that must wait: those past `queried`, and with cutsRecorded
    // those whose entryCut_ is set or whose pair was cut.
    void finishUpdate(std::size_t queried, std::uint32_t maxNewPairs, bool cutsRecorded);

    void settleStaticTreeSlow() const;
    // Whether the static tree may hold waiting leaves, and the lock of the
    // first query that inserts them. A copy of a broad phase gets its own.
    struct WaitingGuard {
        std::atomic<bool> flag{false};
        std::mutex mutex;
        WaitingGuard() = default;
        WaitingGuard(const WaitingGuard& o) : flag(o.flag.load(std::memory_order_relaxed)) {}
        WaitingGuard& operator=(const WaitingGuard& o) {
            flag.store(o.flag.load(std::memory_order_relaxed), std::memory_order_relaxed);
            return *this;
        }
    };

    BroadPhaseConfig config_;
    // Mutable for settleStaticTree() only: inserting the waiting leaves
    // changes no proxy's id, box or pairs, only what queries can reach.
    mutable DynamicTree staticTree_;
    mutable WaitingGuard staticWaiting_;
    DynamicTree movingTree_;
    detail::LargeArray<ProxyRecord> records_;
    ProxyId freeRecord_ = kNullProxy;
    std::vector<MoveEntry> moveBuffer_;
    std::vector<SkippedRun> skippedRuns_;    // in buffer order (see "Static proxies created beside ...")
    std::size_t skippedCount_ = 0;           // their proxies in all
    std::vector<MoveEntry> waitingScratch_;  // finishUpdate: the entries that wait
    std::vector<std::uint8_t> entryCut_;     // per move entry: 1 its query stopped at its share, 2 a pair of it was cut
    std::vector<ProxyPair> pairs_;
    std::vector<QueryScratch> workerPairs_;  // [0] also serves the queries on one thread
    std::vector<DescentPart> descentParts_, descentSplit_;  // splitDescents' scratch
    PairUpdateStats lastUpdate_;
};

// ---- templates ------------------------------------------------------------------

template <typename Partners>
void BroadPhase::QueryScratch::stampPartners(ProxyId self, const Partners& partners) {
    if (++epoch == 0) {  // wrapped: old stamps could match again
        std::fill(stamp.begin(), stamp.end(), 0u);
        epoch = 1;
    }
    partners(self, [&](ProxyId partner) { stamp[static_cast<std::size_t>(partner)] = epoch; });
}

template <typename Predicate, typename Partners>
bool BroadPhase::findNewPairs(const MoveEntry& entry, const Predicate& canPair, const Partners& partners,
                              std::uint32_t entryCap, std::size_t outCap, QueryScratch& scratch,
                              std::vector<ProxyPair>& out, bool descended) const {
    const ProxyId self = entry.proxy;
    const ProxyRecord& me = record(self);
    const AABB& box = fatAABB(self);
    std::uint32_t found = 0;
    bool stamped = false;  // scratch holds self's partners (stamped on first need)
    bool complete = true;
    const auto visit = [&](std::int32_t, std::uint32_t otherValue) {
        const auto other = static_cast<ProxyId>(otherValue);
        if (other == self) return true;
        const ProxyRecord& them = record(other);
        // Both moved: the query of the smaller id reports the pair (it finds
        // the larger one too, since overlap is symmetric and the type rule
        // sends each proxy's query to every tree holding allowed partners).
        const bool themMoved = them.moveIndex >= 0;
        const MoveEntry* theirs = themMoved ? &moveBuffer_[static_cast<std::size_t>(them.moveIndex)] : nullptr;
        const bool theyReport = themMoved && (!descended || theirs->fresh);
        if (theyReport && other < self) return true;
        if (!typesPair(me.type, them.type)) return true;
        // New only if the boxes as of the last update did not overlap.
        const bool eitherFresh = entry.fresh || (theirs != nullptr && theirs->fresh);
        if (!eitherFresh) {
            const AABB& theirOld = theirs != nullptr ? theirs->oldFat : fatAABB(other);
            if (overlaps(entry.oldFat, theirOld)) return true;
        }
        if (!shouldCollide(me.filter, them.filter)) return true;
        const bool selfFirst = self < other;
        const ProxyRecord& first = selfFirst ? me : them;
        const ProxyRecord& second = selfFirst ? them : me;
        if (!canPair(first.userValue, second.userValue)) return true;
        // A fresh entry's pairs may be in S already (it waited over the limit).
        if (!std::is_same_v<Partners, NoKnownPairs> && eitherFresh) {
            if (!stamped) {
                scratch.stampPartners(self, partners);
                stamped = true;
            }
            if (scratch.stamp[static_cast<std::size_t>(other)] == scratch.epoch) return true;
        }
        if (found == entryCap || out.size() >= outCap) {
            complete = false;
            return false;
        }
        out.push_back({selfFirst ? self : other, selfFirst ? other : self, first.userValue, second.userValue});
        ++found;
        return true;
    };
    // Static partners first: over the limit they come first in an entry's
    // share. Static proxies only pair with moving ones; kinematic proxies pair
    // with static ones only when non-dynamic pairs are wanted.
    if (me.type == BodyType::Dynamic || (me.type == BodyType::Kinematic && !config_.requireDynamic)) {
        if (!staticTree_.query(box, visit)) return complete;
    }
    movingTree_.query(box, visit);
    return complete;
}

template <typename Predicate>
bool BroadPhase::considerPair(ProxyId x, ProxyId y, const Predicate& canPair, std::size_t outCap,
                              std::vector<ProxyPair>& out) const {
    const ProxyRecord& rx = record(x);
    const ProxyRecord& ry = record(y);
    if (rx.moveIndex < 0 && ry.moveIndex < 0) return true;  // neither moved: an old pair
    const MoveEntry* ex = rx.moveIndex >= 0 ? &moveBuffer_[static_cast<std::size_t>(rx.moveIndex)] : nullptr;
    const MoveEntry* ey = ry.moveIndex >= 0 ? &moveBuffer_[static_cast<std::size_t>(ry.moveIndex)] : nullptr;
    if ((ex != nullptr && ex->fresh) || (ey != nullptr && ey->fresh)) return true;  // the fresh one's query
    if (!typesPair(rx.type, ry.type)) return true;
    // New only if the boxes as of the last update did not overlap.
    if (overlaps(ex != nullptr ? ex->oldFat : fatAABB(x), ey != nullptr ? ey->oldFat : fatAABB(y))) return true;
    if (!shouldCollide(rx.filter, ry.filter)) return true;
    const bool xFirst = x < y;
    const ProxyRecord& first = xFirst ? rx : ry;
    const ProxyRecord& second = xFirst ? ry : rx;
    if (!canPair(first.userValue, second.userValue)) return true;
    if (out.size() >= outCap) return false;
    out.push_back({xFirst ? x : y, xFirst ? y : x, first.userValue, second.userValue});
    return true;
}

template <typename Predicate, typename Partners>
void BroadPhase::runDescents(std::size_t outCap, const Predicate& canPair, const Partners& partners,
                             TaskSystem* tasks) {
    const std::uint32_t workers = tasks != nullptr ? tasks->workerCount() : 1;
    const std::int32_t movingRoot = movingTree_.root();
    const std::int32_t staticRoot = staticTree_.root();
    movingTree_.prepareSelfDescent();  // a large tree's depth-first copy, which its descent walks
    pairs_.clear();
    if (workers <= 1) {
        const auto add = [&](std::uint32_t x, std::uint32_t y) {
            return considerPair(static_cast<ProxyId>(x), static_cast<ProxyId>(y), canPair, outCap, pairs_);
        };
        if (!movingTree_.overlapPairs(movingRoot, movingTree_, movingRoot, add)) return;
        if (!movingTree_.overlapPairs(movingRoot, staticTree_, staticRoot, add)) return;
        for (const MoveEntry& entry : moveBuffer_) {
            if (entry.proxy == kNullProxy || !entry.fresh) continue;
            if (pairs_.size() >= outCap) return;
            findNewPairs(entry, canPair, partners, kNoEntryCap, outCap, workerPairs_[0], pairs_, true);
        }
        return;
    }
    for (QueryScratch& wp : workerPairs_) wp.pairs.clear();
    movingTree_.prepareDescentIndex();  // the parts start below the root
    splitDescents(std::size_t{8} * workers);
    const std::vector<DescentPart>& parts = descentParts_;
    tasks->parallelFor(static_cast<std::uint32_t>(parts.size()), 1,
                       [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
                           std::vector<ProxyPair>& out = workerPairs_[worker].pairs;
                           const auto add = [&](std::uint32_t x, std::uint32_t y) {
                               return considerPair(static_cast<ProxyId>(x), static_cast<ProxyId>(y), canPair, outCap,
                                                   out);
                           };
                           for (std::uint32_t i = begin; i < end; ++i) {
                               const DescentPart& part = parts[i];
                               const DynamicTree& other = part.withStatic ? staticTree_ : movingTree_;
                               if (!movingTree_.overlapPairs(part.moving, other, part.other, add)) return;
                           }
                       });
    tasks->parallelFor(static_cast<std::uint32_t>(moveBuffer_.size()), 32,
                       [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
                           QueryScratch& scratch = workerPairs_[worker];
                           for (std::uint32_t i = begin; i < end && scratch.pairs.size() < outCap; ++i) {
                               const MoveEntry& entry = moveBuffer_[i];
                               if (entry.proxy == kNullProxy || !entry.fresh) continue;
                               findNewPairs(entry, canPair, partners, kNoEntryCap, outCap, scratch, scratch.pairs,
                                            true);
                           }
                       });
    // Concatenated in worker order; finishUpdate() sorts them.
    for (const QueryScratch& wp : workerPairs_) pairs_.insert(pairs_.end(), wp.pairs.begin(), wp.pairs.end());
}

template <typename Predicate, typename Partners>
void BroadPhase::runQueries(std::size_t count, std::uint32_t entryCap, std::size_t outCap, bool recordCuts,
                            const Predicate& canPair, const Partners& partners, TaskSystem* tasks) {
    const std::uint32_t workers = tasks != nullptr ? tasks->workerCount() : 1;
    pairs_.clear();
    if (workers <= 1) {
        for (std::size_t i = 0; i < count && pairs_.size() < outCap; ++i) {
            const MoveEntry& entry = moveBuffer_[i];
            if (entry.proxy == kNullProxy) continue;
            const bool complete = findNewPairs(entry, canPair, partners, entryCap, outCap, workerPairs_[0], pairs_);
            if (recordCuts) entryCut_[i] = complete ? 0 : 1;
        }
        return;
    }
    for (QueryScratch& wp : workerPairs_) wp.pairs.clear();
    // A query costs ~0.3-1 us; 32 of them amortise a range's scheduling.
    tasks->parallelFor(static_cast<std::uint32_t>(count), 32,
                       [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
                           QueryScratch& scratch = workerPairs_[worker];
                           for (std::uint32_t i = begin; i < end && scratch.pairs.size() < outCap; ++i) {
                               const MoveEntry& entry = moveBuffer_[i];
                               if (entry.proxy == kNullProxy) continue;
                               const bool complete =
                                   findNewPairs(entry, canPair, partners, entryCap, outCap, scratch, scratch.pairs);
                               if (recordCuts) entryCut_[i] = complete ? 0 : 1;
                           }
                       });
    // Concatenated in worker order, which depends on timing; the sort in
    // finishUpdate() makes the result a function of the pairs alone.
    for (const QueryScratch& wp : workerPairs_) pairs_.insert(pairs_.end(), wp.pairs.begin(), wp.pairs.end());
}

template <PairPredicate Predicate, typename Partners>
std::span<const ProxyPair> BroadPhase::updatePairs(const Predicate& canPair, const Partners& partners,
                                                   TaskSystem* tasks, std::uint32_t maxNewPairs) {
    settleStaticTree();
    prepareQueries(tasks != nullptr ? tasks->workerCount() : 1);
    const std::size_t entries = moveBuffer_.size();
    const bool descend = preferDescent();
    if (maxNewPairs == kNoPairLimit) {
        if (descend) {
            runDescents(SIZE_MAX, canPair, partners, tasks);
        } else {
            runQueries(entries, kNoEntryCap, SIZE_MAX, false, canPair, partners, tasks);
        }
        finishUpdate(entries, maxNewPairs, false);
        dropSkippedMoves();
        return pairs_;
    }
    // First every new pair, stopping once any buffer holds more than the
    // room: if they all fit, that is the answer (as without a limit). A worker
    // stops only past maxNewPairs, so "they fit" does not depend on how the
    // entries were spread over the workers.
    if (descend) {
        runDescents(std::size_t{maxNewPairs} + 1, canPair, partners, tasks);
    } else {
        runQueries(entries, kNoEntryCap, std::size_t{maxNewPairs} + 1, false, canPair, partners, tasks);
    }
    if (pairs_.size() <= maxNewPairs) {
        finishUpdate(entries, maxNewPairs, false);
        dropSkippedMoves();
        return pairs_;
    }
    // They don't: from here on the order of the entries counts, the skipped
    // ones' too. No room at all: every entry waits.
    restoreSkippedMoves();
    prepareQueries(tasks != nullptr ? tasks->workerCount() : 1);
    const std::size_t allEntries = moveBuffer_.size();
    if (maxNewPairs == 0) {
        pairs_.clear();
        finishUpdate(0, maxNewPairs, false);
        return pairs_;
    }
    // Again, fewer entries, each up to its share, noting who stopped.
    const std::size_t queried =
        std::min(allEntries, std::max(kMinEntriesPerUpdate, std::size_t{maxNewPairs} / kMinShare));
    const auto share = static_cast<std::uint32_t>(std::max<std::size_t>(1, maxNewPairs / queried));
    std::fill(entryCut_.begin(), entryCut_.begin() + static_cast<std::ptrdiff_t>(queried), std::uint8_t{0});
    runQueries(queried, share, SIZE_MAX, true, canPair, partners, tasks);
    finishUpdate(queried, maxNewPairs, true);
    return pairs_;
}

template <typename Callback>
void BroadPhase::query(const AABB& box, Callback&& callback) const {
    settleStaticTree();
    const auto forward = [&](std::int32_t, std::uint32_t proxy) {
        return static_cast<bool>(callback(static_cast<ProxyId>(proxy), record(static_cast<ProxyId>(proxy)).userValue));
    };
    if (!movingTree_.query(box, forward)) return;
    staticTree_.query(box, forward);
}

template <typename Callback>
void BroadPhase::queryStatic(const AABB& box, Callback&& callback) const {
    settleStaticTree();
    staticTree_.query(box, [&](std::int32_t, std::uint32_t proxy) {
        return static_cast<bool>(callback(static_cast<ProxyId>(proxy), record(static_cast<ProxyId>(proxy)).userValue));
    });
}

template <typename Callback>
void BroadPhase::rayCast(const RayCastInput& input, Callback&& callback) const {
    settleStaticTree();
    const auto forward = [&](const RayCastInput& in, std::int32_t, std::uint32_t proxy) {
        return static_cast<Real>(callback(in, static_cast<ProxyId>(proxy), record(static_cast<ProxyId>(proxy)).userValue));
    };
    RayCastInput rest = input;
    rest.maxFraction = movingTree_.rayCast(input, forward);
    if (rest.maxFraction <= Real(0)) return;
    staticTree_.rayCast(rest, forward);
}

}  // namespace fulcrum
