// Diagnostics: energy, momentum and contacts. Sums run in double so that a
// thousand-body scene does not lose the small terms (the drift the tests measure
// is often 1e-4 of the total).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "world/world_impl.hpp"

namespace fulcrum {

namespace {

struct DVec3 {
    double x = 0, y = 0, z = 0;
};
DVec3 toD(const Vec3& v) { return {v.x, v.y, v.z}; }
double dotD(const DVec3& a, const DVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
DVec3 crossD(const DVec3& a, const DVec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
DVec3 mulD(const Mat3& m, const DVec3& v) {
    return {m(0, 0) * v.x + m(0, 1) * v.y + m(0, 2) * v.z, m(1, 0) * v.x + m(1, 1) * v.y + m(1, 2) * v.z,
            m(2, 0) * v.x + m(2, 1) * v.y + m(2, 2) * v.z};
}
// I_w w = R I_b R^T w, in double.
DVec3 angularMomentumAboutCom(const detail::BodyMotion& m, const detail::BodyParams& p) {
    const DVec3 wb = toD(inverseRotate(m.q, m.w));
    const DVec3 lb = mulD(p.localInertia, wb);
    const Mat3 r = toMat3(m.q);
    return mulD(r, lb);
}

}  // namespace

// Kinetic: 1/2 m v^2 + 1/2 w . I_w w of dynamic bodies (kinematic bodies have no
// mass). Potential: gravity -m s g . x_com (zero at the origin) plus springs
// 1/2 k (L - L0)^2. ForceCallbacks have no potential (they need not be
// conservative), so with a callback `total` is not conserved by itself.
EnergyReport World::energy() const {
    const WorldImpl& w = *impl_;
    EnergyReport e;
    const DVec3 g = toD(w.settings.gravity);
    for (std::size_t i = 0; i < w.motion.size(); ++i) {
        const detail::BodyParams& p = w.params[i];
        if (p.type != BodyType::Dynamic) continue;
        const detail::BodyMotion& m = w.motion[i];
        const DVec3 v = toD(m.v);
        e.kinetic += 0.5 * p.mass * dotD(v, v);
        e.kinetic += 0.5 * dotD(toD(m.w), angularMomentumAboutCom(m, p));
        e.potential -= static_cast<double>(p.mass) * p.gravityScale * dotD(g, toD(m.com));
    }
    for (const detail::SpringData& s : w.springs) {
        if (!s.alive) continue;
        const double len = distance(w.anchorWorld(w.denseOrNone(s.bodyA), s.localA),
                                    w.anchorWorld(w.denseOrNone(s.bodyB), s.localB));
        const double stretch = len - s.restLength;
        e.potential += 0.5 * s.stiffness * stretch * stretch;
    }
    detail::addParticleEnergy(w, e.kinetic, e.potential);  // ropes and cloths (world/particle_coupling.hpp)
    e.total = e.kinetic + e.potential;
    return e;
}

Vec3 World::linearMomentum() const {
    const WorldImpl& w = *impl_;
    DVec3 sum;
    for (std::size_t i = 0; i < w.motion.size(); ++i) {
        if (w.params[i].type != BodyType::Dynamic) continue;
        const double m = w.params[i].mass;
        sum.x += m * w.motion[i].v.x;
        sum.y += m * w.motion[i].v.y;
        sum.z += m * w.motion[i].v.z;
    }
    double particleLinear[3] = {0, 0, 0}, particleAngular[3] = {0, 0, 0};
    detail::addParticleMomentum(w, particleLinear, particleAngular);
    sum.x += particleLinear[0];
    sum.y += particleLinear[1];
    sum.z += particleLinear[2];
    return {static_cast<Real>(sum.x), static_cast<Real>(sum.y), static_cast<Real>(sum.z)};
}

// About the world origin: sum of m x_com x v + I_w w.
Vec3 World::angularMomentum() const {
    const WorldImpl& w = *impl_;
    DVec3 sum;
    for (std::size_t i = 0; i < w.motion.size(); ++i) {
        const detail::BodyParams& p = w.params[i];
        if (p.type != BodyType::Dynamic) continue;
        const detail::BodyMotion& m = w.motion[i];
        const DVec3 orbital = crossD(toD(m.com), toD(m.v));
        const DVec3 spin = angularMomentumAboutCom(m, p);
        sum.x += p.mass * orbital.x + spin.x;
        sum.y += p.mass * orbital.y + spin.y;
        sum.z += p.mass * orbital.z + spin.z;
    }
    double particleLinear[3] = {0, 0, 0}, particleAngular[3] = {0, 0, 0};
    detail::addParticleMomentum(w, particleLinear, particleAngular);
    sum.x += particleAngular[0];
    sum.y += particleAngular[1];
    sum.z += particleAngular[2];
    return {static_cast<Real>(sum.x), static_cast<Real>(sum.y), static_cast<Real>(sum.z)};
}

std::vector<ContactReport> World::contacts() const {
    impl_->ensureContactReport();  // built on first read after a step (world_impl.hpp)
    const auto first = impl_->contacts.begin();
    return {first, first + static_cast<std::ptrdiff_t>(impl_->contactReportCount)};
}
Vec3 World::contactForce(BodyId body) const {
    const BodyId one[1] = {body};
    return contactForces(one)[0];
}
std::vector<Vec3> World::contactForces(std::span<const BodyId> bodies) const {
    for (const BodyId id : bodies) {
        if (!isValid(id)) {
            throw Error("World::contactForces: body (index " + std::to_string(id.index) + ", generation " +
                        std::to_string(id.generation) + ") does not exist or was destroyed");
        }
    }
    impl_->ensureContactReport();
    std::vector<Vec3> out(bodies.size());
    // Where each listed body sits, by body slot (the report names bodies by handle).
    std::vector<std::uint32_t> order(bodies.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return bodies[x].index < bodies[y].index; });
    const auto add = [&](BodyId id, const Vec3& f) {
        auto it = std::lower_bound(order.begin(), order.end(), id.index,
                                   [&](std::uint32_t k, std::uint32_t index) { return bodies[k].index < index; });
        for (; it != order.end() && bodies[*it].index == id.index; ++it) out[*it] += f;
    };
    for (std::size_t i = 0; i < impl_->contactReportCount; ++i) {
        const ContactReport& c = impl_->contacts[i];
        add(c.bodyB, c.force);
        if (!c.bodyA.isNull()) add(c.bodyA, -c.force);
    }
    return out;
}
std::vector<DeepOverlap> World::deepOverlaps(Real fraction) const {
    if (!std::isfinite(fraction) || !(fraction > 0)) {
        throw Error("World::deepOverlaps: fraction must be finite and > 0, got " + std::to_string(fraction));
    }
    impl_->ensureContactReport();
    std::vector<DeepOverlap> deep;
    for (std::size_t i = 0; i < impl_->contactReportCount; ++i) {
        const ContactReport& c = impl_->contacts[i];
        // The smaller dynamic body's smallest extent: a static ground (or a
        // flat mesh) says nothing about how deep a box may rest in it.
        Real size = std::numeric_limits<Real>::infinity();
        for (const BodyId id : {c.bodyA, c.bodyB}) {
            if (!isValid(id) || bodyType(id) != BodyType::Dynamic) continue;
            const AABB box = shape(id).localBounds();
            const Vec3 extent = box.max - box.min;
            size = std::min({size, extent.x, extent.y, extent.z});
        }
        if (std::isfinite(size) && c.depth > fraction * size) deep.push_back({c.bodyA, c.bodyB, c.depth, size});
    }
    // Deepest first, ties by the bodies' handles: a total order, so std::sort
    // (std::stable_sort's temporary buffer trips ASan's new/free check with GCC 12).
    std::sort(deep.begin(), deep.end(), [](const DeepOverlap& a, const DeepOverlap& b) {
        if (a.depth != b.depth) return a.depth > b.depth;
        if (a.bodyA.index != b.bodyA.index) return a.bodyA.index < b.bodyA.index;
        return a.bodyB.index < b.bodyB.index;
    });
    return deep;
}

std::span<const ContactEvent> World::contactBeginEvents() const { return impl_->contactManager.beginEvents; }
std::span<const ContactEvent> World::contactEndEvents() const { return impl_->contactManager.endEvents; }
std::span<const ContactEvent> World::sensorBeginEvents() const { return impl_->contactManager.sensorBeginEvents; }
std::span<const ContactEvent> World::sensorEndEvents() const { return impl_->contactManager.sensorEndEvents; }

// ---------------------------------------------------------------- FixedStepper

FixedStepper::FixedStepper(World& world, Real dt, int maxSteps) : world_(&world), dt_(dt), maxSteps_(maxSteps) {
    if (!std::isfinite(dt) || dt <= 0) throw Error("FixedStepper: dt must be a positive finite time, got " + std::to_string(dt));
    if (maxSteps < 1) throw Error("FixedStepper: maxSteps must be at least 1, got " + std::to_string(maxSteps));
}

int FixedStepper::advance(Real frameSeconds) {
    if (!std::isfinite(frameSeconds) || frameSeconds < 0) {
        throw Error("FixedStepper::advance: frameSeconds must be finite and not negative, got " + std::to_string(frameSeconds));
    }
    accumulator_ += frameSeconds;
    int steps = 0;
    while (accumulator_ >= dt_ && steps < maxSteps_) {
        world_->step(dt_);
        accumulator_ -= dt_;
        ++steps;
    }
    // Spiral of death: when a frame needs more than maxSteps, drop the backlog
    // (the simulation runs slower than real time) instead of falling further behind.
    if (steps == maxSteps_ && accumulator_ >= dt_) accumulator_ = std::fmod(accumulator_, dt_);
    alpha_ = accumulator_ / dt_;
    return steps;
}

Transform FixedStepper::interpolatedTransform(BodyId id) const {
    const Transform a = world_->previousTransform(id);
    const Transform b = world_->transform(id);
    return {lerp(a.p, b.p, alpha_), slerp(a.q, b.q, alpha_)};
}

}  // namespace fulcrum
