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
// collide). A contact ends when the fat boxes stop overlapping.
//
// Each contact with at least one awake body runs collide() with a speculative
// margin of `WorldDef::speculativeMargin` plus the pair's possible approach
// over one step (relative speed + spin times extent, times dt), so a fast body
// gets its speculative points a step before it arrives. New manifold points
// take the accumulated impulses of the old points with the same feature id
// (manifolds are matched by their child ids) for warm starting.
//
// "Touching" (events, islands, reports) means a point within kTouchSlop of
// contact: the soft solver rests bodies a fraction of a millimetre apart or
// into each other, and a strict depth > 0 would flicker between frames.
// A touching manifold with a sleeping body wakes the sleeping body's island.
//
// Threads (docs/threading.md): update() computes tight boxes, runs the broad
// phase's queries and collides the contacts as parallelFor calls on
// w.taskSystem(); each contact writes only itself and its flag byte, and the
// destructions, wakes and events are applied afterwards in contact order, so
// the result is the same for any thread count. report() fills the reports in
// parallel at offsets from a prefix sum.
#include <cstdint>
#include <span>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/manifold.hpp"
#include "fulcrum/world.hpp"
#include "solver/contact.hpp"

namespace fulcrum {
struct WorldImpl;
struct SnapshotAccess;  // src/world/snapshot.cpp: saves and restores private state
}

namespace fulcrum::detail {

inline constexpr Real kTouchSlop = Real(0.005);

// The joint rule and the sensor-sensor rule for two bodies (by slot).
bool mayCollide(const WorldImpl& w, std::uint32_t slotA, std::uint32_t slotB);

class ContactManager {
public:
    // Body lifetime (called by World::createBody / destroyBody / setTransform).
    void addBody(WorldImpl& w, std::uint32_t dense);
    void removeBody(WorldImpl& w, std::uint32_t slot);  // before the dense arrays are changed
    void bodyTeleported(WorldImpl& w, std::uint32_t dense);
    // Grows every per-step buffer for `bodyCount` bodies (about 4 contacts and
    // 2 reports per body), at body creation, so steps don't allocate.
    void reserve(WorldImpl& w, std::size_t bodyCount);
    // Drops the body's contacts and reports all its overlaps anew next step
    // (a joint that changes which partners it may collide with).
    void resetPairs(WorldImpl& w, std::uint32_t slot);

    // Broad phase + narrow phase + events. Clears the previous step's events.
    void update(WorldImpl& w, Real dt);
    // Fills w.contacts with the touching manifolds (after the solver stored its results).
    void report(WorldImpl& w) const;

    std::vector<Contact>& contacts() { return contacts_; }
    const std::vector<Contact>& contacts() const { return contacts_; }
    const BroadPhase& broadPhase() const { return broad_; }
    ProxyId proxyOfSlot(std::uint32_t slot) const { return proxyOfSlot_[slot]; }

    std::vector<ContactEvent> beginEvents, endEvents, sensorBeginEvents, sensorEndEvents;

private:
    friend struct fulcrum::SnapshotAccess;
    void createContact(WorldImpl& w, std::uint32_t slotA, std::uint32_t slotB, ProxyId proxyA, ProxyId proxyB);
    void destroyContact(WorldImpl& w, std::uint32_t index);
    // Per-worker narrow-phase scratch (threads: docs/threading.md).
    struct alignas(64) NarrowScratch {
        ManifoldBuffer buffer;
        std::vector<CachedManifold> manifolds;
    };
    // Runs on any worker: reads the world, writes only c and scratch; returns
    // kTouching / kWakeA / kWakeB flags that update() applies in index order.
    std::uint8_t collideContact(const WorldImpl& w, Contact& c, Real dt, NarrowScratch& scratch) const;
    void ensureWorkers(std::size_t workers);
    void updateTouching(WorldImpl& w, Contact& c, bool touching);

    BroadPhase broad_;
    std::vector<ProxyId> proxyOfSlot_;
    std::vector<Contact> contacts_;
    std::uint32_t freeContact_ = UINT32_MAX;
    std::vector<NarrowScratch> narrow_;       // one per worker
    std::vector<AABB> tightBoxes_;            // per dense body, computed in parallel
    std::vector<std::uint8_t> contactFlags_;  // per contact: what the parallel pass found
    mutable std::vector<std::uint32_t> reportStart_;  // per contact: its first report (report())
};

}  // namespace fulcrum::detail
