// Small editing helpers of ParticleSystem: they validate, since users call them.
#include "particles/particle_system.hpp"

#include <limits>

#include "dynamics/validation.hpp"

namespace fulcrum {

namespace {

std::string labelOf(const ParticleSystem& s) { return detail::particleSystemLabel(toString(s.kind), s.name); }

void requireParticle(const ParticleSystem& s, std::uint32_t particle, std::string_view field) {
    if (particle >= s.particleCount()) {
        detail::fail(labelOf(s), field,
                     "refers to particle " + std::to_string(particle) + ", but the system has " +
                     std::to_string(s.particleCount()) + " particles");
    }
}

}  // namespace

const char* toString(ParticleSystemKind kind) {
    switch (kind) {
        case ParticleSystemKind::Rope: return "rope";
        case ParticleSystemKind::Cloth: return "cloth";
        case ParticleSystemKind::Particles: return "particles";
    }
    return "particles";
}

std::uint32_t addParticle(ParticleSystem& system, const Vec3& position, Real mass, Real radius) {
    const std::string label = labelOf(system);
    detail::requireFinite(label, "position", position);
    detail::requireNonNegative(label, "particle_mass", mass);
    detail::requirePositive(label, "radius", radius);
    const auto index = static_cast<std::uint32_t>(system.particleCount());
    system.position.push_back(position);
    system.displacement.push_back(Vec3::zero());
    system.restPosition.push_back(position);
    system.force.push_back(Vec3::zero());
    system.inverseMass.push_back(mass > 0 ? 1 / mass : 0);
    system.radius.push_back(radius);
    return index;
}

void setParticleMass(ParticleSystem& system, std::uint32_t particle, Real mass) {
    requireParticle(system, particle, "particle");
    detail::requirePositive(labelOf(system), "particle_mass", mass);
    system.inverseMass[particle] = 1 / mass;
}

void setParticlePosition(ParticleSystem& system, std::uint32_t particle, const Vec3& position) {
    requireParticle(system, particle, "particle");
    detail::requireFinite(labelOf(system), "position", position);
    system.position[particle] = position;
    system.displacement[particle] = Vec3::zero();
}

void setParticleVelocity(ParticleSystem& system, std::uint32_t particle, const Vec3& velocity, Real substep) {
    requireParticle(system, particle, "particle");
    detail::requireFinite(labelOf(system), "velocity", velocity);
    detail::requirePositive(labelOf(system), "substep", substep);
    system.displacement[particle] = velocity * substep;
    system.previousSubstep = substep;
}

void pinParticle(ParticleSystem& system, std::uint32_t particle) {
    requireParticle(system, particle, "pinned");
    system.inverseMass[particle] = 0;
    for (const ParticlePin& p : system.pins) {
        if (p.particle == particle) return;
    }
    system.pins.push_back({particle, system.position[particle]});
}

void addParticleSpring(ParticleSystem& system, const ParticleSpring& spring) {
    const std::string label = labelOf(system);
    requireParticle(system, spring.a, "spring.a");
    requireParticle(system, spring.b, "spring.b");
    if (spring.a == spring.b) detail::fail(label, "spring", "joins particle " + std::to_string(spring.a) + " to itself");
    detail::requireNonNegative(label, "spring.rest_length", spring.restLength);
    detail::requireNonNegative(label, "spring.stiffness", spring.stiffness);
    detail::requireNonNegative(label, "spring.damping", spring.damping);
    system.springs.push_back(spring);
}

void attachParticle(ParticleSystem& system, std::uint32_t particle, std::uint32_t bodyIndex, Real compliance,
                    const char* field) {
    requireParticle(system, particle, field);
    detail::requireNonNegative(labelOf(system), "attach_compliance", compliance);
    ParticleAttachment a;
    a.particle = particle;
    a.body = bodyIndex;
    a.compliance = compliance;
    a.field = field;
    system.attachments.push_back(a);
}

void addTethers(ParticleSystem& system, Real slack) {
    detail::requireNonNegative(labelOf(system), "tether_slack", slack);
    if (system.pins.empty()) return;
    system.tethers.constraints.clear();
    system.tethers.lambda.clear();
    system.tethers.unilateral = true;
    for (std::uint32_t i = 0; i < system.particleCount(); ++i) {
        if (system.inverseMass[i] == 0) continue;
        Real best = std::numeric_limits<Real>::max();
        std::uint32_t bestPin = 0;
        for (const ParticlePin& p : system.pins) {
            const Real d = distance(system.restPosition[i], system.restPosition[p.particle]);
            if (d < best) { best = d; bestPin = p.particle; }
        }
        system.tethers.add(bestPin, i, best * (1 + slack));
    }
}

}  // namespace fulcrum
