#pragma once
// ContactManager: the collision pipeline of the World (broad phase -> contacts
// -> narrow phase -> events), the first half of the step.
//
// Each body owns one broad-phase proxy (static bodies in the static tree). At
// the start of a step every awake, non-static body moves its proxy to its tight
// box, fattened by its displacement over the step (v dt) so the pairs of the
// coming motion already exist. New pairs, in the broad phase's deterministic
// order, become Contacts after the filters (CollisionFilter, sensor-sensor,
// and the joint rule: bodies joined by a joint without collideConnected don't
// collide). A contact ends when the fat boxes stop overlapping. At most
// WorldDef::maxContactPairs contacts live (contactPairLimit below): the broad
// phase reports no more new pairs than there is room for and keeps the
// bodies whose pairs wait (docs/solver.md, "Contact pair limit").
//
// Each contact with at least one awake body runs collide() with a speculative
// margin of `WorldDef::speculativeMargin` plus the pair's possible approach
// over one step (relative speed + spin times extent, times dt; a spinning
// compound's children each with their own distance from the centre of mass:
// SpeculativeReach), so a fast body gets its speculative points a step before
// it arrives. New manifold points
// take the accumulated impulses of the old points with the same feature id
// (manifolds are matched by their child ids) for warm starting.
//
// "Touching" (events, islands, reports) means a point within kTouchSlop of
// contact: the soft solver rests bodies a fraction of a millimetre apart or
// into each other, and a strict depth > 0 would flicker between frames.
// A touching manifold with a sleeping body wakes the sleeping body's island.
//
// Sleeping costs nothing (docs/solver.md, "Sleeping"): update() moves the
// proxies of the awake bodies only (BodyStore::awakeBodies) and visits only
// the contacts that can change: those of an awake body (each body keeps a
// doubly linked list of its contacts, as Box2D's contact edges) and those
// created this step, gathered through a bitmap so they come out in ascending
// contact order, the order the full pass used. A contact whose bodies are both
// asleep or static has nothing to do: neither proxy moved, so its fat boxes
// still overlap and its manifolds still hold. (A static body teleported by
// setTransform moves its proxy without waking anything: the next update then
// visits every contact once.) report() is not called by the step: the world
// builds the report when it is read (WorldImpl::ensureContactReport).
//
// Its contract is the body store (dynamics/body_store.hpp), the collision
// settings, the joints' pair filter and the task system, all passed in: it
// wakes bodies through the store's wake queue (BodyStore::wakeBody).
//
// Threads (docs/threading.md): update() computes tight boxes, runs the broad
// phase's queries and collides the contacts as parallelFor calls on
// the task system; each contact writes only itself and its flag byte, and the
// destructions, wakes and events are applied afterwards in contact order, so
// the result is the same for any thread count. report() fills the reports in
// parallel at offsets from a prefix sum.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/manifold.hpp"
#include "collision/narrow_phase.hpp"
#include "fulcrum/world.hpp"
#include "contacts/contact.hpp"
#include "dynamics/body_store.hpp"
#include "fulcrum/task_system.hpp"

namespace fulcrum {
struct SnapshotAccess;  // src/world/snapshot.cpp: saves and restores private state
}

