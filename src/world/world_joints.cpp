// Joints: validated and stored with body-local anchors and axes. They are not
// enforced yet: the constraint solver (a later issue) reads JointData from
// WorldImpl::joints and solves them in stage 3 of the sub-step (step.cpp).
// jointError already reports the geometric violation, so tools and tests can
// watch it.
#include <cmath>
#include <numbers>

#include "dynamics/validation.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

using detail::fail;
using detail::formatReal;
using detail::kNoIndex;
using detail::Subject;

namespace {

// Finite or +infinity, and positive (break thresholds: infinity means unbreakable).
void requireBreakThreshold(const Subject& who, const char* field, Real v) {
    if (std::isnan(v) || v <= 0 || v == -std::numeric_limits<Real>::infinity()) {
        fail(who, field, "must be positive (or +infinity for unbreakable), got " + formatReal(v));
    }
}

bool usesAxis(JointType t) { return t == JointType::Hinge || t == JointType::Slider || t == JointType::ConeTwist; }

// A joint between two bodies changes whether they may collide (unless it
// keeps collideConnected): drop A's contacts and let the broad phase report
// its pairs anew under the new rule. Joined bodies wake.
void jointChangedPairs(WorldImpl& w, const JointDef& def) {
    if (!def.bodyA.isNull()) w.wakeBody(w.bodySlots[def.bodyA.index].dense);
    if (!def.bodyB.isNull()) w.wakeBody(w.bodySlots[def.bodyB.index].dense);
    if (def.bodyA.isNull() || def.bodyB.isNull() || def.collideConnected) return;
    w.contactManager.resetPairs(w, def.bodyA.index);
}

}  // namespace

detail::JointData& WorldImpl::resolveJoint(JointId id, const char* where) {
    return const_cast<detail::JointData&>(static_cast<const WorldImpl*>(this)->resolveJoint(id, where));
}

const detail::JointData& WorldImpl::resolveJoint(JointId id, const char* where) const {
    if (id.isNull()) throw Error(std::string(where) + ": null JointId");
    if (id.index >= joints.size()) {
        throw Error(std::string(where) + ": JointId index " + std::to_string(id.index) + " does not exist");
    }
    const detail::JointData& j = joints[id.index];
    if (!j.alive || j.generation != id.generation) {
        throw Error(std::string(where) + ": stale JointId (index " + std::to_string(id.index) +
                    "): that joint was destroyed (or one of its bodies was)");
    }
    return j;
}

