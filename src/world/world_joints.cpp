// Joints: validated and stored with body-local anchors and axes, plus the
// rest pose (relative orientation at creation) that angles are measured from.
// Every type is created by one path (createJointOf), its own fields checked
// and made by its file pair (src/solver/joints/joint_types.hpp lists them);
// a JointDef is first turned into its type's definition. The joint solver (src/solver/joint_solver.hpp) reads them from
// WorldImpl::joints every step and writes back impulses, reaction forces and
// the broken flag. docs/joints.md describes every joint type.
#include <cmath>
#include <limits>

#include "dynamics/validation.hpp"
#include "solver/joints/joint_types.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

using detail::fail;
using detail::formatReal;
using detail::kNoIndex;
using detail::Subject;

namespace {

using detail::validateMotor;
using detail::validateSpring;
using detail::withJointType;

// Whether JointDef::axis means something for the type: its definition has axes.
bool usesAxis(JointType t) {
    return withJointType(t, [](auto type) { return requires(typename decltype(type)::Def d) { d.localAxisA; }; });
}

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
    return detail::resolveHandle(joints, id, where, "JointId", "joint");
}

namespace {

// The poses of a joint's ends now (the static world: none).
detail::JointEnds endsOf(const WorldImpl& w, std::uint32_t a, std::uint32_t b) {
    const auto pose = [&](std::uint32_t dense) {
        return dense == kNoIndex ? detail::EndPose{} : detail::EndPose{w.motion[dense].com, w.motion[dense].q, false};
    };
    return {pose(a), pose(b)};
}

// The dense index of a joint's end (kNoIndex: the static world), checked.
std::uint32_t endpoint(const WorldImpl& w, const Subject& who, BodyId id, const char* field) {
    if (id.isNull()) return kNoIndex;
    if (!w.isLive(id)) {
        fail(who, field, "refers to a body that does not exist or was destroyed (index " + std::to_string(id.index) +
                             ", generation " + std::to_string(id.generation) + ")");
    }
    return w.bodySlots[id.index].dense;
}

std::uint32_t nextJointSlot(const WorldImpl& w) {
    return w.joints.nextSlot();
}

// The checks of a JointDef as they have always been: every field, whatever
// the type (so a definition that was refused still is), errors naming
// JointDef's fields.
void validateJointDef(const WorldImpl& w, const JointDef& def, const Subject& who) {
    if (!detail::isJointType(def.type)) fail(who, "type", "is not a known joint type");
    if (def.bodyB.isNull()) fail(who, "bodyB", "must be a body (only bodyA may be the static world)");
    const std::uint32_t a = endpoint(w, who, def.bodyA, "bodyA");
    const std::uint32_t b = endpoint(w, who, def.bodyB, "bodyB");
    if (a == b) fail(who, "bodyB", "is the same body as bodyA: a joint connects two different bodies");

    detail::requireFinite(who, "anchor", def.anchor);
    detail::requireFinite(who, "anchorB", def.anchorB);
    if (usesAxis(def.type)) {
        detail::requireDirection(who, "axis", def.axis);
    } else {
        detail::requireFinite(who, "axis", def.axis);
    }

    detail::validateLimits(who, def.hasLimits, def.lowerLimit, def.upperLimit, def.type == JointType::Hinge);
    validateMotor(who, def.motor);
    validateSpring(who, def.spring);
    detail::requireFinite(who, "minLength", def.minLength);
    detail::requireFinite(who, "maxLength", def.maxLength);
    detail::requireNonNegative(who, "stiffness", def.stiffness);
    detail::requireNonNegative(who, "damping", def.damping);
    detail::validateConeTwistRanges(who, def.swingLimit, def.twistLower, def.twistUpper);
    detail::requireBreakThreshold(who, "breakForce", def.breakForce);
    detail::requireBreakThreshold(who, "breakTorque", def.breakTorque);
    detail::requireFinite(who, "frictionTorque", def.frictionTorque);
    detail::validateFrictionTorque(who, def.frictionTorque);

    // Distance joints: negative lengths mean "the distance at creation" (joint.hpp);
    // for a soft one (stiffness or damping > 0) a negative limit means "no limit on that side".
    if (def.type == JointType::Distance) {
        const Real d0 = distance(def.anchor, def.anchorB);
        const bool soft = def.stiffness > 0 || def.damping > 0;
        const Real minLength = def.minLength < 0 ? (soft ? 0 : d0) : def.minLength;
        const Real maxLength = def.maxLength < 0 ? (soft ? std::numeric_limits<Real>::infinity() : d0) : def.maxLength;
        if (minLength > maxLength) {
            fail(who, "minLength", "(" + formatReal(minLength) + (def.minLength < 0 ? ", the distance at creation" : "") +
                                       ") is above maxLength (" + formatReal(maxLength) +
                                       (def.maxLength < 0 ? ", the distance at creation" : "") + ")");
        }
    }
}

// The one creation path of every joint type T: the ends and the common
// fields checked here, T's own fields by T::setup (joint_types.hpp), then
// stored. `record`: what World::jointDef reports (a JointDef's own copy),
// else the one T::setup makes.
template <class T>
JointId createJointOf(WorldImpl& w, const typename T::Def& def, const JointDef* record) {
    const std::uint32_t slot = nextJointSlot(w);
    const Subject who{"joint", def.name, slot};
    if (def.bodyB.isNull()) fail(who, "bodyB", "must be a body (only bodyA may be the static world)");
    const std::uint32_t a = endpoint(w, who, def.bodyA, "bodyA");
    const std::uint32_t b = endpoint(w, who, def.bodyB, "bodyB");
    if (a == b) fail(who, "bodyB", "is the same body as bodyA: a joint connects two different bodies");
    detail::requireBreakThreshold(who, "breakForce", def.breakForce);
    detail::requireBreakThreshold(who, "breakTorque", def.breakTorque);
    detail::JointSetup setup = T::setup(def, who, endsOf(w, a, b));
    if (record != nullptr) setup.record = *record;

    detail::JointData& j = w.joints.add();
    j.def = std::move(setup.record);
    j.localAnchorA = setup.localAnchorA;
    j.localAnchorB = setup.localAnchorB;
    j.localAxisA = setup.localAxisA;
    j.localAxisB = setup.localAxisB;
    j.minLength = setup.minLength;
    j.maxLength = setup.maxLength;
    j.restLength = setup.restLength;
    j.localFrameA = setup.localFrameA;
    j.relativeRotation = conjugate(a == kNoIndex ? Quat{} : w.motion[a].q) * w.motion[b].q;
    j.enabled = true;
    j.broken = false;
    j.impulses = {};
    j.reactionForce = {};
    j.reactionTorque = {};
    w.jointSolver.reserve(w.joints.size());
    w.jointSolver.graph().add(w.joints.slots(), slot);
    jointChangedPairs(w, j.def);
    return w.joints.handleOf(slot);
}

}  // namespace

