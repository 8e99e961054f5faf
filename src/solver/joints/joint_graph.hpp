#pragma once
// Which joints each body has: per body slot, a linked list of its joints (by
// joint slot), kept as joints are created and destroyed (a body's destruction
// destroys its joints first).
//
// Why: the broad phase asks, for every new candidate pair, whether a joint
// between the two bodies keeps them from colliding (collideConnected off).
// Scanning every joint for that was ~20 % of the ragdoll pile's step
// (docs/joints.md); the lists make it O(joints of the body with fewer).
//
// A world filled by a snapshot load (which writes the joint records directly)
// starts out of sync; until JointSolver::prepare rebuilds the lists (every
// step, O(1) when in sync), the question falls back to the scan.
#include <cstdint>
#include <vector>

namespace fulcrum::detail {

struct JointData;

class JointGraph {
public:
    using Joints = std::vector<JointData>;  // WorldImpl::joints
    // After a joint was created in `jointSlot` (alive, bodies set).
    void add(const Joints& w, std::uint32_t jointSlot);
    // Before or after a joint is destroyed (its def still names its bodies).
    void remove(const Joints& w, std::uint32_t jointSlot);
    void rebuild(const Joints& w);
    bool inSync(const Joints& w) const;
    // An enabled joint without collideConnected joins the bodies in these slots.
    bool keepsApart(const Joints& w, std::uint32_t slotA, std::uint32_t slotB) const;
    // False only when the lists are in sync and name no joint of the body in
    // this slot (World::destroyBody then skips its scan of every joint slot).
    bool mayHaveJoints(const Joints& w, std::uint32_t body) const {
        return !inSync(w) || (body < degree_.size() && degree_[body] != 0);
    }

private:
    static constexpr std::uint32_t kNone = UINT32_MAX;
    void link(std::uint32_t body, std::uint32_t jointSlot, int end);
    std::uint32_t& nextOf(const Joints& w, std::uint32_t jointSlot, std::uint32_t body);
    std::vector<std::uint32_t> head_;     // per body slot: its first joint slot (kNone: none)
    std::vector<std::uint32_t> degree_;   // per body slot: how many joints
    std::vector<std::uint32_t> next_;     // per joint slot, 2 entries: the next joint on bodyA's / bodyB's list
    std::size_t jointSlots_ = 0;          // WorldImpl::joints.size() the lists describe
};

}  // namespace fulcrum::detail
