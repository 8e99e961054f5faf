#pragma once
// StrayBodies: the bodies whose current shape bounds have left their
// broad-phase proxy, so that world queries between steps stay exact.
//
// Why: the contact manager moves each awake body's proxy at the *start* of a
// step, to the tight box fattened by a margin and by the coming motion (v dt).
// The solver, restitution, continuous collision and particle coupling then
// move the body, so after the step a body that bounced, was pushed sideways
// or fell asleep mid-step may sit partly outside its fat box (measured in
// tests/queries/overlap_test.cpp: a ball hitting the ground at 10 m/s with
// restitution 0.9 is outside its box after 13 of 30 steps, by up to 9.4 cm).
// A query that
// trusted the trees would miss it. Box2D v3 avoids this by moving proxies
// after the solve; here the contact pipeline is not the query's to change, so
// the queries ask the trees for everything else and test the few stray
// bodies one by one.
//
// The list is rebuilt lazily by the first query after a step (one pass over
// the non-static bodies: Shape::bounds and a containment test each) and kept
// until the next step. It stays a safe over-approximation between steps:
// setTransform moves the proxy so the body is inside it again, a new body's
// proxy is its tight box, and a slot freed (or reused by a new body) is at
// worst tested by hand as well. Anything else that moves bodies outside
// World::step (a snapshot restore, say) must call invalidate().
//
// Thread safety: const queries may run concurrently; the rebuild is guarded
// by a mutex and published by an atomic stamp (stepCount + 1), after which
// the lists are only read until the next (non-const) step.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

namespace fulcrum {
struct WorldImpl;
}

namespace fulcrum::detail {

class StrayBodies {
public:
    StrayBodies() = default;
    // A copy (of a whole WorldImpl) starts empty and is rebuilt on first use.
    StrayBodies(const StrayBodies&) {}
    StrayBodies& operator=(const StrayBodies&) {
        invalidate();
        return *this;
    }

    void invalidate() { stamp_.store(0, std::memory_order_release); }

    // Makes the list current for w's step count (cheap when it already is).
    void refresh(const WorldImpl& w) const;

    // Slots of the bodies to test by hand (some may since have been freed).
    std::span<const std::uint32_t> slots() const { return slots_; }
    // Whether the broad phase's answer for this slot is to be ignored (the
    // slot is tested by hand instead, so it is never reported twice).
    bool isStray(std::uint32_t slot) const { return slot < flags_.size() && flags_[slot] != 0; }

private:
    mutable std::mutex mutex_;
    mutable std::atomic<std::uint64_t> stamp_{0};  // stepCount + 1 the lists were built for; 0: never
    mutable std::vector<std::uint32_t> slots_;
    mutable std::vector<std::uint8_t> flags_;      // by slot
};

}  // namespace fulcrum::detail