JointId World::createJoint(const JointDef& def) {
    WorldImpl& w = *impl_;
    validateJointDef(w, def, {"joint", def.name, nextJointSlot(w)});
    // The same joint as its type's definition makes (one creation path per type).
    const detail::JointEnds ends = endsOf(w, w.denseOrNone(def.bodyA), w.denseOrNone(def.bodyB));
    return withJointType(def.type, [&](auto type) {
        using T = decltype(type);
        return createJointOf<T>(w, T::fromJointDef(def, ends), &def);
    });
}

JointId World::createJoint(const BallJointDef& def) { return createJointOf<detail::BallJoint>(*impl_, def, nullptr); }
JointId World::createJoint(const HingeJointDef& def) { return createJointOf<detail::HingeJoint>(*impl_, def, nullptr); }
JointId World::createJoint(const SliderJointDef& def) { return createJointOf<detail::SliderJoint>(*impl_, def, nullptr); }
JointId World::createJoint(const DistanceJointDef& def) { return createJointOf<detail::DistanceJoint>(*impl_, def, nullptr); }
JointId World::createJoint(const FixedJointDef& def) { return createJointOf<detail::FixedJoint>(*impl_, def, nullptr); }
JointId World::createJoint(const ConeTwistJointDef& def) {
    return createJointOf<detail::ConeTwistJoint>(*impl_, def, nullptr);
}
JointId World::createJoint(const SixDofJointDef& def) { return createJointOf<detail::SixDofJoint>(*impl_, def, nullptr); }

void World::destroyJoint(JointId id) {
    detail::JointData& j = impl_->resolveJoint(id, "World::destroyJoint");
    impl_->jointSolver.graph().remove(impl_->joints.slots(), id.index);
    j.alive = false;  // already dead for the pairs it stops filtering
    jointChangedPairs(*impl_, j.def);
    impl_->joints.remove(id.index);
}

