// Joints: validated and stored with body-local anchors and axes, plus the
// rest pose (relative orientation at creation) that angles are measured from.
// The joint solver (src/solver/joint_solver.hpp) reads them from
// WorldImpl::joints every step and writes back impulses, reaction forces and
// the broken flag. docs/joints.md describes every joint type.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "dynamics/validation.hpp"
#include "solver/joints/joint_common.hpp"
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

constexpr Real kPi = std::numbers::pi_v<Real>;

void validateLimits(const Subject& who, JointType type, bool enabled, Real lower, Real upper) {
    detail::requireFinite(who, "lowerLimit", lower);
    detail::requireFinite(who, "upperLimit", upper);
    if (!enabled) return;
    if (lower > upper) {
        fail(who, "lowerLimit", "(" + formatReal(lower) + ") is above upperLimit (" + formatReal(upper) + ")");
    }
    // Hinge angles are measured in (-pi, pi]: a limit outside can never be reached.
    if (type == JointType::Hinge && (lower < -kPi || upper > kPi)) {
        fail(who, lower < -kPi ? "lowerLimit" : "upperLimit",
             "must be within [-pi, pi] radians for a hinge, got [" + formatReal(lower) + ", " + formatReal(upper) + "]");
    }
}

void validateMotor(const Subject& who, const JointMotor& m) {
    detail::requireFinite(who, "motor.speed", m.speed);
    detail::requireNonNegative(who, "motor.maxForce", m.maxForce);
}

void validateSpring(const Subject& who, const JointSpring& s) {
    detail::requireFinite(who, "spring.target", s.target);
    detail::requireNonNegative(who, "spring.stiffness", s.stiffness);
    detail::requireNonNegative(who, "spring.damping", s.damping);
}

bool hasFreeAxis(JointType t) { return t == JointType::Hinge || t == JointType::Slider; }

