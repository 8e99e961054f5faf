#include "dynamics/forces.hpp"

namespace fulcrum::detail {

Vec3 springForceOnB(const Vec3& pA, const Vec3& pB, const Vec3& vRel, Real restLength, Real stiffness, Real damping) {
    // F = -k (L - L0) n - c (v_rel . n) n, written as -k (d - L0 n) - ... so that a
    // zero-rest-length spring stays well defined when L -> 0 (d -> 0, n undefined):
    // with L0 = 0 the elastic part is just -k d. Below a length of 1e-9 m the
    // direction is unknown; n = 0 then drops the L0 and damping terms, which is the
    // limit of a zero-length spring and a negligible blip for any other.
    const Vec3 d = pB - pA;
    const Real len = length(d);
    const Vec3 n = len > Real(1e-9) ? d / len : Vec3::zero();
    return -(d - n * restLength) * stiffness - n * (damping * dot(vRel, n));
}

void evaluateForces(WorldImpl& w, double time) {
    if (evaluateBodyForces(w, 0, static_cast<std::uint32_t>(w.awakeBodies.size()))) addCallbackForces(w, time);
    addSpringForces(w);
}

bool evaluateBodyForces(WorldImpl& w, std::uint32_t begin, std::uint32_t end) {
    const Vec3 g = w.settings.gravity;
    bool callbacks = false;
    // Awake bodies only (world_impl.hpp, "Awake list"): a sleeping body's
    // forces are not used until it wakes, and the step re-evaluates them then.
    // Its ForceCallback is not called while it sleeps.
    for (std::uint32_t k = begin; k < end; ++k) {
        const std::uint32_t i = w.awakeBodies[k];
        ForceTorque& out = w.forces[i];
        const BodyParams& p = w.params[i];
        if (p.type != BodyType::Dynamic) {
            out = {};
            continue;
        }
        const BodyMotion& m = w.motion[i];
        Vec3 f = w.applied[i].force + g * (p.mass * p.gravityScale);
        if (p.linearDrag > 0 || p.quadraticDrag > 0) f -= m.v * (p.linearDrag + p.quadraticDrag * length(m.v));
        out.force = f;
        out.torque = w.applied[i].torque;
        callbacks = callbacks || static_cast<bool>(w.cold[i].callback);
    }
    return callbacks;
}

// The callbacks' wrenches, added after the rest of each body's force: the
// additions evaluateForces always did, in the same order.
void addCallbackForces(WorldImpl& w, double time) {
    const Real t = static_cast<Real>(time);
    for (const std::uint32_t i : w.awakeBodies) {
        const BodyParams& p = w.params[i];
        const ForceCallback& cb = w.cold[i].callback;
        if (p.type != BodyType::Dynamic || !cb) continue;
        const BodyMotion& m = w.motion[i];
        const Wrench wr = cb(BodyKinematics{m.com, m.q, m.v, m.w, p.mass, t});
        w.forces[i].force += wr.force;
        w.forces[i].torque += wr.torque;
    }
}

void addSpringForces(WorldImpl& w) {
    for (const SpringData& s : w.springs) {
        if (!s.alive) continue;
        const std::uint32_t a = w.denseOrNone(s.bodyA), b = w.denseOrNone(s.bodyB);
        const Vec3 pA = w.anchorWorld(a, s.localA), pB = w.anchorWorld(b, s.localB);
        Vec3 vA, vB;
        if (a != kNoIndex) vA = w.motion[a].v + cross(w.motion[a].w, pA - w.motion[a].com);
        if (b != kNoIndex) vB = w.motion[b].v + cross(w.motion[b].w, pB - w.motion[b].com);
        const Vec3 f = springForceOnB(pA, pB, vB - vA, s.restLength, s.stiffness, s.damping);
        // A sleeping end keeps its forces untouched (they are not used while it sleeps).
        if (a != kNoIndex && w.params[a].type == BodyType::Dynamic && w.params[a].awake) {
            w.forces[a].force -= f;
            w.forces[a].torque -= cross(pA - w.motion[a].com, f);
        }
        if (b != kNoIndex && w.params[b].type == BodyType::Dynamic && w.params[b].awake) {
            w.forces[b].force += f;
            w.forces[b].torque += cross(pB - w.motion[b].com, f);
        }
    }
}

}  // namespace fulcrum::detail