namespace fulcrum::detail {

struct JointPairFilter;  // solver/joint_data.hpp: which pairs joints keep apart

inline constexpr Real kTouchSlop = Real(0.005);

// The contact pair limit in effect for `bodyCount` bodies
// (WorldDef::maxContactPairs, 0: automatic; docs/solver.md, "Contact pair
// limit"). Its largest value, kMaxContactPairs, keeps the contact list keys
// (index * 2 + end) below UINT32_MAX, which means "none".
inline std::uint32_t contactPairLimit(std::int64_t maxContactPairs, std::size_t bodyCount) {
    const std::int64_t limit =
        maxContactPairs > 0 ? maxContactPairs
                            : kAutoContactPairsBase + kAutoContactPairsPerBody * static_cast<std::int64_t>(bodyCount);
    return static_cast<std::uint32_t>(std::min(limit, kMaxContactPairs));
}

// The joint rule and the sensor-sensor rule for two bodies (by slot).
bool mayCollide(const BodyStore& w, const JointPairFilter& joints, std::uint32_t slotA, std::uint32_t slotB);

// The apart cache's motion bound (docs/narrow-phase.md, "Pairs proved apart"):
// how far any point of B can have moved in A's frame between the relative
// poses `from` and `to` (B's body frame in A's) when B's reach is the smaller,
// else any point of A in B's frame; `reachA` and `reachB` bound the shapes'
// distances from their body origins. The distance between the shapes shrank
// by at most that.
Real apartMotionBound(const Transform& from, const Transform& to, Real reachA, Real reachB);

// The settings the collision pipeline reads.
struct CollisionSettings {
    Real speculativeMargin = Real(0.02);
    std::int64_t maxContactPairs = 0;
};

class ContactManager {
public:
    // Body lifetime (called by World::createBody / destroyBody / setTransform).
    void addBody(BodyStore& w, std::uint32_t dense);
    // Capacity for `slots` body slots and `bodies` bodies (World::reserveBodies).
    void reserveBodies(std::size_t slots, std::size_t bodies) {
        proxyOfSlot_.reserve(slots);
        headOfSlot_.reserve(slots);
        broad_.reserveProxies(bodies);
    }
    // Before the dense arrays are changed, after the world built the last step's contact report.
    void removeBody(BodyStore& w, std::uint32_t slot);
    void bodyTeleported(BodyStore& w, std::uint32_t dense);
    // Grows every per-step buffer for `bodyCount` bodies (about 4 contacts and
    // 2 reports per body), at body creation, so steps don't allocate.
    void reserve(std::size_t bodyCount, std::int64_t maxContactPairs, std::vector<ContactReport>& reports);
    // The body count to size the per-contact and per-awake-body buffers for
    // (reserve above, the contact solver's, the islands'): the moving bodies,
    // plus as many static ones at most. A contact needs a moving body, so a
    // world of a million static bodies and a hundred spheres needs no million
    // contacts: reserving for every body made Box3D's large_world take 3 GB
    // (4 pooled contacts and 2 reports with their point buffers per body).
    std::size_t bufferBodyCount() const {
        const auto moving = static_cast<std::size_t>(broad_.movingTree().proxyCount());
        const auto fixed = static_cast<std::size_t>(broad_.staticProxyCount());
        return moving + std::min(fixed, moving);
    }
    // Drops the body's contacts and reports all its overlaps anew next step
    // (a joint that changes which partners it may collide with). Like
    // removeBody, after the world built the last step's contact report.
    void resetPairs(BodyStore& w, std::uint32_t slot);
    // Every live contact's material mixed from its bodies' (as collideContact
    // does): for a snapshot written before the contacts held it.
    void mixMaterials(const BodyStore& w);

    // Broad phase + narrow phase + events. Clears the previous step's events.
    void update(BodyStore& w, const CollisionSettings& settings, const JointPairFilter& joints, TaskSystem& tasks, Real dt);
    // Fills out[0, count) with the touching manifolds (after the solver stored its results).
    // The forces are the stored step impulses over `dt` (the last step's).
    void report(const BodyStore& w, std::vector<ContactReport>& out, std::size_t& count, Real dt, TaskSystem& tasks) const;
    // The impacts of the last step (World::contactHitEvents) among `solved`,
    // the solver's constraints of that step (ContactSolver::pairs), in their
    // order: each manifold whose fastest-approaching point that pushed
    // approached faster than `threshold`. Clears `out` first.
    template <class Pairs>
    void hitEvents(const BodyStore& w, const Pairs& solved, Real threshold, std::vector<ContactHitEvent>& out) const {
        out.clear();
        for (const auto& pc : solved) {
            if (pc.contact >= contacts_.size()) continue;
            const Contact& c = contacts_[pc.contact];
            // A pair dropped since (a joint's or a destroyed body's) has no manifold left.
            if (!c.alive || c.sensor || pc.manifold >= c.manifolds.size()) continue;
            appendHitEvent(w, c, c.manifolds[pc.manifold], threshold, out);
        }
    }

