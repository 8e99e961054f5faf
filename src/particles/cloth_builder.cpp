// buildCloth: a rectangular grid of particles with structural, shear and bend
// distance constraints (the classic mass-spring cloth topology, solved as
// XPBD constraints instead of springs).
#include <algorithm>
#include <cmath>

#include "particles/particle_builders.hpp"
#include "dynamics/validation.hpp"

namespace fulcrum {

ParticleSystem buildCloth(const ClothDef& def) {
    const std::string label = detail::particleSystemLabel("cloth", def.name);
    detail::requireFinite(label, "origin", def.origin);
    detail::requireFinite(label, "u_axis", def.uAxis);
    detail::requireFinite(label, "v_axis", def.vAxis);
    if (lengthSquared(def.uAxis) == 0) detail::fail(label, "u_axis", "must not be the zero vector");
    if (lengthSquared(def.vAxis) == 0) detail::fail(label, "v_axis", "must not be the zero vector");
    const Real sine = length(cross(normalize(def.uAxis), normalize(def.vAxis)));
    if (sine < Real(1e-4)) {
        detail::fail(label, "v_axis", detail::formatVec(def.vAxis) + " is parallel to u_axis " +
                     detail::formatVec(def.uAxis) + ": the grid would be degenerate");
    }
    for (int k = 0; k < 2; ++k) {
        if (def.size[static_cast<std::size_t>(k)] < 2) {
            detail::fail(label, k == 0 ? "size[0]" : "size[1]",
                         "must be at least 2 particles, got " + std::to_string(def.size[static_cast<std::size_t>(k)]));
        }
    }
    detail::requirePositive(label, "spacing", def.spacing);
    detail::requirePositive(label, "particle_mass", def.particleMass);
    detail::requirePositive(label, "radius", def.radius);
    detail::requireNonNegative(label, "stretch_compliance", def.stretchCompliance);
    detail::requireNonNegative(label, "bend_compliance", def.bendCompliance);
    if (def.shearCompliance) detail::requireNonNegative(label, "shear_compliance", *def.shearCompliance);
    detail::requireNonNegative(label, "damping", def.damping);
    detail::requireNonNegative(label, "friction", def.friction);
    detail::requireNonNegative(label, "drag_coefficient", def.dragCoefficient);
    detail::requireFinite(label, "lift_coefficient", def.liftCoefficient);
    const int nu = def.size[0], nv = def.size[1];
    for (std::size_t k = 0; k < def.pinned.size(); ++k) {
        const auto& p = def.pinned[k];
        if (p[0] < 0 || p[0] >= nu || p[1] < 0 || p[1] >= nv) {
            detail::fail(label, "pinned[" + std::to_string(k) + "]",
                         "= [" + std::to_string(p[0]) + ", " + std::to_string(p[1]) + "] is outside the " +
                         std::to_string(nu) + " x " + std::to_string(nv) + " grid (i in [0, " +
                         std::to_string(nu - 1) + "], j in [0, " + std::to_string(nv - 1) + "])");
        }
    }
    if (static_cast<double>(nu) * static_cast<double>(nv) > static_cast<double>(kMaxParticlesPerSystem)) {
        detail::fail(label, "size", "asks for more than 1e8 particles");
    }

    ParticleSystem cloth;
    cloth.name = def.name;
    cloth.kind = ParticleSystemKind::Cloth;
    cloth.gridSize[0] = nu;
    cloth.gridSize[1] = nv;
    const auto count = static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv);
    cloth.position.reserve(count);
    for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
            const Vec3 p = def.origin + (def.uAxis * static_cast<Real>(i) + def.vAxis * static_cast<Real>(j)) * def.spacing;
            if (!isFinite(p)) detail::fail(label, "origin", "and spacing place a particle at a non-finite position");
            addParticle(cloth, p, def.particleMass, def.radius);
        }
    }
    const auto id = [&](int i, int j) { return clothParticle(cloth, i, j); };
    const auto link = [&](DistanceConstraintGroup& g, std::uint32_t a, std::uint32_t b) {
        g.add(a, b, distance(cloth.position[a], cloth.position[b]));
    };
    // Row by row, so Gauss-Seidel sweeps propagate along the grid in a fixed,
    // deterministic order.
    for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
            if (i + 1 < nu) link(cloth.stretch, id(i, j), id(i + 1, j));
            if (j + 1 < nv) link(cloth.stretch, id(i, j), id(i, j + 1));
            if (i + 1 < nu && j + 1 < nv) {
                link(cloth.shear, id(i, j), id(i + 1, j + 1));
                link(cloth.shear, id(i + 1, j), id(i, j + 1));
                // Alternate the diagonal so the surface has no preferred direction.
                if ((i + j) % 2 == 0) {
                    cloth.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
                    cloth.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
                } else {
                    cloth.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
                    cloth.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
                }
            }
            if (i + 2 < nu) link(cloth.bend, id(i, j), id(i + 2, j));
            if (j + 2 < nv) link(cloth.bend, id(i, j), id(i, j + 2));
        }
    }
    cloth.stretch.compliance = def.stretchCompliance;
    cloth.shear.compliance = def.shearCompliance.value_or(def.stretchCompliance);
    cloth.bend.compliance = def.bendCompliance;
    cloth.damping = def.damping;
    cloth.friction = def.friction;
    cloth.dragCoefficient = def.dragCoefficient;
    cloth.liftCoefficient = def.liftCoefficient;
    cloth.selfCollision = def.selfCollision;
    // Neighbours up to two cells apart (rest distance < 2.5 cells) are held by
    // the constraints; only farther pairs (a fold) need contacts.
    const Real cell = def.spacing * std::min(length(def.uAxis), length(def.vAxis));
    cloth.selfCollisionExclusion = std::max(Real(2.5) * cell, Real(2.02) * def.radius);

    for (const auto& p : def.pinned) pinParticle(cloth, id(p[0], p[1]));
    if (def.tethers) addTethers(cloth);
    return cloth;
}

}  // namespace fulcrum