bool World::isValid(JointId id) const { return impl_->joints.isLive(id); }

std::vector<JointId> World::joints() const {
    std::vector<JointId> out;
    for (std::uint32_t i = 0; i < impl_->joints.size(); ++i) {
        if (impl_->joints[i].alive) out.push_back(impl_->joints.handleOf(i));
    }
    return out;
}

const JointDef& World::jointDef(JointId id) const { return impl_->resolveJoint(id, "World::jointDef").def; }
const std::string& World::name(JointId id) const { return impl_->resolveJoint(id, "World::name").def.name; }

namespace {

detail::JointPose poseOf(const WorldImpl& w, const detail::JointData& j) {
    const std::uint32_t a = w.denseOrNone(j.def.bodyA), b = w.denseOrNone(j.def.bodyB);
    return {w.anchorWorld(b, j.localAnchorB) - w.anchorWorld(a, j.localAnchorA),
            a == kNoIndex ? nullptr : &w.motion[a].q,
            &w.motion[b].q,
            &j.localAxisA,
            &j.relativeRotation,
            &j.minLength,
            &j.maxLength,
            &j.localFrameA,
            &j.def.axes};
}

}  // namespace

Real World::jointError(JointId id) const {
    const detail::JointData& j = impl_->resolveJoint(id, "World::jointError");
    const detail::JointPose pose = poseOf(*impl_, j);
    return withJointType(j.def.type, [&](auto type) { return decltype(type)::error(pose); });
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
    const detail::JointData& j = impl_->resolveJoint(id, "World::jointPosition");
    const detail::JointPose pose = poseOf(*impl_, j);
    return withJointType(j.def.type, [&](auto type) { return decltype(type)::position(pose); });
}

Real World::jointVelocity(JointId id) const {
    const detail::JointData& j = impl_->resolveJoint(id, "World::jointVelocity");
    if (j.def.type != JointType::Hinge && j.def.type != JointType::Slider) return 0;
    const WorldImpl& w = *impl_;
    const std::uint32_t a = w.denseOrNone(j.def.bodyA), b = w.denseOrNone(j.def.bodyB);
    const Vec3 axis = a == kNoIndex ? j.localAxisA : rotate(w.motion[a].q, j.localAxisA);
    const Vec3 wA = a == kNoIndex ? Vec3{} : w.motion[a].w;
    if (j.def.type == JointType::Hinge) return dot(w.motion[b].w - wA, axis);
    // The slider: the anchors' velocities (B's anchor is the point that moves along A's axis).
    const Vec3 pB = w.anchorWorld(b, j.localAnchorB);
    const Vec3 vB = w.motion[b].v + cross(w.motion[b].w, pB - w.motion[b].com);
    const Vec3 vA = a == kNoIndex ? Vec3{} : w.motion[a].v + cross(wA, pB - w.motion[a].com);
    return dot(vB - vA, axis);
}

Real World::jointEffort(JointId id) const {
    const detail::JointData& j = impl_->resolveJoint(id, "World::jointEffort");
    if (!j.enabled || (j.def.type != JointType::Hinge && j.def.type != JointType::Slider)) return 0;
    // The reaction's component along the axis: the spring (drive), motor,
    // friction and limits; the rows holding the other axes act across it.
    // Not the free axis's impulses alone: those carry the held rows' share
    // (solver/joints/coupled_row.hpp), which has a component along the axis
    // (1-2 % of a KR5 arm's gravity torques).
    // The hinge's axis is B's (a robot's joint frame moves with its child
    // link, URDF's convention): the alignment rows carry the torques across
    // the axis (tens of N m in an arm), so A's axis, off B's by the rows'
    // small give, would mix a share of them in (1.3 % of a KR5's shoulder).
    // The slider's is A's, the axis B slides along.
    const WorldImpl& w = *impl_;
    if (j.def.type == JointType::Hinge) {
        const std::uint32_t b = w.denseOrNone(j.def.bodyB);
        return dot(j.reactionTorque, rotate(w.motion[b].q, j.localAxisB));
    }
    const std::uint32_t a = w.denseOrNone(j.def.bodyA);
    const Vec3 axis = a == kNoIndex ? j.localAxisA : rotate(w.motion[a].q, j.localAxisA);
    return dot(j.reactionForce, axis);
}

