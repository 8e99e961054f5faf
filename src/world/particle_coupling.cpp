// The World side of particle-rigid coupling: the RigidCollider over the
// World's bodies and broad phase, the per-step call, detaching from destroyed
// bodies, and the particles' share of the energy and momentum diagnostics.
// Why it is shaped like this: world/particle_coupling.hpp.
#include "world/particle_coupling.hpp"

#include <cmath>

#include "particles/particle_metrics.hpp"
#include "dynamics/validation.hpp"
#include "world/world_impl.hpp"

namespace fulcrum::detail {

// ---------------------------------------------------------------- WorldRigidCollider

bool WorldRigidCollider::isValidBody(std::uint32_t slot) const {
    return slot < w_->bodySlots.size() && w_->bodySlots[slot].dense != kNoIndex;
}

RigidBodyState WorldRigidCollider::bodyState(std::uint32_t slot) const {
    const std::uint32_t d = w_->bodySlots[slot].dense;
    const BodyMotion& m = w_->motion[d];
    const BodyParams& p = w_->params[d];
    RigidBodyState s;
    s.transform = w_->originTransform(d);
    s.previousTransform = w_->previous[d];
    s.centerOfMass = m.com;
    s.linearVelocity = m.v;
    s.angularVelocity = m.w;
    // Kinematic and static bodies have invMass 0 already: particles cannot push them.
    s.inverseMass = p.type == BodyType::Dynamic ? m.invMass : 0;
    s.inverseInertia = p.type == BodyType::Dynamic ? m.invInertiaWorld : Mat3::zero();
    s.friction = p.friction;
    return s;
}

void WorldRigidCollider::queryShapes(const AABB& bounds, RigidShapeVisitor& visitor) const {
    WorldImpl& w = *w_;
    // The broad phase visits the moving tree, then the static tree, each in its
    // (deterministic) node order; no allocation (the trees query with a fixed stack).
    w.contactManager.broadPhase().query(bounds, [&](std::int32_t, std::uint32_t slot) {
        const std::uint32_t d = w.bodySlots[slot].dense;
        if (d == kNoIndex || w.params[d].isSensor) return true;
        const Shape& shape = w.cold[d].shape;
        const Transform now = w.originTransform(d);
        // Fat boxes are loose (margin, predicted motion): keep only shapes whose
        // tight bounds over the step's path reach the particles.
        AABB tight = shape.bounds(now);
        if (!(w.previous[d] == now)) tight.grow(shape.bounds(w.previous[d]));
        if (overlaps(tight, bounds)) visitor.visit(slot, shape, now);
        return true;
    });
}

void WorldRigidCollider::applyImpulse(std::uint32_t slot, const Vec3& linearImpulse, const Vec3& angularImpulse) {
    WorldImpl& w = *w_;
    const std::uint32_t d = w.bodySlots[slot].dense;
    BodyParams& p = w.params[d];
    if (p.type != BodyType::Dynamic) return;
    BodyMotion& m = w.motion[d];
    const Vec3 dv = linearImpulse * m.invMass;
    const Vec3 dw = m.invInertiaWorld * angularImpulse;
    if (!p.awake) {
        // A push below the sleep thresholds (a cloth resting on a sleeping box)
        // does not wake it and is dropped; a real one wakes the island.
        if (length(dv) <= w.settings.linearSleepVelocity && length(dw) <= w.settings.angularSleepVelocity) return;
        w.wakeBody(d);
    }
    m.v += dv;
    m.w += dw;
}

void WorldRigidCollider::applyDisplacement(std::uint32_t slot, const Vec3& translation, const Quat& rotation) {
    WorldImpl& w = *w_;
    const std::uint32_t d = w.bodySlots[slot].dense;
    if (w.params[d].type != BodyType::Dynamic || !w.params[d].awake) return;  // asleep: the impulse was dropped too
    BodyMotion& m = w.motion[d];
    m.com += translation;
    m.q = normalize(rotation * m.q);
    w.updateWorldInertia(d);
}

// ---------------------------------------------------------------- the step

namespace {

// Throws NumericalError naming the first particle whose position is not finite.
void checkFinite(const WorldImpl& w) {
    const ParticleWorld& pw = w.particles.world;
    for (const ParticleSystemId id : w.particles.live) {
        const ParticleSystem& s = pw.system(id);
        for (std::size_t i = 0; i < s.particleCount(); ++i) {
            if (isFinite(s.position[i])) continue;
            throw NumericalError(particleSystemLabel(toString(s.kind), s.name) + " particle " + std::to_string(i) +
                                 ": position became NaN/inf at step " + std::to_string(w.stepCount + 1));
        }
    }
}

}  // namespace

void stepParticles(WorldImpl& w, Real dt) {
    ParticleWorld& pw = w.particles.world;
    if (pw.systemCount() == 0) return;
    if (!(pw.settings().gravity == w.settings.gravity)) {
        ParticleWorldSettings s = pw.settings();
        s.gravity = w.settings.gravity;
        pw.setSettings(s);
    }
    WorldRigidCollider collider(w);
    // The task system: the step's, unless the rigid bodies were too few for
    // the pool (WorldDef::parallelMinBodies) but the particles are not.
    std::size_t particles = 0;
    for (const ParticleSystemId id : w.particles.live) particles += pw.system(id).particleCount();
    const bool onCaller = w.stepOnCaller;
    if (particles >= w.settings.parallelMinBodies) w.stepOnCaller = false;
    TaskSystem& tasks = w.taskSystem();
    w.stepOnCaller = onCaller;
    pw.step(dt, &collider, &tasks);
    checkFinite(w);
}

void detachParticlesFromBody(WorldImpl& w, std::uint32_t slot) {
    ParticleWorld& pw = w.particles.world;
    if (pw.systemCount() == 0) return;
    for (const ParticleSystemId id : w.particles.live) {
        std::vector<ParticleAttachment>& a = pw.system(id).attachments;
        std::erase_if(a, [slot](const ParticleAttachment& at) { return at.body == slot; });
    }
}

// ---------------------------------------------------------------- diagnostics

void addParticleEnergy(const WorldImpl& w, double& kinetic, double& potential) {
    const ParticleWorld& pw = w.particles.world;
    if (pw.systemCount() == 0) return;
    for (const ParticleSystemId id : w.particles.live) {
        const ParticleEnergy e = energy(pw.system(id), w.settings.gravity);
        kinetic += e.kinetic;
        potential += e.potential + e.elastic;
    }
}

void addParticleMomentum(const WorldImpl& w, double linear[3], double angular[3]) {
    const ParticleWorld& pw = w.particles.world;
    if (pw.systemCount() == 0) return;
    for (const ParticleSystemId id : w.particles.live) {
        const ParticleSystem& s = pw.system(id);
        if (!(s.previousSubstep > 0)) continue;
        const double invH = 1.0 / static_cast<double>(s.previousSubstep);
        for (std::size_t i = 0; i < s.particleCount(); ++i) {
            if (s.inverseMass[i] == 0) continue;  // pinned: held by the world, like a static body
            const double m = 1.0 / static_cast<double>(s.inverseMass[i]);
            const double x[3] = {s.position[i].x, s.position[i].y, s.position[i].z};
            const Vec3& d = s.displacement[i];  // x - x_prev over the last sub-step
            const double p[3] = {m * d.x * invH, m * d.y * invH, m * d.z * invH};
            for (int c = 0; c < 3; ++c) linear[c] += p[c];
            angular[0] += x[1] * p[2] - x[2] * p[1];
            angular[1] += x[2] * p[0] - x[0] * p[2];
            angular[2] += x[0] * p[1] - x[1] * p[0];
        }
    }
}

}  // namespace fulcrum::detail