    ContactArray& contacts() { return contacts_; }
    const ContactArray& contacts() const { return contacts_; }
    // Piece recycling against a static mesh (contact.hpp, PiecePose): on
    // unless a test turns it off (then every piece runs the narrow phase,
    // as before it existed), and how many pieces it has recycled.
    void setPieceRecycling(bool on) { pieceRecycling_ = on; }
    // The live-contact list of contactsOfAwakeBodies with most bodies awake:
    // on unless a test turns it off (then the solver's prepare walks every
    // contact slot, as before it existed).
    void setLiveContactList(bool on) { liveContactList_ = on; }
    // One bit per contact slot: the contact may hold manifolds. A superset:
    // set by update() for every contact it leaves with manifolds (and by
    // rebuildLinks for the live ones), cleared only by the solver's prepare
    // when it finds a slot without manifolds (clearMayHaveManifolds). A
    // clear bit means no manifolds and Contact::grownBy 0, so that pass
    // skips the contact without reading it (the same list). Null while the
    // contact lists are not built, or when a test turned it off
    // (setManifoldBits(false): the prepare then reads every contact).
    std::uint64_t* mayHaveManifoldBits() {
        return manifoldBitsOn_ && !linksRebuild_ && 64 * mayHaveManifolds_.size() > contacts_.size() ? mayHaveManifolds_.data()
                                                                                                       : nullptr;
    }
    void setManifoldBits(bool on) { manifoldBitsOn_ = on; }
    std::uint64_t recycledPieceCount() const;
    const BroadPhase& broadPhase() const { return broad_; }
    ProxyId proxyOfSlot(std::uint32_t slot) const { return proxyOfSlot_[slot]; }
    // The live contacts of the bodies w.awakeBodies lists, ascending, into
    // `out`, when that is cheaper than every contact: fewer than half the
    // bodies awake, and the per-body contact lists built (else false, `out`
    // untouched). Every contact the solver works on has an awake body, so
    // this is the contact solver's candidate list (prepareConstraintList):
    // a world that sleeps then costs nothing per contact. With most bodies
    // awake, every live contact (the alive bitmap) when they are fewer than
    // half the contact slots: a superset of the awake bodies' contacts, the
    // rest of which give no constraint.
    bool contactsOfAwakeBodies(const BodyStore& w, std::vector<std::uint32_t>& out);
    // Contacts the last update() visited (tests: a sleeping world visits none).
    std::size_t visitedContactCount() const { return activeContacts_.size() + newContacts_.size(); }
    // Live contacts (pairs), the limit the last update() worked under, and
    // what it left for later because of that limit (BroadPhase::lastUpdate).
    std::uint32_t liveContactCount() const { return liveContacts_; }
    std::uint32_t lastPairLimit() const { return lastPairLimit_; }
    const PairUpdateStats& lastPairStats() const { return broad_.lastUpdate(); }
    // Read-only views of the per-body contact lists and the free list, for
    // the FULCRUM_VALIDATE checks (src/world/invariants.cpp). A key is
    // contact * 2 + end (0: the contact's slotA, 1: its slotB), UINT32_MAX
    // at a list's end. The lists exist only once built (contactListsBuilt).
    bool contactListsBuilt() const { return !linksRebuild_; }
    // Forget the lists until the next update (or joint) rebuilds them, as a
    // new manager starts: removeBody then scans every contact
    // (tests/world/destroy_lists_test.cpp compares the two paths).
    void dropContactLists() { linksRebuild_ = true; }
    std::size_t contactListCount() const { return headOfSlot_.size(); }  // one per body slot
    std::uint32_t firstContactKey(std::uint32_t slot) const { return headOfSlot_[slot]; }
    std::uint32_t nextContactKey(std::uint32_t key) const { return links_[key >> 1].next[key & 1]; }
    std::uint32_t previousContactKey(std::uint32_t key) const { return links_[key >> 1].prev[key & 1]; }
    std::uint32_t firstFreeContact() const { return freeContact_; }  // then Contact::nextFree