namespace {

// Wakes the joint's bodies: a changed joint acts on them at once.
void wakeJointBodies(WorldImpl& w, const detail::JointData& j) {
    if (!j.def.bodyA.isNull()) w.wakeBody(w.bodySlots[j.def.bodyA.index].dense);
    w.wakeBody(w.bodySlots[j.def.bodyB.index].dense);
}

Subject subjectOf(const detail::JointData& j, JointId id) { return {"joint", j.def.name, id.index}; }

bool hasFreeAxis(JointType t) {
    return withJointType(t, [](auto type) { return decltype(type)::kHasFreeAxis; });
}

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
    withJointType(j.def.type, [&](auto type) {
        using T = decltype(type);
        if constexpr (T::kHasFreeAxis) {
            T::validateLimits(who, enabled, lower, upper);
        } else {
            fail(who, "limits", std::string("only hinge and slider joints have limits, not ") + toString(j.def.type));
        }
    });
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

void World::setSixDofAxis(JointId id, int axis, const SixDofAxis& settings) {
    detail::JointData& j = impl_->resolveJoint(id, "World::setSixDofAxis");
    const Subject who = subjectOf(j, id);
    if (j.def.type != JointType::SixDof) {
        fail(who, "axes", std::string("only six-DOF joints have six axes, not ") + toString(j.def.type));
    }
    if (axis < 0 || axis >= kSixDofAxes) fail(who, "axis", "must be 0..5 (x, y, z, rx, ry, rz), got " + std::to_string(axis));
    detail::SixDofJoint::validateAxis(who, axis, settings);
    SixDofAxis& current = j.def.axes[static_cast<std::size_t>(axis)];
    // The mode decides the joint's rows and whether the tree solver may take
    // it (all linear axes locked): fixed at creation.
    if (settings.mode != current.mode) {
        fail(who, "mode", std::string("is fixed at creation (") + toString(current.mode) + "), got " + toString(settings.mode));
    }
    current = settings;
    wakeJointBodies(*impl_, j);
}

void World::setConeTwistDrive(JointId id, const ConeTwistDrive& drive) {
    detail::JointData& j = impl_->resolveJoint(id, "World::setConeTwistDrive");
    const Subject who = subjectOf(j, id);
    if (j.def.type != JointType::ConeTwist) {
        fail(who, "drive", std::string("only cone-twist joints have an orientation drive, not ") + toString(j.def.type));
    }
    detail::validateConeTwistDrive(who, drive);
    j.def.coneDrive = drive;
    wakeJointBodies(*impl_, j);
}

SixDofReading World::sixDofReading(JointId id) const {
    const detail::JointData& j = impl_->resolveJoint(id, "World::sixDofReading");
    SixDofReading r;
    if (j.def.type != JointType::SixDof) return r;
    const WorldImpl& w = *impl_;
    const detail::JointPose pose = poseOf(w, j);
    const detail::SixDofGeometry g =
        detail::sixDofGeometry(pose.orientationA(), *pose.qB, j.relativeRotation, j.localFrameA, pose.d);
    const std::uint32_t a = w.denseOrNone(j.def.bodyA), b = w.denseOrNone(j.def.bodyB);
    const Vec3 pB = w.anchorWorld(b, j.localAnchorB);
    const Vec3 wA = a == kNoIndex ? Vec3{} : w.motion[a].w;
    const Vec3 vB = w.motion[b].v + cross(w.motion[b].w, pB - w.motion[b].com);
    const Vec3 vA = a == kNoIndex ? Vec3{} : w.motion[a].v + cross(wA, pB - w.motion[a].com);
    const Vec3 spin = w.motion[b].w - wA;
    const Vec3 force = j.enabled ? j.reactionForce : Vec3{}, torque = j.enabled ? j.reactionTorque : Vec3{};
    for (std::size_t k = 0; k < 3; ++k) {
        r.position[k] = g.linear[k];
        r.velocity[k] = dot(vB - vA, g.linearAxis[k]);
        r.effort[k] = dot(force, g.linearAxis[k]);
        r.position[3 + k] = g.angle[k];
        r.velocity[3 + k] = dot(spin, g.angularRow[k]);
        r.effort[3 + k] = dot(torque, g.gimbal[k]);
    }
    return r;
}

std::span<const JointBreakEvent> World::jointBreakEvents() const { return impl_->jointSolver.breakEvents(); }
std::span<const ContactHitEvent> World::contactHitEvents() const {
    impl_->ensureHitEvents();  // built on first read after a step (world_impl.hpp)
    return impl_->hitEvents;
}

}  // namespace fulcrum
