// World: the particle-system API (ropes and cloths). Everything here is API
// boundary: handles and attachments are validated, then the ParticleWorld in
// WorldImpl does the work. The coupling with the bodies lives in
// particle_coupling.cpp.
#include <algorithm>

#include "particles/particle_builders.hpp"
#include "particles/particle_metrics.hpp"
#include "dynamics/validation.hpp"
#include "particles/shape_query_adapter.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

namespace {

// An attachment must name a live body: a null handle means "not attached",
// anything else unknown or stale is an error naming the system and field.
void requireAttachBody(const WorldImpl& w, const std::string& label, const char* field, BodyId id) {
    if (id.isNull()) return;
    if (id.index >= w.bodySlots.size()) {
        detail::fail(label, field, "BodyId index " + std::to_string(id.index) + " does not exist (" +
                     std::to_string(w.bodySlots.size()) + " body slots)");
    }
    if (!w.isLive(id)) {
        detail::fail(label, field, "stale BodyId (index " + std::to_string(id.index) + ", generation " +
                     std::to_string(id.generation) + "): that body was destroyed");
    }
}

ParticleSystemId addSystem(WorldImpl& w, ParticleSystem system) {
    detail::WorldRigidCollider collider(w);
    w.particles.live.reserve(w.particles.live.size() + 1);  // nothing may throw after add()
    const ParticleSystemId id = w.particles.world.add(std::move(system), &collider);
    w.particles.live.push_back(id);
    return id;
}

}  // namespace

ParticleSystemId World::createRope(const RopeDef& def) {
    WorldImpl& w = *impl_;
    const std::string label = detail::particleSystemLabel("rope", def.name);
    requireAttachBody(w, label, "attach_start", def.attachStart);
    requireAttachBody(w, label, "attach_end", def.attachEnd);
    // buildRope names bodies by BodyId::index, the slot: the body index of
    // the World's RigidCollider (world/particle_coupling.hpp).
    return addSystem(w, buildRope(def));
}

ParticleSystemId World::createCloth(const ClothDef& def) { return addSystem(*impl_, buildCloth(def)); }

void World::destroyParticleSystem(ParticleSystemId id) {
    WorldImpl& w = *impl_;
    w.particles.world.remove(id);  // throws for a null or stale handle
    std::erase(w.particles.live, id);
}

bool World::isValid(ParticleSystemId id) const { return impl_->particles.world.isValid(id); }

std::vector<ParticleSystemId> World::particleSystems() const { return impl_->particles.live; }

const std::string& World::name(ParticleSystemId id) const { return impl_->particles.world.system(id).name; }

ParticleSystemType World::particleSystemType(ParticleSystemId id) const {
    return impl_->particles.world.system(id).kind == ParticleSystemKind::Cloth ? ParticleSystemType::Cloth
                                                                                : ParticleSystemType::Rope;
}

std::array<int, 2> World::clothSize(ParticleSystemId id) const {
    const ParticleSystem& s = impl_->particles.world.system(id);
    if (s.kind == ParticleSystemKind::Cloth) return {s.gridSize[0], s.gridSize[1]};
    return {static_cast<int>(s.particleCount()), 1};
}

std::size_t World::particleCount(ParticleSystemId id) const { return impl_->particles.world.system(id).particleCount(); }

Real World::particleRadius(ParticleSystemId id) const {
    const ParticleSystem& s = impl_->particles.world.system(id);
    return s.radius.empty() ? Real(0) : *std::max_element(s.radius.begin(), s.radius.end());
}

std::span<const Vec3> World::particlePositions(ParticleSystemId id) const {
    return impl_->particles.world.system(id).position;
}

Vec3 World::particleVelocity(ParticleSystemId id, std::size_t particle) const {
    const ParticleSystem& s = impl_->particles.world.system(id);
    if (particle >= s.particleCount()) {
        detail::fail(detail::particleSystemLabel(toString(s.kind), s.name), "particle",
                     "index " + std::to_string(particle) + " is outside the system (" +
                     std::to_string(s.particleCount()) + " particles)");
    }
    return s.velocity(particle);
}

ParticleReport World::particleReport(ParticleSystemId id) const {
    const ParticleSystem& s = impl_->particles.world.system(id);
    // The collider only reads here (queryShapes); it needs a
    // mutable WorldImpl for the pushes, which report() never makes.
    const detail::WorldRigidCollider collider(const_cast<WorldImpl&>(*impl_));
    return report(s, &collider);
}

}  // namespace fulcrum
