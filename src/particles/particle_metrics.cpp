#include "particles/particle_metrics.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "particles/shape_query_adapter.hpp"

namespace fulcrum {

Vec3 centroid(const ParticleSystem& s) {
    if (s.particleCount() == 0) return Vec3::zero();
    double sx = 0, sy = 0, sz = 0;
    for (const Vec3& p : s.position) { sx += p.x; sy += p.y; sz += p.z; }
    const double inv = 1.0 / static_cast<double>(s.particleCount());
    return {static_cast<Real>(sx * inv), static_cast<Real>(sy * inv), static_cast<Real>(sz * inv)};
}

StretchStats structuralStretch(const ParticleSystem& s) {
    StretchStats out;
    if (s.stretch.size() == 0) return out;
    double sum = 0;
    Real mx = -std::numeric_limits<Real>::max();
    for (const DistanceConstraint& c : s.stretch.constraints) {
        const Real e = (distance(s.position[c.a], s.position[c.b]) - c.restLength) / c.restLength;
        sum += e;
        mx = std::max(mx, e);
    }
    out.max = mx;
    out.mean = static_cast<Real>(sum / static_cast<double>(s.stretch.size()));
    return out;
}

namespace {

class PenetrationProbe final : public RigidShapeVisitor {
public:
    explicit PenetrationProbe(const ParticleSystem& s) : s_(s) {}
    void visit(std::uint32_t body, const Shape& shape, const Transform& xf) override {
        // Attached particles sit on or inside their body by design (the
        // particle contacts skip it too): that is the attachment, not a collision.
        for (const ParticleAttachment& a : s_.attachments) {
            if (a.body == body) return;
        }
        for (std::size_t i = 0; i < s_.particleCount(); ++i) {
            const detail::SurfacePoint q = detail::surfaceQuery(shape, xf, s_.position[i]);
            deepest = std::max(deepest, s_.radius[i] - q.distance);
        }
    }
    Real deepest = 0;

private:
    const ParticleSystem& s_;
};

}  // namespace

Real maxPenetration(const ParticleSystem& s, const RigidCollider& collider) {
    if (s.particleCount() == 0) return 0;
    AABB box;
    Real maxRadius = 0;
    for (std::size_t i = 0; i < s.particleCount(); ++i) {
        box.grow(s.position[i]);
        maxRadius = std::max(maxRadius, s.radius[i]);
    }
    PenetrationProbe probe(s);
    collider.queryShapes(box.fattened(maxRadius), probe);
    return probe.deepest;
}

ParticleReport report(const ParticleSystem& s, const RigidCollider* collider) {
    ParticleReport r;
    r.name = s.name;
    r.particles = s.particleCount();
    r.centroid = centroid(s);
    const StretchStats st = structuralStretch(s);
    r.maxStretch = st.max;
    r.meanStretch = st.mean;
    r.maxPenetration = collider ? maxPenetration(s, *collider) : 0;
    return r;
}

ParticleEnergy energy(const ParticleSystem& s, const Vec3& gravity) {
    ParticleEnergy e;
    const double invH = s.previousSubstep > 0 ? 1.0 / static_cast<double>(s.previousSubstep) : 0.0;
    for (std::size_t i = 0; i < s.particleCount(); ++i) {
        if (s.inverseMass[i] == 0) continue;
        const double m = 1.0 / static_cast<double>(s.inverseMass[i]);
        const double dx = s.displacement[i].x, dy = s.displacement[i].y, dz = s.displacement[i].z;
        e.kinetic += 0.5 * m * (dx * dx + dy * dy + dz * dz) * invH * invH;
        e.potential -= m * (static_cast<double>(gravity.x) * s.position[i].x + static_cast<double>(gravity.y) * s.position[i].y +
                            static_cast<double>(gravity.z) * s.position[i].z);
    }
    for (const DistanceConstraintGroup* g : {&s.stretch, &s.shear, &s.bend}) {
        if (g->compliance <= 0) continue;
        for (const DistanceConstraint& c : g->constraints) {
            const double C = static_cast<double>(distance(s.position[c.a], s.position[c.b])) - c.restLength;
            e.elastic += C * C / (2.0 * static_cast<double>(g->compliance));
        }
    }
    return e;
}

Vec3 linearMomentum(const ParticleSystem& s) {
    double px = 0, py = 0, pz = 0;
    const double invH = s.previousSubstep > 0 ? 1.0 / static_cast<double>(s.previousSubstep) : 0.0;
    for (std::size_t i = 0; i < s.particleCount(); ++i) {
        if (s.inverseMass[i] == 0) continue;
        const double m = 1.0 / static_cast<double>(s.inverseMass[i]);
        px += m * static_cast<double>(s.displacement[i].x) * invH;
        py += m * static_cast<double>(s.displacement[i].y) * invH;
        pz += m * static_cast<double>(s.displacement[i].z) * invH;
    }
    return {static_cast<Real>(px), static_cast<Real>(py), static_cast<Real>(pz)};
}

}  // namespace fulcrum
