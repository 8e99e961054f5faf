#include "particles/rigid_coupling.hpp"

#include <algorithm>
#include <cmath>

#include "particles/shape_query_adapter.hpp"

namespace fulcrum::detail {

namespace {

Quat rotateBy(const Quat& q, const Vec3& rotationVector) {
    // First-order update q + 1/2 [theta, 0] q, renormalised: the corrections
    // are tiny rotations, far below where the first-order map loses accuracy.
    return normalize(q + Quat(0, rotationVector.x, rotationVector.y, rotationVector.z) * q * Real(0.5));
}

// A particle against a static surface (no body to push back): the normal
// correction moves it out by -C along n, and friction removes the slip of
// this sub-step - all of it (static) when it is within mu times that push,
// else mu times the push (kinetic). The same law as solveContact with the
// body's inverse mass 0, written so the common cases need no division and
// no square root beyond the caller's distance: static friction is decided
// on squared lengths (cloth benchmark: 1.87 -> 1.70 ms CPU per step).
inline void solveStaticContact(ParticleSoA& p, std::size_t i, const Vec3& normal, Real C, Real mu) {
    Vec3 x = p.position(i) + normal * -C;
    if (mu > 0) {
        const Vec3 rel = (x - p.predicted(i)) + p.displacement(i);  // this sub-step's motion; the surface is still
        const Vec3 tangential = rel - normal * dot(rel, normal);
        const Real slip2 = lengthSquared(tangential);
        const Real limit = mu * -C;
        if (slip2 <= limit * limit) {
            x -= tangential;
        } else {
            x -= tangential * (limit / std::sqrt(slip2));
        }
    }
    p.setPosition(i, x);
}

}  // namespace

class CandidateGatherer final : public RigidShapeVisitor {
public:
    CandidateGatherer(RigidCoupling& coupling, RigidCollider& collider, const ParticleSystem& system, Real fatten)
        : coupling_(coupling), collider_(collider), system_(system), fatten_(fatten) {}
    void visit(std::uint32_t bodyIndex, const Shape& shape, const Transform& shapeTransform) override {
        // A system does not collide with the bodies it is attached to: the
        // attached particles sit on (often inside) the body by design, and
        // contacts would fight the attachment.
        for (const ParticleAttachment& a : system_.attachments) {
            if (a.body == bodyIndex) return;
        }
        RigidCoupling::Candidate c;
        c.body = bodyIndex;
        c.proxy = coupling_.proxyFor(collider_, bodyIndex);
        const auto& proxy = coupling_.proxies_[static_cast<std::size_t>(c.proxy)];
        c.dynamic = proxy.base.inverseMass > 0;
        c.moves = c.dynamic || proxy.moving;
        c.shape = &shape;
        c.transform = shapeTransform;
        // Bounds over the whole step's path (start and end poses).
        c.bounds = shape.bounds(shapeTransform);
        if (proxy.moving) c.bounds.grow(shape.bounds(proxy.base.previousTransform * relative(proxy.base.transform, shapeTransform)));
        c.bounds = c.bounds.fattened(fatten_);
        c.friction = coupling_.proxies_[static_cast<std::size_t>(c.proxy)].base.friction;
        coupling_.candidates_.push_back(c);
    }

private:
    RigidCoupling& coupling_;
    RigidCollider& collider_;
    const ParticleSystem& system_;
    Real fatten_;
};

std::int32_t RigidCoupling::proxyFor(RigidCollider& collider, std::uint32_t body) {
    if (body >= proxyOfBody_.size()) proxyOfBody_.resize(static_cast<std::size_t>(body) + 1, -1);  // grows with the world only
    std::int32_t& slot = proxyOfBody_[body];
    if (slot < 0) {
        Proxy p;
        p.body = body;
        p.base = collider.bodyState(body);
        p.moving = !(p.base.previousTransform == p.base.transform);
        p.localCenter = inverseTransformPoint(p.base.transform, p.base.centerOfMass);
        p.path = p.base.previousTransform;
        slot = static_cast<std::int32_t>(proxies_.size());
        proxies_.push_back(p);
    }
    return slot;
}

void RigidCoupling::beginStep(RigidCollider& collider, const std::vector<ParticleSystem*>& systems,
                              const std::vector<Real>& margin) {
    candidates_.clear();
    ranges_.clear();
    near_.clear();
    for (std::size_t k = 0; k < systems.size(); ++k) {
        const ParticleSystem& s = *systems[k];
        Range range;
        range.begin = candidates_.size();
        if (s.particleCount() > 0) {
            AABB box;
            Real maxRadius = 0;
            for (std::size_t i = 0; i < s.particleCount(); ++i) {
                box.grow(s.position[i]);
                maxRadius = std::max(maxRadius, s.radius[i]);
            }
            const Real fatten = maxRadius + margin[k];
            CandidateGatherer gatherer(*this, collider, s, fatten);
            collider.queryShapes(box.fattened(fatten), gatherer);
            // A static shape cannot come to a particle, so a particle farther
            // from it than it can travel this step never touches it: list the
            // near ones once per step instead of testing every particle every
            // sub-step (the distance to a surface changes at most as fast as
            // the particle moves). The margin is doubled since constraints can
            // accelerate a particle beyond the step's largest speed.
            const Real reach = 2 * margin[k] + 2 * maxRadius;
            for (std::size_t ci = range.begin; ci < candidates_.size(); ++ci) {
                Candidate& c = candidates_[ci];
                c.nearBegin = c.nearEnd = near_.size();
                if (c.moves) continue;
                const AABB shapeBox = c.shape->bounds(c.transform).fattened(reach);
                for (std::size_t i = 0; i < s.particleCount(); ++i) {
                    if (s.inverseMass[i] == 0 || !shapeBox.contains(s.position[i])) continue;
                    if (surfaceQuery(*c.shape, c.transform, s.position[i]).distance - s.radius[i] < reach) {
                        near_.push_back(static_cast<std::uint32_t>(i));
                    }
                }
                c.nearEnd = near_.size();
            }
        }
        range.end = candidates_.size();
        ranges_.push_back(range);
        for (ParticleAttachment& a : systems[k]->attachments) proxyFor(collider, a.body);
    }
}

Transform RigidCoupling::moved(const Proxy& p, const Transform& base) const {
    const Transform onPath = p.path * relative(p.base.transform, base);
    const Vec3 c = transformPoint(p.path, p.localCenter);
    return {c + p.deltaPosition + rotate(p.deltaRotation, onPath.p - c), p.deltaRotation * onPath.q};
}

void RigidCoupling::beginSubstep(int index, int count, Real substep) {
    const Real s = static_cast<Real>(index + 1) / static_cast<Real>(count);
    for (Proxy& p : proxies_) {
        // Prediction: the velocity the particles gave the body moves it on
        // (from the second sub-step on: the first has no earlier push).
        if (index > 0 && p.base.inverseMass > 0) {
            p.deltaPosition += p.extraLinearVelocity * substep;
            p.deltaRotation = rotateBy(p.deltaRotation, p.extraAngularVelocity * substep);
        }
        if (!p.moving) continue;
        p.path = {lerp(p.base.previousTransform.p, p.base.transform.p, s), slerp(p.base.previousTransform.q, p.base.transform.q, s)};
    }
}

Real RigidCoupling::inverseMassAt(const Proxy& p, const Vec3& point, const Vec3& direction) const {
    if (p.base.inverseMass == 0) return 0;
    const Vec3 rn = cross(point - currentCenter(p), direction);
    return p.base.inverseMass + dot(rn, p.base.inverseInertia * rn);
}

void RigidCoupling::applyCorrection(Proxy& p, const Vec3& positionalImpulse, const Vec3& point, Real substep) {
    if (p.base.inverseMass == 0) return;
    const Vec3 r = point - currentCenter(p);
    const Vec3 dx = positionalImpulse * p.base.inverseMass;
    const Vec3 dTheta = p.base.inverseInertia * cross(r, positionalImpulse);
    p.deltaPosition += dx;
    p.deltaRotation = rotateBy(p.deltaRotation, dTheta);
    const Real invH = 1 / substep;
    p.extraLinearVelocity += dx * invH;
    p.extraAngularVelocity += dTheta * invH;
    p.linearImpulse += positionalImpulse * invH;
    p.angularImpulse += cross(r, positionalImpulse) * invH;
}

void RigidCoupling::solveContact(const Candidate& c, Proxy& proxy, const SurfacePoint& q, Real mu, ParticleSoA& p,
                                 std::size_t i, Real radius, Real substep) {
    const Vec3 xi = p.position(i);
    const Real C = q.distance - radius;
    if (C >= 0) return;
    const Real wi = p.w[i];
    const Vec3 normal = q.normal;
    // Normal: push the particle sphere out of the surface.
    const Real wBody = c.dynamic ? inverseMassAt(proxy, q.point, normal) : 0;
    const Real dLambda = -C / (wi + wBody);
    Vec3 x = xi + normal * (wi * dLambda);
    if (c.dynamic) applyCorrection(proxy, normal * -dLambda, q.point, substep);
    if (mu > 0) {
        // Friction: relative tangential displacement of the particle over
        // the body's surface during this sub-step.
        Vec3 surfaceMotion = Vec3::zero();
        if (proxy.base.inverseMass > 0 || lengthSquared(proxy.base.linearVelocity) > 0 ||
            lengthSquared(proxy.base.angularVelocity) > 0) {
            const Vec3 r = q.point - currentCenter(proxy);
            const Vec3 v = proxy.base.linearVelocity + proxy.extraLinearVelocity +
                           cross(proxy.base.angularVelocity + proxy.extraAngularVelocity, r);
            surfaceMotion = v * substep;
        }
        const Vec3 rel = (x - p.predicted(i)) + p.displacement(i) - surfaceMotion;  // this sub-step's motion
        const Vec3 tangential = rel - normal * dot(rel, normal);
        const Real slip = length(tangential);
        if (slip >= Real(1e-12)) {
            // Static friction removes all the slip; kinetic at most mu * depth
            // (one friction coefficient for both).
            const Real removed = std::min(slip, mu * (-C));
            const Vec3 t = tangential / slip;
            const Real wBodyT = c.dynamic ? inverseMassAt(proxy, q.point, t) : 0;
            const Real dLambdaT = removed / (wi + wBodyT);
            x -= t * (wi * dLambdaT);
            if (c.dynamic) applyCorrection(proxy, t * dLambdaT, q.point, substep);
        }
    }
    p.setPosition(i, x);
}

void RigidCoupling::solveContacts(std::size_t k, const ParticleSystem& s, ParticleSoA& p, Real substep) {
    if (k >= ranges_.size()) return;
    const Range range = ranges_[k];
    if (range.begin == range.end) return;
    const Real* w = p.w.data();
    const Real* radius = s.radius.data();
    const std::size_t n = p.size();
    for (std::size_t ci = range.begin; ci < range.end; ++ci) {
        const Candidate& c = candidates_[ci];
        Proxy& proxy = proxies_[static_cast<std::size_t>(c.proxy)];
        const Transform xf = c.moves ? moved(proxy, c.transform) : c.transform;
        const Real mu = std::sqrt(std::max(s.friction, Real(0)) * std::max(c.friction, Real(0)));
        if (c.moves) {
            for (std::size_t i = 0; i < n; ++i) {
                if (w[i] == 0 || !c.bounds.contains(p.position(i))) continue;
                solveContact(c, proxy, surfaceQuery(*c.shape, xf, p.position(i)), mu, p, i, radius[i], substep);
            }
            continue;
        }
        // Static shapes: only the particles that were near when the step
        // began. Spheres and planes, the common static colliders, are tested
        // in world space without the general query's two frame changes (it
        // was 35 % of the cloth benchmark's step); most particles are
        // rejected by one comparison before any square root.
        if (c.shape->type() == ShapeType::Sphere) {
            const Vec3 center = c.transform.p;
            const Real R = c.shape->radius();
            const Vec3 fallbackNormal = rotate(c.transform.q, Vec3::unitY());  // a particle exactly at the centre
            for (std::size_t e = c.nearBegin; e < c.nearEnd; ++e) {
                const std::uint32_t i = near_[e];
                const Vec3 d = p.position(i) - center;
                const Real len2 = lengthSquared(d);
                const Real touch = R + radius[i];
                if (len2 >= touch * touch) continue;
                const Real len = std::sqrt(len2);
                const Vec3 normal = len > 0 ? d * (1 / len) : fallbackNormal;
                solveStaticContact(p, i, normal, len - touch, mu);
            }
        } else if (c.shape->type() == ShapeType::Plane) {
            const Vec3 normal = rotate(c.transform.q, c.shape->planeNormal());
            const Real offset = c.shape->planeOffset() + dot(normal, c.transform.p);
            for (std::size_t e = c.nearBegin; e < c.nearEnd; ++e) {
                const std::uint32_t i = near_[e];
                const Real distance = dot(normal, p.position(i)) - offset;
                if (distance >= radius[i]) continue;
                solveStaticContact(p, i, normal, distance - radius[i], mu);
            }
        } else {
            for (std::size_t e = c.nearBegin; e < c.nearEnd; ++e) {
                const std::uint32_t i = near_[e];
                solveContact(c, proxy, surfaceQuery(*c.shape, xf, p.position(i)), mu, p, i, radius[i], substep);
            }
        }
    }
}

void RigidCoupling::resetAttachmentMultipliers(ParticleSystem& s) {
    for (ParticleAttachment& a : s.attachments) a.lambda = 0;
}

void RigidCoupling::solveAttachments(ParticleSystem& s, ParticleSoA& p, Real substep) {
    const Real invH2 = 1 / (substep * substep);
    for (ParticleAttachment& a : s.attachments) {
        Proxy& proxy = proxies_[static_cast<std::size_t>(proxyOfBody_[a.body])];
        const Transform xf = moved(proxy, proxy.base.transform);
        const Vec3 anchor = transformPoint(xf, a.localAnchor);
        const Vec3 d = p.position(a.particle) - anchor;
        const Real C = length(d);
        if (C < Real(1e-9)) continue;
        const Vec3 n = d / C;
        const Real alphaTilde = a.compliance * invH2;
        const Real wp = p.w[a.particle];
        const Real wb = inverseMassAt(proxy, anchor, n);
        const Real denominator = wp + wb + alphaTilde;
        if (denominator <= 0) continue;
        const Real dLambda = (-C - alphaTilde * a.lambda) / denominator;
        a.lambda += dLambda;
        p.setPosition(a.particle, p.position(a.particle) + n * (wp * dLambda));
        applyCorrection(proxy, n * -dLambda, anchor, substep);
    }
}

void RigidCoupling::endStep(RigidCollider& collider) {
    for (const Proxy& p : proxies_) {
        if (p.base.inverseMass > 0 && (p.linearImpulse != Vec3::zero() || p.angularImpulse != Vec3::zero())) {
            collider.applyImpulse(p.body, p.linearImpulse, p.angularImpulse);
            collider.applyDisplacement(p.body, p.deltaPosition, p.deltaRotation);
        }
        proxyOfBody_[p.body] = -1;
    }
    proxies_.clear();
    candidates_.clear();
}

}  // namespace fulcrum::detail
