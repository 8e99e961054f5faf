#pragma once
// Two-way coupling of particles with rigid bodies: contacts (with Coulomb
// friction) against every rigid shape, and attachments of particles to bodies.
//
// Contacts are position constraints C = d(x) - r >= 0, with d the signed
// distance to the shape's surface (the shared closestPoint query) and r the
// particle radius, solved like XPBD constraints with zero compliance. Friction
// follows Macklin et al. 2014 ("Unified Particle Physics for Real-Time
// Applications", sec. 6.1): the relative tangential displacement over the
// sub-step is removed up to mu times the normal correction - Coulomb's law in
// position form.
//
// Dynamic bodies take part through a per-step "proxy": the generalised
// inverse mass w = 1/m + (r x n)^T I^-1 (r x n) at the contact point shares
// each correction between particle and body (Müller et al. 2020, "Detailed
// Rigid Body Simulation with Extended Position Based Dynamics"); the body's
// share moves the proxy (so the constraint is satisfied and not re-applied
// next sub-step) and adds to the body's velocity, exactly as PBD turns a
// particle's correction into velocity. The momentum given to the body,
// -sum(dLambda n) / h, is exactly the opposite of what the particles received;
// it is handed to the RigidCollider as one impulse per body at the end of the
// step, with the displacement the proxy took (applyDisplacement).
#include <cstdint>
#include <vector>

#include "particles/particle_soa.hpp"
#include "particles/particle_system.hpp"
#include "particles/rigid_collider.hpp"
#include "particles/shape_query_adapter.hpp"

namespace fulcrum::detail {

class RigidCoupling {
public:
    // Gathers the shapes near each system (one broad-phase query per system
    // per step) and prepares proxies of the dynamic bodies involved.
    // `systems` are the live systems in stepping order; `margin[k]` is how far
    // system k's particles may travel this step.
    void beginStep(RigidCollider& collider, const std::vector<ParticleSystem*>& systems, const std::vector<Real>& margin);
    // Contacts of system k (its step working copy `particles`) against its gathered shapes.
    void solveContacts(std::size_t k, const ParticleSystem& system, ParticleSoA& particles, Real substep);
    // Attachments of system k (two-way for dynamic bodies).
    void solveAttachments(ParticleSystem& system, ParticleSoA& particles, Real substep);
    void resetAttachmentMultipliers(ParticleSystem& system);
    // Advances the proxies by the velocity the particles gave them and places
    // the bodies on their path at the end of sub-step `index` of `count`.
    void beginSubstep(int index, int count, Real substep);
    // Hands the accumulated impulses to the bodies.
    void endStep(RigidCollider& collider);

private:
    struct Proxy {
        std::uint32_t body = 0;
        RigidBodyState base;
        bool moving = false;          // previousTransform != transform
        Vec3 localCenter;             // centre of mass in the body frame
        Transform path;               // body pose on the step's path at the current sub-step
        Vec3 deltaPosition;           // of the centre of mass, since the step began
        Quat deltaRotation;           // about the centre of mass
        Vec3 extraLinearVelocity;     // from the particles' impulses
        Vec3 extraAngularVelocity;
        Vec3 linearImpulse;           // N s, accumulated
        Vec3 angularImpulse;          // N m s about the centre of mass
    };
    struct Candidate {
        std::uint32_t body = 0;
        std::int32_t proxy = -1;      // cached body state; moves only for dynamic bodies
        bool dynamic = false;         // the body has finite mass: it is pushed back
        bool moves = false;           // dynamic or moving kinematic: transform changes during the step
        const Shape* shape = nullptr;
        Transform transform;          // of the shape at the step's start
        AABB bounds;                  // fattened by particle radius and travel
        Real friction = 0;
        std::size_t nearBegin = 0, nearEnd = 0;  // static shapes: particles near it this step (near_)
    };
    struct Range {
        std::size_t begin = 0, end = 0;
    };

    std::int32_t proxyFor(RigidCollider& collider, std::uint32_t body);
    // Where a frame given at the body's end-of-step pose is now: on the path, plus the particles' push.
    Transform moved(const Proxy& p, const Transform& base) const;
    Vec3 currentCenter(const Proxy& p) const { return transformPoint(p.path, p.localCenter) + p.deltaPosition; }
    Real inverseMassAt(const Proxy& p, const Vec3& point, const Vec3& direction) const;
    void applyCorrection(Proxy& p, const Vec3& positionalImpulse, const Vec3& point, Real substep);
    void solveContact(const Candidate& c, Proxy& proxy, const SurfacePoint& q, Real mu, ParticleSoA& particles,
                      std::size_t i, Real radius, Real substep);

    friend class CandidateGatherer;
    std::vector<Proxy> proxies_;
    std::vector<std::int32_t> proxyOfBody_;  // body index -> proxy slot, -1 when none
    std::vector<Candidate> candidates_;
    std::vector<Range> ranges_;              // per system
    std::vector<std::uint32_t> near_;        // particle lists of the static candidates
};

}  // namespace fulcrum::detail