// A joint between two bodies changes whether they may collide (unless it
// keeps collideConnected): drop A's contacts and let the broad phase report
// its pairs anew under the new rule. Joined bodies wake.
void jointChangedPairs(WorldImpl& w, const JointDef& def) {
    if (!def.bodyA.isNull()) w.wakeBody(w.bodySlots[def.bodyA.index].dense);
    if (!def.bodyB.isNull()) w.wakeBody(w.bodySlots[def.bodyB.index].dense);
    if (def.bodyA.isNull() || def.bodyB.isNull() || def.collideConnected) return;
    w.ensureContactReport();  // the last step's report still holds the contacts dropped here
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

    validateLimits(who, def.type, def.hasLimits, def.lowerLimit, def.upperLimit);
    validateMotor(who, def.motor);
    validateSpring(who, def.spring);
    detail::requireFinite(who, "minLength", def.minLength);
    detail::requireFinite(who, "maxLength", def.maxLength);
    detail::requireNonNegative(who, "stiffness", def.stiffness);
    detail::requireNonNegative(who, "damping", def.damping);
    detail::requireFinite(who, "swingLimit", def.swingLimit);
    if (def.swingLimit <= 0 || def.swingLimit > kPi) {
        fail(who, "swingLimit", "must be in (0, pi] radians (pi: no cone), got " + formatReal(def.swingLimit));
    }
    detail::requireFinite(who, "twistLower", def.twistLower);
    detail::requireFinite(who, "twistUpper", def.twistUpper);
    if (def.twistLower > def.twistUpper) {
        fail(who, "twistLower", "(" + formatReal(def.twistLower) + ") is above twistUpper (" + formatReal(def.twistUpper) + ")");
    }
    if (def.twistLower < -kPi || def.twistUpper > kPi) {
        fail(who, def.twistLower < -kPi ? "twistLower" : "twistUpper",
             "must be within [-pi, pi] radians, got [" + formatReal(def.twistLower) + ", " + formatReal(def.twistUpper) + "]");
    }
    requireBreakThreshold(who, "breakForce", def.breakForce);
    requireBreakThreshold(who, "breakTorque", def.breakTorque);
    detail::requireFinite(who, "frictionTorque", def.frictionTorque);
    detail::requireNonNegative(who, "frictionTorque", def.frictionTorque);

    // Distance joints: negative lengths mean "the distance at creation" (joint.hpp);
    // for a soft one (stiffness or damping > 0) the spring's rest length is the
    // distance at creation and a negative limit means "no limit on that side".
    const Vec3 worldAnchorB = def.type == JointType::Distance ? def.anchorB : def.anchor;
    Real minLength = 0, maxLength = 0, restLength = 0;
    if (def.type == JointType::Distance) {
        const Real d0 = distance(def.anchor, def.anchorB);
        const bool soft = def.stiffness > 0 || def.damping > 0;
        minLength = def.minLength < 0 ? (soft ? 0 : d0) : def.minLength;
        maxLength = def.maxLength < 0 ? (soft ? std::numeric_limits<Real>::infinity() : d0) : def.maxLength;
        restLength = std::clamp(d0, minLength, maxLength);
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
    j.restLength = restLength;
    j.relativeRotation = conjugate(a == kNoIndex ? Quat{} : w.motion[a].q) * w.motion[b].q;
    j.enabled = true;
    j.broken = false;
    j.impulses = {};
    j.reactionForce = {};
    j.reactionTorque = {};
    w.jointSolver.reserve(w.joints.size());
    w.jointSolver.graph().add(w.joints, slot);
    jointChangedPairs(w, j.def);
    return {slot, j.generation};
}

void World::destroyJoint(JointId id) {
    detail::JointData& j = impl_->resolveJoint(id, "World::destroyJoint");
    impl_->jointSolver.graph().remove(impl_->joints, id.index);
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

Vec3 World::jointReactionForce(JointId id) const {
    const detail::JointData& j = impl_->resolveJoint(id, "World::jointReactionForce");
    return j.enabled ? j.reactionForce : Vec3{};
}

Vec3 World::jointReactionTorque(JointId id) const {
    const detail::JointData& j = impl_->resolveJoint(id, "World::jointReactionTorque");
    return j.enabled ? j.reactionTorque : Vec3{};
}

Real World::jointPosition(JointId id) const {
    const WorldImpl& w = *impl_;
    const detail::JointData& j = w.resolveJoint(id, "World::jointPosition");
    const std::uint32_t a = w.denseOrNone(j.def.bodyA), b = w.denseOrNone(j.def.bodyB);
    const Quat qA = a == kNoIndex ? Quat{} : w.motion[a].q;
    const Quat qB = w.motion[b].q;
    const Vec3 d = w.anchorWorld(b, j.localAnchorB) - w.anchorWorld(a, j.localAnchorA);
    switch (j.def.type) {
        case JointType::Hinge:
        case JointType::ConeTwist: return detail::twistAngle(j.relativeRotation, qA, qB, j.localAxisA);
        case JointType::Slider: return dot(d, rotate(qA, j.localAxisA));
        case JointType::Distance: return length(d);
        case JointType::Ball:
        case JointType::Fixed: return 0;
    }
    return 0;
}

namespace {

// Wakes the joint's bodies: a changed joint acts on them at once.
void wakeJointBodies(WorldImpl& w, const detail::JointData& j) {
    if (!j.def.bodyA.isNull()) w.wakeBody(w.bodySlots[j.def.bodyA.index].dense);
    w.wakeBody(w.bodySlots[j.def.bodyB.index].dense);
}

Subject subjectOf(const detail::JointData& j, JointId id) { return {"joint", j.def.name, id.index}; }

}  // namespace

void World::setJointEnabled(JointId id, bool enabled) {
    detail::JointData& j = impl_->resolveJoint(id, "World::setJointEnabled");
    if (j.enabled == enabled) return;
    j.enabled = enabled;
    j.broken = false;
    j.impulses = {};
    j.reactionForce = {};
    j.reactionTorque = {};
    // Whether the joined bodies may collide changes with it.
    jointChangedPairs(*impl_, j.def);
}

bool World::isJointEnabled(JointId id) const { return impl_->resolveJoint(id, "World::isJointEnabled").enabled; }
bool World::isJointBroken(JointId id) const { return impl_->resolveJoint(id, "World::isJointBroken").broken; }

void World::setJointMotor(JointId id, const JointMotor& motor) {
    detail::JointData& j = impl_->resolveJoint(id, "World::setJointMotor");
    const Subject who = subjectOf(j, id);
    if (!hasFreeAxis(j.def.type)) fail(who, "motor", std::string("only hinge and slider joints have a motor, not ") + toString(j.def.type));
    validateMotor(who, motor);
    j.def.motor = motor;
    wakeJointBodies(*impl_, j);
}

void World::setJointLimits(JointId id, bool enabled, Real lower, Real upper) {
    detail::JointData& j = impl_->resolveJoint(id, "World::setJointLimits");
    const Subject who = subjectOf(j, id);
    if (!hasFreeAxis(j.def.type)) fail(who, "limits", std::string("only hinge and slider joints have limits, not ") + toString(j.def.type));
    validateLimits(who, j.def.type, enabled, lower, upper);
    j.def.hasLimits = enabled;
    j.def.lowerLimit = lower;
    j.def.upperLimit = upper;
    wakeJointBodies(*impl_, j);
}

void World::setJointSpring(JointId id, const JointSpring& spring) {
    detail::JointData& j = impl_->resolveJoint(id, "World::setJointSpring");
    const Subject who = subjectOf(j, id);
    if (!hasFreeAxis(j.def.type)) fail(who, "spring", std::string("only hinge and slider joints have a spring, not ") + toString(j.def.type));
    validateSpring(who, spring);
    j.def.spring = spring;
    wakeJointBodies(*impl_, j);
}

std::span<const JointBreakEvent> World::jointBreakEvents() const { return impl_->jointSolver.breakEvents(); }

}  // namespace fulcrum