    std::vector<ContactEvent> beginEvents, endEvents, sensorBeginEvents, sensorEndEvents;

private:
    static void appendHitEvent(const BodyStore& w, const Contact& c, const CachedManifold& m, Real threshold,
                               std::vector<ContactHitEvent>& out);
    friend struct fulcrum::SnapshotAccess;
    // Returns the new contact's index.
    std::uint32_t createContact(BodyStore& w, std::uint32_t slotA, std::uint32_t slotB, ProxyId proxyA, ProxyId proxyB);
    void destroyContact(BodyStore& w, std::uint32_t index);
    // Per-worker narrow-phase scratch (threads: docs/threading.md).
    struct alignas(64) NarrowScratch {
        ManifoldBuffer buffer;
        std::vector<CachedManifold> manifolds;
        std::vector<TriangleAxisEntry> triangleAxes;  // a contact's new triangle axis cache, copied back to it
        // Piece recycling against a mesh (PiecePose): the pieces the narrow
        // phase skips, their recycled manifolds, the contact's new poses.
        std::vector<std::uint8_t> skip;
        std::vector<std::uint8_t> near;  // the pieces the narrow phase looks at
        std::vector<ChildReach> children;  // a compound piece body's children when the pool has none
        std::vector<CachedManifold> recycled;
        std::vector<PiecePose> piecePoses;
        std::uint64_t recycledPieces = 0;  // pieces recycled by this worker (recycledPieceCount)
    };
    // Where an awake compound body's top-level children are in childPool_:
    // valid when `update` is this update's updateCount_ (else none: the
    // narrow phase computes them per pair).
    struct ChildrenRef {
        std::uint32_t update = 0;
        std::uint32_t offset = 0;
    };
    // The body's children at this update's pose, or null.
    const ChildReach* knownChildren(std::uint32_t dense) const {
        if (dense >= childrenOfDense_.size()) return nullptr;
        const ChildrenRef& r = childrenOfDense_[dense];
        return r.update == updateCount_ ? childPool_.data() + r.offset : nullptr;
    }
    // Runs on any worker: reads the world, writes only c and scratch; returns
    // kTouching / kWakeA / kWakeB flags that update() applies in index order.
    std::uint8_t collideContact(const BodyStore& w, Contact& c, Real dt, NarrowScratch& scratch) const;
    // Cache hints for a contact update()'s loop reaches soon (contact_manager.cpp).
    void prefetchRecords(const BodyStore& w, const Contact& c) const;
    bool recordPieces(Contact& c, NarrowScratch& ns, bool meshIsA, const Shape& pieceShape, const Transform& toPiece,
                      const SpeculativeReach& reach, const ChildReach* pieceChildren) const;
    std::uint8_t collideSpheres(const BodyStore& w, Contact& c, std::uint32_t dA, std::uint32_t dB, Real margin) const;
    void ensureWorkers(std::size_t workers);
    void updateTouching(BodyStore& w, Contact& c, bool touching);
    // Per-body contact lists (slot-indexed heads, links parallel to contacts_).
    void linkContact(std::uint32_t index);
    void unlinkContact(std::uint32_t index);
    void rebuildLinks();
    void markContact(std::uint32_t index) { marks_[index >> 6] |= std::uint64_t(1) << (index & 63); }
    // aliveBits_ follows alive with the links (kept by create/destroy, rebuilt by rebuildLinks).
    void setAliveBit(std::uint32_t index, bool alive) {
        const std::uint64_t bit = std::uint64_t(1) << (index & 63);
        aliveBits_[index >> 6] = alive ? (aliveBits_[index >> 6] | bit) : (aliveBits_[index >> 6] & ~bit);
    }
    // The existing contacts update() must visit, ascending, into activeContacts_.
    void gatherActiveContacts(const BodyStore& w);
    // Marks the contacts of the awake bodies (their per-body lists) in `marks`,
    // then appends every live marked contact to `out`, ascending, and clears
    // `marks` (gatherActiveContacts with marks_, contactsOfAwakeBodies with awakeMarks_).
    void collectAwakeContacts(const BodyStore& w, std::vector<std::uint64_t>& marks, std::vector<std::uint32_t>& out) const;
    // The broad phase's `partners`: the other proxy of each contact of a
    // proxy's body (its list; read-only, so any thread may walk it).
    struct KnownPartners {
        const ContactManager* manager;
        template <typename Visit>
        void operator()(ProxyId proxy, Visit&& visit) const {
            const ContactManager& m = *manager;
            const std::uint32_t slot = m.broad_.userValue(proxy);
            for (std::uint32_t key = m.headOfSlot_[slot]; key != UINT32_MAX;) {
                const std::uint32_t i = key >> 1;
                const Contact& c = m.contacts_[i];
                visit((key & 1) == 0 ? c.proxyB : c.proxyA);
                key = m.links_[i].next[key & 1];
            }
        }
    };
    // [0]: the contact's place in slotA's list, [1]: in slotB's. Entries are
    // keys (contact * 2 + end), UINT32_MAX at the list's ends.
    struct ContactLinks {
        std::uint32_t prev[2] = {UINT32_MAX, UINT32_MAX};
        std::uint32_t next[2] = {UINT32_MAX, UINT32_MAX};
    };

