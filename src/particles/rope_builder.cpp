// buildRope: a chain of particles joined by stretch and bend constraints.
#include "particles/particle_builders.hpp"
#include "dynamics/validation.hpp"

namespace fulcrum {

ParticleSystem buildRope(const RopeDef& def) {
    const std::string label = detail::particleSystemLabel("rope", def.name);
    detail::requireFinite(label, "start", def.start);
    detail::requireFinite(label, "end", def.end);
    if (def.segments < 1) {
        detail::fail(label, "segments", "must be at least 1, got " + std::to_string(def.segments));
    }
    if (def.segments >= kMaxParticlesPerSystem) {  // segments + 1 particles
        detail::fail(label, "segments", "must be below " + std::to_string(kMaxParticlesPerSystem) +
                     " (the particle limit of a system), got " + std::to_string(def.segments));
    }
    detail::requirePositive(label, "particle_mass", def.particleMass);
    detail::requirePositive(label, "radius", def.radius);
    detail::requireNonNegative(label, "stretch_compliance", def.stretchCompliance);
    detail::requireNonNegative(label, "bend_compliance", def.bendCompliance);
    detail::requireNonNegative(label, "damping", def.damping);
    detail::requireNonNegative(label, "friction", def.friction);
    detail::requireNonNegative(label, "attach_compliance", def.attachCompliance);
    const Real length = distance(def.start, def.end);
    const Real spacing = length / static_cast<Real>(def.segments);
    if (!(spacing > 0)) {
        detail::fail(label, "end", "coincides with start " + detail::formatVec(def.start) +
                     ": the segment spacing must be positive, got " + detail::formatReal(spacing));
    }

    ParticleSystem rope;
    rope.name = def.name;
    rope.kind = ParticleSystemKind::Rope;
    const auto n = static_cast<std::uint32_t>(def.segments) + 1;
    for (std::uint32_t i = 0; i < n; ++i) {
        const Real t = static_cast<Real>(i) / static_cast<Real>(def.segments);
        addParticle(rope, lerp(def.start, def.end, t), def.particleMass, def.radius);
    }
    rope.stretch.compliance = def.stretchCompliance;
    rope.bend.compliance = def.bendCompliance;
    for (std::uint32_t i = 0; i + 1 < n; ++i) {
        rope.stretch.add(i, i + 1, distance(rope.position[i], rope.position[i + 1]));
    }
    for (std::uint32_t i = 0; i + 2 < n; ++i) {
        rope.bend.add(i, i + 2, distance(rope.position[i], rope.position[i + 2]));
    }
    rope.damping = def.damping;
    rope.friction = def.friction;

    if (!def.attachStart.isNull()) {
        attachParticle(rope, 0, def.attachStart.index, def.attachCompliance, "attach_start");
    } else if (def.pinStart) {
        pinParticle(rope, 0);
    }
    if (!def.attachEnd.isNull()) {
        attachParticle(rope, n - 1, def.attachEnd.index, def.attachCompliance, "attach_end");
    } else if (def.pinEnd) {
        pinParticle(rope, n - 1);
    }
    if (def.tethers) addTethers(rope);
    return rope;
}

}  // namespace fulcrum
