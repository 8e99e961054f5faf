#pragma once
// ParticleWorld: owns the particle systems (ropes, cloths, free particles) and
// advances them; the World calls step() after its rigid step, handing it a
// RigidCollider over its bodies.
//
// One step(dt) runs `substeps` sub-steps of h = dt / substeps (Macklin et al.
// 2019, "Small Steps in Physics Simulation": many sub-steps with one
// iteration each converge faster than one step with many iterations). Each
// sub-step:
//   1. forces -> accelerations (gravity, user forces, drag, springs, wind);
//   2. position Verlet prediction (particle_integration.hpp), pins placed;
//   3. `iterations` Gauss-Seidel sweeps of XPBD projection: stretch, shear,
//      bend, tethers, attachments, self-collision, rigid contacts (last, so
//      the final positions are never inside a rigid shape);
//   4. the proxies of pushed bodies advance.
// After the sub-steps the bodies receive the impulses, user forces are cleared.
//
// Broad-phase work happens once per step: one shape query per system (with a
// travel margin); self-collision re-searches its pairs only when particles
// have moved far enough to need it (self_collision.hpp). Systems are
// stepped in creation order, one thread: the result is deterministic.
#include <cstdint>
#include <memory>
#include <vector>

#include "fulcrum/particles.hpp"
#include "fulcrum/task_system.hpp"
#include "dynamics/slot_pool.hpp"
#include "particles/particle_integration.hpp"
#include "particles/particle_soa.hpp"
#include "particles/particle_system.hpp"
#include "particles/rigid_collider.hpp"
#include "particles/rigid_coupling.hpp"
#include "particles/self_collision.hpp"
#include "particles/xpbd_distance.hpp"

namespace fulcrum {

struct SnapshotAccess;  // src/world/snapshot.cpp: saves and restores private state

struct ParticleWorldSettings {
    Vec3 gravity{0, Real(-9.81), 0};
    int substeps = 16;           // >= 1 (16: a 1 m, 20-segment rope hangs within 1 %)
    int iterations = 1;          // XPBD sweeps per sub-step, >= 1
    Vec3 wind;                   // m/s: air velocity for cloth aerodynamics
    Real airDensity = Real(1.2); // kg/m^3
};

class ParticleWorld {
public:
    explicit ParticleWorld(const ParticleWorldSettings& settings = {});
    ~ParticleWorld();
    ParticleWorld(ParticleWorld&&) noexcept;
    ParticleWorld& operator=(ParticleWorld&&) noexcept;
    ParticleWorld(const ParticleWorld&) = delete;
    ParticleWorld& operator=(const ParticleWorld&) = delete;

    const ParticleWorldSettings& settings() const { return settings_; }
    void setSettings(const ParticleWorldSettings& settings);  // validated

    // Adds a system. Attachments are checked against `collider`
    // (RigidCollider::isValidBody) and their local anchors computed from the
    // bodies' current poses; a system with attachments needs a collider.
    ParticleSystemId add(ParticleSystem system, const RigidCollider* collider = nullptr);
    ParticleSystemId addRope(const RopeDef& def, const RigidCollider* collider = nullptr);
    ParticleSystemId addCloth(const ClothDef& def, const RigidCollider* collider = nullptr);
    void remove(ParticleSystemId id);
    bool isValid(ParticleSystemId id) const;
    ParticleSystem& system(ParticleSystemId id);
    const ParticleSystem& system(ParticleSystemId id) const;
    std::vector<ParticleSystemId> systems() const;  // live systems in creation order
    std::size_t systemCount() const;

    // Advances every system by dt (> 0). `collider` may be null (no rigid
    // bodies). `tasks` (may be null: this thread) runs the large loops of a
    // system (the self-collision search, the large constraint colours) in
    // parallel, with the same bits for any worker count (docs/particles.md,
    // "Threads").
    void step(Real dt, RigidCollider* collider = nullptr, TaskSystem* tasks = nullptr);
    // Sweeps run as StagedParallel stages so far (tests: the threaded path ran).
    std::uint64_t stagedSweeps() const { return stagedSweeps_; }

private:
    friend struct fulcrum::SnapshotAccess;
    struct Slot : detail::PoolSlot {
        std::unique_ptr<ParticleSystem> system;  // null when free
        std::uint64_t order = 0;                 // creation order, for deterministic stepping
        detail::SelfCollision selfCollision;
        std::vector<Vec3> accel;                 // scratch
        detail::ParticleSoA particles;           // the step's working copy of the positions
        // The system's constraint groups, coloured for SIMD (xpbd_distance.hpp).
        detail::DistanceBatches stretch, shear, bend, tethers;
        // The four groups' sweeps as the stages of one parallel run, when a
        // group has a colour large enough to split (useStages).
        detail::StagedParallel stages;
        bool useStages = false;
    };
    Slot& slotOf(ParticleSystemId id);
    const Slot& slotOf(ParticleSystemId id) const;

    ParticleWorldSettings settings_;
    detail::SlotPool<Slot, ParticleSystemId> slots_;
    std::uint64_t nextOrder_ = 0;
    detail::RigidCoupling coupling_;
    std::uint64_t stagedSweeps_ = 0;
    // Step scratch, capacity kept.
    std::vector<Slot*> active_;
    std::vector<ParticleSystem*> activeSystems_;
    std::vector<Real> travel_;
    std::vector<std::uint8_t> extraForces_;
};

}  // namespace fulcrum
