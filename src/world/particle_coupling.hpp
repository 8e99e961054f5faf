#pragma once
// The World's particle systems: a ParticleWorld (src/particles) inside
// WorldImpl, and the RigidCollider through which the particles see and push
// the World's bodies.
//
// Body indices
// ------------
// The particle module names bodies by a plain uint32 "body index". Here it is
// the body's *slot* (BodyId::index): slots never move, while dense indices
// change when another body is destroyed (swap-remove). A slot is reused with a
// new generation after its body dies, so an index alone could alias a new
// body; that cannot happen because World::destroyBody calls
// detachParticlesFromBody first, which removes every attachment to the slot.
// Contacts need no such care: shapes are gathered afresh every step.
//
// When the particles step (see step.cpp)
// --------------------------------------
// After the rigid sub-steps, continuous collision included, and before
// islands/sleeping. The particle module's timing contract
// (src/particles/rigid_collider.hpp) is exactly that: bodies move along the
// path from their pose at the step's start to their pose now while the
// particles take their own sub-steps, pushed in proportion to their
// generalised inverse mass; at the end they receive the impulse and the
// displacement. Interleaving the particle sub-steps with the rigid sub-steps
// would tie the cloth's sub-step count to the rigid solver's (4 by default,
// while a stiff cloth wants 16) and put particle work inside the rigid
// solver's hot loop; the price of stepping after is that the rigid contact
// solver sees the particles' push one step late (explicit coupling), which
// the proxy's mass on the particle side keeps stable. Sleeping runs after the
// particles, so it judges the velocities the particles left.
//
// Sleeping bodies: the particles see them with their real mass. A push big
// enough to change the velocity by more than the sleep thresholds wakes the
// body's island; a smaller one (a cloth lying on a sleeping box) is dropped,
// so resting cloth does not keep bodies awake. The particles then lose that
// small momentum: the one place where momentum is not exchanged exactly.
#include <cstdint>
#include <vector>

#include "particles/particle_world.hpp"
#include "particles/rigid_collider.hpp"

namespace fulcrum {

struct WorldImpl;

namespace detail {

// The RigidCollider over a WorldImpl's bodies and broad phase. A tiny view
// (one pointer), made on the stack whenever the particles need it.
class WorldRigidCollider final : public RigidCollider {
public:
    explicit WorldRigidCollider(WorldImpl& world) : w_(&world) {}

    bool isValidBody(std::uint32_t slot) const override;
    RigidBodyState bodyState(std::uint32_t slot) const override;
    // Both broad-phase trees (fat boxes), then the tight bounds of the body's
    // shape over the step's path; sensors are skipped (they never push).
    void queryShapes(const AABB& bounds, RigidShapeVisitor& visitor) const override;
    void applyImpulse(std::uint32_t slot, const Vec3& linearImpulse, const Vec3& angularImpulse) override;
    void applyDisplacement(std::uint32_t slot, const Vec3& translation, const Quat& rotation) override;

private:
    WorldImpl* w_;
};

// What WorldImpl holds for particles.
struct WorldParticles {
    ParticleWorld world;
    std::vector<ParticleSystemId> live;  // creation order; iterated without allocating
};

// Advances the particle systems by dt with the World's gravity (no-op without systems).
void stepParticles(WorldImpl& w, Real dt);
// Removes every attachment to the body in `slot` (the particle it held goes free).
void detachParticlesFromBody(WorldImpl& w, std::uint32_t slot);
// Particle contributions to World::energy / linearMomentum / angularMomentum (double sums).
void addParticleEnergy(const WorldImpl& w, double& kinetic, double& potential);
void addParticleMomentum(const WorldImpl& w, double linear[3], double angular[3]);

}  // namespace detail
}  // namespace fulcrum
