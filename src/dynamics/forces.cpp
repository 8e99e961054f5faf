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

bool evaluateBodyForces(BodyStore& w, const Vec3& g, std::uint32_t begin, std::uint32_t end, bool* dragged) {
    bool callbacks = false, drag = false;
    const bool mayHaveCallbacks = w.anyForceCallback;
    // Awake bodies only (body_store.hpp, "Awake list"): a sleeping body's
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
        const Vec3& v = w.state[k + 1].v;
        Vec3 f = w.applied[i].force + g * (p.mass * p.gravityScale);
        if (p.linearDrag > 0 || p.quadraticDrag > 0) {
            f -= v * (p.linearDrag + p.quadraticDrag * length(v));
            drag = true;
        }
        out.force = f;
        out.torque = w.applied[i].torque;
        callbacks = callbacks || (mayHaveCallbacks && static_cast<bool>(w.cold[i].callback));
    }
    if (dragged != nullptr && drag) *dragged = true;
    return callbacks;
}

// The callbacks' wrenches, added after the rest of each body's force: the
// additions evaluateForces always did, in the same order.
void addCallbackForces(BodyStore& w, double time) {
    const Real t = static_cast<Real>(time);
    for (std::size_t k = 0; k < w.awakeBodies.size(); ++k) {
        const std::uint32_t i = w.awakeBodies[k];
        const BodyParams& p = w.params[i];
        const ForceCallback& cb = w.cold[i].callback;
        if (p.type != BodyType::Dynamic || !cb) continue;
        const BodyPose& x = w.pose[k + 1];
        const SolverBody& s = w.state[k + 1];
        const Wrench wr = cb(BodyKinematics{x.com, x.q, s.v, s.w, p.mass, t});
        w.forces[i].force += wr.force;
        w.forces[i].torque += wr.torque;
    }
}

void addSpringForces(BodyStore& w, std::span<const SpringData> springs) {
    for (const SpringData& s : springs) {
        if (!s.alive) continue;
        const std::uint32_t a = w.denseOrNone(s.bodyA), b = w.denseOrNone(s.bodyB);
        const Vec3 pA = w.anchorNow(a, s.localA), pB = w.anchorNow(b, s.localB);
        Vec3 vA, vB;
        if (a != kNoIndex) vA = w.velocityNow(a) + cross(w.angularVelocityNow(a), pA - w.comNow(a));
        if (b != kNoIndex) vB = w.velocityNow(b) + cross(w.angularVelocityNow(b), pB - w.comNow(b));
        const Vec3 f = springForceOnB(pA, pB, vB - vA, s.restLength, s.stiffness, s.damping);
        // A sleeping end keeps its forces untouched (they are not used while it sleeps).
        if (a != kNoIndex && w.params[a].type == BodyType::Dynamic && w.params[a].awake) {
            w.forces[a].force -= f;
            w.forces[a].torque -= cross(pA - w.comNow(a), f);
        }
        if (b != kNoIndex && w.params[b].type == BodyType::Dynamic && w.params[b].awake) {
            w.forces[b].force += f;
            w.forces[b].torque += cross(pB - w.comNow(b), f);
        }
    }
}

}  // namespace fulcrum::detail