    BroadPhase broad_;
    LargeArray<ProxyId> proxyOfSlot_;
    ContactArray contacts_;
    std::uint32_t freeContact_ = UINT32_MAX;
    std::uint32_t liveContacts_ = 0;          // alive entries of contacts_ (kept by create/destroy, counted by rebuildLinks)
    std::uint32_t lastPairLimit_ = 0;         // contactPairLimit of the last update()
    bool pieceRecycling_ = true;              // setPieceRecycling
    bool liveContactList_ = true;             // setLiveContactList
    bool manifoldBitsOn_ = true;              // setManifoldBits
    Real speculativeMargin_ = 0;              // update()'s CollisionSettings, for the narrow phase
    std::vector<NarrowScratch> narrow_;       // one per worker
    // The awake compound bodies' top-level children at this update's pose,
    // bounded once in update()'s step 1 for all of the body's pairs (a
    // spinning drum of 40 hulls met by 8000 bodies bounded each child per
    // pair: a third of Box3D's washer). Grows only.
    std::vector<ChildReach> childPool_;
    LargeArray<ChildrenRef> childrenOfDense_;  // per dense body: its entries in childPool_
    std::uint32_t updateCount_ = 0;           // update()s so far (ChildrenRef::update)
    std::vector<std::uint8_t> contactFlags_;  // per contact: what the parallel pass found
    std::vector<std::uint64_t> flaggedWords_;  // per 64 active contacts: which have a flag (set atomically)
    mutable std::vector<std::uint32_t> reportStart_;  // per contact: its first report (report())
    std::vector<ContactLinks> links_;         // per contact
    LargeArray<std::uint32_t> headOfSlot_;   // per body slot: its first contact's key (UINT32_MAX: none)
    std::vector<std::uint64_t> marks_;        // one bit per contact: visit in this update
    std::vector<std::uint64_t> awakeMarks_;   // one bit per contact: contactsOfAwakeBodies' scratch (all zero between calls)
    std::vector<std::uint64_t> aliveBits_;    // one bit per contact: alive (valid when !linksRebuild_)
    std::vector<std::uint64_t> mayHaveManifolds_;  // one bit per contact: mayHaveManifoldBits (valid when !linksRebuild_)
    std::vector<std::uint8_t> proxyMoves_;    // per awake body: its tight box left its fat box (update())
    std::vector<AABB> movedFrom_;             // per awake body that moved: its fat box before (update())
    std::vector<std::uint32_t> activeContacts_;  // this update's contacts to visit, ascending (made before it)
    std::vector<std::uint32_t> newContacts_;     // the contacts this update made, ascending
    std::vector<std::uint32_t> resetScratch_;    // resetPairs, removeBody: the body's contacts, ascending
    bool linksRebuild_ = true;                // links_/headOfSlot_ not built (new manager, snapshot)
    bool visitAll_ = true;                    // the next update visits every contact
};

}  // namespace fulcrum::detail