JointId World::createJoint(const JointDef& def) {
    WorldImpl& w = *impl_;
    const std::uint32_t slot =
        w.freeJointSlots.empty() ? static_cast<std::uint32_t>(w.joints.size()) : w.freeJointSlots.back();
    const Subject who{"joint", def.name, slot};

    switch (def.type) {
        case JointType::Ball:
        case JointType::Hinge:
        case JointType::Slider:
        case JointType::Distance:
        case JointType::Fixed:
        case JointType::ConeTwist: break;
        default: fail(who, "type", "is not a known joint type");
    }
    if (def.bodyB.isNull()) fail(who, "bodyB", "must be a body (only bodyA may be the static world)");
    auto endpoint = [&](BodyId id, const char* field) -> std::uint32_t {
        if (id.isNull()) return kNoIndex;
        if (!w.isLive(id)) {
            fail(who, field, "refers to a body that does not exist or was destroyed (index " + std::to_string(id.index) +
                                 ", generation " + std::to_string(id.generation) + ")");
        }
        return w.bodySlots[id.index].dense;
    };
    const std::uint32_t a = endpoint(def.bodyA, "bodyA");
    const std::uint32_t b = endpoint(def.bodyB, "bodyB");
    if (a == b) fail(who, "bodyB", "is the same body as bodyA: a joint connects two different bodies");

    detail::requireFinite(who, "anchor", def.anchor);
    detail::requireFinite(who, "anchorB", def.anchorB);
    Vec3 axis = normalize(def.axis);
    if (usesAxis(def.type)) {
        axis = detail::requireDirection(who, "axis", def.axis);
    } else {
        detail::requireFinite(who, "axis", def.axis);
    }

    detail::requireFinite(who, "lowerLimit", def.lowerLimit);
    detail::requireFinite(who, "upperLimit", def.upperLimit);
    if (def.hasLimits && def.lowerLimit > def.upperLimit) {
        fail(who, "lowerLimit", "(" + formatReal(def.lowerLimit) + ") is above upperLimit (" + formatReal(def.upperLimit) + ")");
    }
    detail::requireFinite(who, "motor.speed", def.motor.speed);
    detail::requireNonNegative(who, "motor.maxForce", def.motor.maxForce);
    detail::requireFinite(who, "spring.target", def.spring.target);
    detail::requireNonNegative(who, "spring.stiffness", def.spring.stiffness);
    detail::requireNonNegative(who, "spring.damping", def.spring.damping);
    detail::requireFinite(who, "minLength", def.minLength);
    detail::requireFinite(who, "maxLength", def.maxLength);
    detail::requireNonNegative(who, "stiffness", def.stiffness);
    detail::requireNonNegative(who, "damping", def.damping);
    detail::requireFinite(who, "swingLimit", def.swingLimit);
    if (def.swingLimit < 0 || def.swingLimit > std::numbers::pi_v<Real>) {
        fail(who, "swingLimit", "must be in [0, pi] radians, got " + formatReal(def.swingLimit));
    }
    detail::requireFinite(who, "twistLower", def.twistLower);
    detail::requireFinite(who, "twistUpper", def.twistUpper);
    if (def.twistLower > def.twistUpper) {
        fail(who, "twistLower", "(" + formatReal(def.twistLower) + ") is above twistUpper (" + formatReal(def.twistUpper) + ")");
    }
    requireBreakThreshold(who, "breakForce", def.breakForce);
    requireBreakThreshold(who, "breakTorque", def.breakTorque);

    // Distance joints: negative lengths mean "the distance at creation" (joint.hpp).
    const Vec3 worldAnchorB = def.type == JointType::Distance ? def.anchorB : def.anchor;
    Real minLength = 0, maxLength = 0;
    if (def.type == JointType::Distance) {
        const Real d0 = distance(def.anchor, def.anchorB);
        minLength = def.minLength < 0 ? d0 : def.minLength;
        maxLength = def.maxLength < 0 ? d0 : def.maxLength;
        if (minLength > maxLength) {
            fail(who, "minLength", "(" + formatReal(minLength) + (def.minLength < 0 ? ", the distance at creation" : "") +
                                       ") is above maxLength (" + formatReal(maxLength) +
                                       (def.maxLength < 0 ? ", the distance at creation" : "") + ")");
        }
    }

    auto localPoint = [&](std::uint32_t dense, const Vec3& p) {
        return dense == kNoIndex ? p : inverseRotate(w.motion[dense].q, p - w.motion[dense].com);
    };
    auto localAxis = [&](std::uint32_t dense, const Vec3& v) {
        return dense == kNoIndex ? v : inverseRotate(w.motion[dense].q, v);
    };
    if (slot == w.joints.size()) {
        w.joints.emplace_back();
    } else {
        w.freeJointSlots.pop_back();
    }
    detail::JointData& j = w.joints[slot];
    j.alive = true;
    j.def = def;
    j.localAnchorA = localPoint(a, def.anchor);
    j.localAnchorB = localPoint(b, worldAnchorB);
    j.localAxisA = localAxis(a, axis);
    j.localAxisB = localAxis(b, axis);
    j.minLength = minLength;
    j.maxLength = maxLength;
    jointChangedPairs(w, j.def);
    return {slot, j.generation};
}

void World::destroyJoint(JointId id) {
    detail::JointData& j = impl_->resolveJoint(id, "World::destroyJoint");
    j.alive = false;
    jointChangedPairs(*impl_, j.def);
    ++j.generation;
    impl_->freeJointSlots.push_back(id.index);
}

bool World::isValid(JointId id) const {
    const WorldImpl& w = *impl_;
    return !id.isNull() && id.index < w.joints.size() && w.joints[id.index].alive &&
           w.joints[id.index].generation == id.generation;
}

std::vector<JointId> World::joints() const {
    std::vector<JointId> out;
    for (std::uint32_t i = 0; i < impl_->joints.size(); ++i) {
        if (impl_->joints[i].alive) out.push_back({i, impl_->joints[i].generation});
    }
    return out;
}

const JointDef& World::jointDef(JointId id) const { return impl_->resolveJoint(id, "World::jointDef").def; }
const std::string& World::name(JointId id) const { return impl_->resolveJoint(id, "World::name").def.name; }

Real World::jointError(JointId id) const {
    const WorldImpl& w = *impl_;
    const detail::JointData& j = w.resolveJoint(id, "World::jointError");
    const std::uint32_t a = w.denseOrNone(j.def.bodyA), b = w.denseOrNone(j.def.bodyB);
    const Vec3 pA = w.anchorWorld(a, j.localAnchorA), pB = w.anchorWorld(b, j.localAnchorB);
    const Vec3 d = pB - pA;
    switch (j.def.type) {
        case JointType::Distance: {
            const Real len = length(d);
            if (len < j.minLength) return j.minLength - len;
            if (len > j.maxLength) return len - j.maxLength;
            return 0;
        }
        case JointType::Slider: {
            // Only motion along the axis (fixed in body A) is free.
            const Vec3 axis = a == kNoIndex ? j.localAxisA : rotate(w.motion[a].q, j.localAxisA);
            return length(d - axis * dot(d, axis));
        }
        case JointType::Ball:
        case JointType::Hinge:
        case JointType::Fixed:
        case JointType::ConeTwist: return length(d);
    }
    return 0;
}

}  // namespace fulcrum
