#pragma once
// The World's characters (fulcrum/character.hpp, docs/characters.md): their
// definitions and state, and the move each makes at the end of a step.
//
// Why at the end of World::step, serially, rather than as a stage of the
// sub-steps: a character moves by queries against the bodies as the step
// left them (exact poses of the platforms it rides, no lag), each character
// sees the ones moved before it (creation order, so character-vs-character
// is deterministic), and the step's parallel stages stay as they were. The
// queries and the push impulses are the same whatever the thread count, so
// the results are too. Pushes are impulses on dynamic bodies that the next
// step resolves with the rest of the contacts.
#include <cstdint>
#include <vector>

#include "collision/manifold.hpp"
#include "dynamics/slot_pool.hpp"
#include "fulcrum/character.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {
class World;
}

namespace fulcrum::detail {

struct CharacterData : PoolSlot {
    CharacterDef def;
    Real cosMaxSlope = 0;      // cos(def.maxSlope), at creation: no libm call in the step
    BodyId body;               // the capsule body (kinematic, kCharacterCategory)
    Vec3 position;             // capsule centre
    Vec3 velocity;             // own velocity (relative to the ground), vertical included
    Vec3 airVelocity;          // the ground's velocity at take-off, kept in the air
    Vec3 reportedVelocity;     // CharacterState::velocity
    GroundState ground = GroundState::InAir;
    Vec3 groundNormal;
    Vec3 groundVelocity;
    BodyId groundBody;
    Vec3 groundLocal;          // the centre in the ground body's frame at the end of the last move
    Vec3 groundPoint;          // where it touches the ground (world)
    Vec3 inputVelocity;        // held input
    bool inputJump = false;
    std::uint32_t nextInput = 0;  // the script's next entry to apply
};

// Moves a character's capsule body to `centre` as a teleport that wakes
// nothing around it (world_characters.cpp; World::setTransform would wake
// every body near it each step).
void placeCharacterBody(World& world, BodyId body, const Vec3& centre);

class CharacterSystem {
public:
    SlotPool<CharacterData, CharacterId> pool;
    std::vector<std::uint32_t> order;  // live slots in creation order

    bool empty() const { return order.empty(); }
    // Moves every character by `dt` (the step that started at world time t0).
    void update(World& world, double t0, Real dt);

private:
    // Scratch, reused so a step with characters allocates only when it grows.
    std::vector<BodyId> nearby_;
    ManifoldBuffer manifolds_;
};

}  // namespace fulcrum::detail
