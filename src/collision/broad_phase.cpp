// BroadPhase: proxy bookkeeping, the move buffer and validation. Pair finding
// is a template in broad_phase.hpp (the caller's predicate inlines into it).
#include "collision/broad_phase.hpp"

#include <algorithm>
#include <sstream>

namespace fulcrum {

BroadPhase::BroadPhase(const BroadPhaseConfig& config)
    : config_(config), staticTree_(config.staticTree), movingTree_(config.movingTree) {}

ProxyId BroadPhase::createProxy(const AABB& tightBox, BodyType type, const CollisionFilter& filter,
                                std::uint32_t userValue) {
    ProxyId id;
    if (freeRecord_ != kNullProxy) {
        id = freeRecord_;
        freeRecord_ = record(id).nextFree;
    } else {
        id = static_cast<ProxyId>(records_.size());
        records_.emplace_back();
    }
    ProxyRecord& r = record(id);
    r = ProxyRecord{};
    r.userValue = userValue;
    r.filter = filter;
    r.type = type;
    r.alive = true;
    if (type == BodyType::Static) {
        r.leaf = staticTree_.createProxyDeferred(tightBox, static_cast<std::uint32_t>(id));
        staticWaiting_.flag.store(true, std::memory_order_release);
        if (config_.skipNewStaticEntries && movingTree_.proxyCount() == 0) {
            // Its query could find nothing the later moving proxies' own do
            // not (see "Static proxies created beside an empty moving tree").
            r.skipped = true;
            const auto position = static_cast<std::uint32_t>(moveBuffer_.size());
            if (!skippedRuns_.empty() && skippedRuns_.back().position == position &&
                skippedRuns_.back().first + static_cast<ProxyId>(skippedRuns_.back().count) == id) {
                ++skippedRuns_.back().count;
            } else {
                skippedRuns_.push_back({position, id, 1});
            }
            ++skippedCount_;
            return id;
        }
    } else {
        r.leaf = movingTree_.createProxy(tightBox, static_cast<std::uint32_t>(id));
    }
    markMoved(id, AABB{}, true);
    return id;
}

void BroadPhase::restoreSkippedMovesSlow() {
    // Merge the runs into the buffer at their positions (ascending).
    waitingScratch_.clear();
    waitingScratch_.reserve(moveBuffer_.size() + skippedCount_);
    std::size_t run = 0;
    for (std::size_t i = 0; i <= moveBuffer_.size(); ++i) {
        for (; run < skippedRuns_.size() && skippedRuns_[run].position == i; ++run) {
            const SkippedRun& s = skippedRuns_[run];
            for (std::uint32_t k = 0; k < s.count; ++k) {
                const ProxyId id = s.first + static_cast<ProxyId>(k);
                record(id).skipped = false;
                waitingScratch_.push_back({id, true, AABB{}});
            }
        }
        if (i < moveBuffer_.size()) waitingScratch_.push_back(moveBuffer_[i]);
    }
    assert(run == skippedRuns_.size());
    moveBuffer_.swap(waitingScratch_);
    for (std::size_t i = 0; i < moveBuffer_.size(); ++i) {
        if (moveBuffer_[i].proxy != kNullProxy) record(moveBuffer_[i].proxy).moveIndex = static_cast<std::int32_t>(i);
    }
    skippedRuns_.clear();
    skippedCount_ = 0;
}

void BroadPhase::dropSkippedMoves() {
    for (const SkippedRun& s : skippedRuns_) {
        for (std::uint32_t k = 0; k < s.count; ++k) record(s.first + static_cast<ProxyId>(k)).skipped = false;
    }
    skippedRuns_.clear();
    skippedCount_ = 0;
}

void BroadPhase::settleStaticTreeSlow() const {
    const std::lock_guard<std::mutex> lock(staticWaiting_.mutex);
    if (!staticWaiting_.flag.load(std::memory_order_relaxed)) return;
    staticTree_.insertPending();
    staticWaiting_.flag.store(false, std::memory_order_release);
}

void BroadPhase::destroyProxy(ProxyId id) {
    assert(isProxy(id));
    if (record(id).skipped) restoreSkippedMovesSlow();  // its entry as it would be, then gone as usual
    ProxyRecord& r = record(id);
    if (r.moveIndex >= 0) moveBuffer_[static_cast<std::size_t>(r.moveIndex)].proxy = kNullProxy;
    treeOf(r.type).destroyProxy(r.leaf);
    r = ProxyRecord{};
    r.nextFree = freeRecord_;
    freeRecord_ = id;
}

bool BroadPhase::moveProxy(ProxyId id, const AABB& tightBox, const Vec3& displacement) {
    assert(isProxy(id));
    ProxyRecord& r = record(id);
    const AABB before = treeOf(r.type).fatAABB(r.leaf);
    if (!treeOf(r.type).moveProxy(r.leaf, tightBox, displacement)) return false;
    markMoved(id, before, false);
    return true;
}

void BroadPhase::setFilter(ProxyId id, const CollisionFilter& filter) {
    assert(isProxy(id));
    record(id).filter = filter;
    refreshProxy(id);
}

void BroadPhase::refreshProxy(ProxyId id) {
    assert(isProxy(id));
    markMoved(id, AABB{}, true);
}

// First change since the last update: remember the box as of that update.
// Later changes keep it; a refresh makes the entry fresh for good.
void BroadPhase::markMoved(ProxyId id, const AABB& oldFat, bool fresh) {
    if (record(id).skipped) restoreSkippedMovesSlow();  // it has its (fresh) entry, as if never skipped
    ProxyRecord& r = record(id);
    if (r.moveIndex < 0) {
        r.moveIndex = static_cast<std::int32_t>(moveBuffer_.size());
        moveBuffer_.push_back({id, fresh, oldFat});
    } else if (fresh) {
        moveBuffer_[static_cast<std::size_t>(r.moveIndex)].fresh = true;
    }
}

void BroadPhase::prepareQueries(std::uint32_t workers) {
    if (workerPairs_.size() < workers) {
        const std::size_t had = workerPairs_.size();
        workerPairs_.resize(workers);
        for (std::size_t k = had; k < workers; ++k) workerPairs_[k].pairs.reserve(pairs_.capacity());
    }
    // Grown with the proxy records' capacity: only when proxies were created.
    for (QueryScratch& wp : workerPairs_) {
        if (wp.stamp.size() < records_.size()) wp.stamp.resize(records_.capacity(), 0u);
    }
    if (entryCut_.size() < moveBuffer_.size()) entryCut_.resize(moveBuffer_.capacity(), 0);
}

bool BroadPhase::preferDescent() const {
    // Only the moved entries count: the descent of the moving tree costs
    // about what its proxies' queries would, so it pays once enough of them
    // would query anyway (fresh entries still do).
    if (config_.pairSearch != BroadPhaseConfig::PairSearch::Auto) {
        return config_.pairSearch == BroadPhaseConfig::PairSearch::Descents;
    }
    const std::size_t needed = std::max(kTreePairsMinEntries, (static_cast<std::size_t>(movingTree_.proxyCount()) +
                                                               kTreePairsShare - 1) / kTreePairsShare);
    if (moveBuffer_.size() < needed) return false;
    std::size_t moved = 0;
    for (const MoveEntry& entry : moveBuffer_) {
        moved += entry.proxy != kNullProxy && !entry.fresh ? 1 : 0;
        if (moved == needed) return true;
    }
    return false;
}

void BroadPhase::splitDescents(std::size_t target) {
    descentParts_.clear();
    const std::int32_t movingRoot = movingTree_.root();
    const std::int32_t staticRoot = staticTree_.root();
    if (movingRoot == kNullNode) return;
    descentParts_.push_back({movingRoot, movingRoot, false});
    if (staticRoot != kNullNode && overlaps(movingTree_.fatAABB(movingRoot), staticTree_.fatAABB(staticRoot))) {
        descentParts_.push_back({movingRoot, staticRoot, true});
    }
    // Breadth first, a level at a time, until there are enough parts for the
    // workers or none splits further (the parts depend on the trees only).
    while (descentParts_.size() < target) {
        descentSplit_.clear();
        bool split = false;
        for (const DescentPart& part : descentParts_) {
            const DynamicTree& other = part.withStatic ? staticTree_ : movingTree_;
            const bool did = movingTree_.splitPairs(part.moving, other, part.other, [&](std::int32_t a, std::int32_t b) {
                descentSplit_.push_back({a, b, part.withStatic});
            });
            if (did) {
                split = true;
            } else {
                descentSplit_.push_back(part);
            }
        }
        descentParts_.swap(descentSplit_);
        if (!split) break;
    }
}

void BroadPhase::finishUpdate(std::size_t queried, std::uint32_t maxNewPairs, bool cutsRecorded) {
    std::sort(pairs_.begin(), pairs_.end(),
              [](const ProxyPair& l, const ProxyPair& r) { return l.a != r.a ? l.a < r.a : l.b < r.b; });
    lastUpdate_ = {};
    if (pairs_.size() > maxNewPairs) {
        // Past the room in (a, b) order. The query that found a pair waits:
        // the smaller id's when both are in the move buffer, else the one there.
        for (std::size_t k = maxNewPairs; k < pairs_.size(); ++k) {
            const ProxyPair& p = pairs_[k];
            const ProxyId reporter = record(p.a).moveIndex >= 0 ? p.a : p.b;
            entryCut_[static_cast<std::size_t>(record(reporter).moveIndex)] |= 2;
        }
        lastUpdate_.leftOut = static_cast<std::uint32_t>(pairs_.size() - maxNewPairs);
        pairs_.resize(maxNewPairs);
    }
    const std::size_t entries = moveBuffer_.size();
    if (queried == entries && !cutsRecorded) {  // everything fit: the buffer empties
        for (const MoveEntry& entry : moveBuffer_) {
            if (entry.proxy != kNullProxy) record(entry.proxy).moveIndex = -1;
        }
        moveBuffer_.clear();
        return;
    }
    // The entries that must wait, fresh: first those that did not query, then
    // those that stopped early, so the next updates take turns through them.
    waitingScratch_.clear();
    for (std::size_t i = queried; i < entries; ++i) {
        if (moveBuffer_[i].proxy != kNullProxy) waitingScratch_.push_back({moveBuffer_[i].proxy, true, AABB{}});
    }
    for (std::size_t i = 0; i < queried; ++i) {
        const MoveEntry& entry = moveBuffer_[i];
        if (entry.proxy == kNullProxy) continue;
        if (cutsRecorded && entryCut_[i] != 0) {
            waitingScratch_.push_back({entry.proxy, true, AABB{}});
            if ((entryCut_[i] & 1) != 0) ++lastUpdate_.leftOut;  // it stopped at its share: one more at least
        } else {
            record(entry.proxy).moveIndex = -1;
        }
    }
    moveBuffer_.swap(waitingScratch_);
    for (std::size_t i = 0; i < moveBuffer_.size(); ++i) record(moveBuffer_[i].proxy).moveIndex = static_cast<std::int32_t>(i);
    lastUpdate_.deferred = static_cast<std::uint32_t>(moveBuffer_.size());
}

std::string BroadPhase::validate() const {
    std::ostringstream why;
    std::string tree = staticTree_.validate();
    if (!tree.empty()) return "static tree: " + tree;
    tree = movingTree_.validate();
    if (!tree.empty()) return "moving tree: " + tree;

    std::int32_t staticCount = 0, movingCount = 0;
    std::size_t skippedCount = 0;
    for (std::size_t i = 0; i < records_.size(); ++i) {
        const ProxyRecord& r = records_[i];
        const auto id = static_cast<ProxyId>(i);
        if (!r.alive) {
            if (r.moveIndex >= 0) {
                why << "dead proxy " << id << " is in the move buffer";
                return why.str();
            }
            continue;
        }
        const DynamicTree& t = treeOf(r.type);
        if (!t.isProxy(r.leaf) || t.userValue(r.leaf) != static_cast<std::uint32_t>(id)) {
            why << "proxy " << id << " does not own leaf " << r.leaf << " of the "
                << (r.type == BodyType::Static ? "static" : "moving") << " tree";
            return why.str();
        }
        (r.type == BodyType::Static ? staticCount : movingCount) += 1;
        if (r.skipped && (r.type != BodyType::Static || r.moveIndex >= 0)) {
            why << "skipped proxy " << id << " is not a static proxy outside the move buffer";
            return why.str();
        }
        skippedCount += r.skipped ? 1 : 0;
        if (r.moveIndex >= 0 &&
            (static_cast<std::size_t>(r.moveIndex) >= moveBuffer_.size() ||
             moveBuffer_[static_cast<std::size_t>(r.moveIndex)].proxy != id)) {
            why << "proxy " << id << " has a stale move-buffer index " << r.moveIndex;
            return why.str();
        }
    }
    if (staticCount != staticTree_.proxyCount() || movingCount != movingTree_.proxyCount()) {
        why << "records hold " << staticCount << " static and " << movingCount << " moving proxies, trees hold "
            << staticTree_.proxyCount() << " and " << movingTree_.proxyCount();
        return why.str();
    }
    std::size_t inRuns = 0;
    for (std::size_t k = 0; k < skippedRuns_.size(); ++k) {
        const SkippedRun& s = skippedRuns_[k];
        if (s.position > moveBuffer_.size() || (k > 0 && s.position < skippedRuns_[k - 1].position)) {
            why << "skipped run " << k << " stands at " << s.position << " of a move buffer of " << moveBuffer_.size();
            return why.str();
        }
        for (std::uint32_t j = 0; j < s.count; ++j) {
            const ProxyId id = s.first + static_cast<ProxyId>(j);
            if (!isProxy(id) || !record(id).skipped) {
                why << "skipped run " << k << " names proxy " << id << " which is not skipped";
                return why.str();
            }
        }
        inRuns += s.count;
    }
    if (inRuns != skippedCount || inRuns != skippedCount_) {
        why << "skipped runs hold " << inRuns << " proxies, the records " << skippedCount << ", the count "
            << skippedCount_;
        return why.str();
    }
    for (std::size_t m = 0; m < moveBuffer_.size(); ++m) {
        const ProxyId id = moveBuffer_[m].proxy;
        if (id != kNullProxy && (!isProxy(id) || record(id).moveIndex != static_cast<std::int32_t>(m))) {
            why << "move-buffer entry " << m << " names proxy " << id << " which does not point back";
            return why.str();
        }
    }
    return {};
}

}  // namespace fulcrum
