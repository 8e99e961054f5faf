#pragma once
// A joint's record as the world keeps it (WorldImpl::joints): what the user
// created plus the joint solver's state between steps. Defined here, below
// the world, because the joint solver, the joint graph, the contact manager's
// pair filter and the islands read it.
#include <cstdint>
#include <vector>

#include "dynamics/slot_pool.hpp"
#include "fulcrum/world.hpp"
#include "solver/joints/joint_common.hpp"

namespace fulcrum::detail {

struct JointData : PoolSlot {  // alive, generation: WorldImpl::joints is a SlotPool
    JointDef def;                    // as created (validated; axis normalised)
    Vec3 localAnchorA, localAnchorB; // from each body's centre of mass, body axes (world point for the world)
    Vec3 localAxisA, localAxisB;     // unit axis in each body's axes (world axis for the world)
    Real minLength = 0, maxLength = 0;  // distance joints, resolved (no negative "use creation" values)
    Quat localFrameA;                // six-DOF: the joint frame in A's body axes (world axes for the world)
    // Joint solver runtime (src/solver/joint_solver.hpp).
    Quat relativeRotation;           // conj(qA) qB at creation: the rest pose angles are measured from
    Real restLength = 0;             // soft distance joints: the spring's rest length
    bool enabled = true;             // false once broken or disabled by the user
    bool broken = false;
    JointImpulses impulses;          // accumulated sub-step impulses (warm starting)
    Vec3 reactionForce, reactionTorque;  // on B, last step
};

class JointGraph;

// What the collision pipeline and the time of impact ask the joints: whether
// an enabled joint without collideConnected joins the bodies in two slots
// (joints/joint_graph.hpp).
struct JointPairFilter {
    const JointGraph* graph = nullptr;
    const std::vector<JointData>* joints = nullptr;
    bool keepsApart(std::uint32_t slotA, std::uint32_t slotB) const;
};

}  // namespace fulcrum::detail
