// World: settings, body lifetime, getters and setters, user forces and
// impulses. Everything here is API boundary: validate, then touch WorldImpl.
// Springs and joints live in world_springs.cpp and world_joints.cpp, the step
// in step.cpp, diagnostics in diagnostics.cpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <new>

#include "dynamics/body_mass.hpp"
#include "dynamics/validation.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

using detail::fail;
using detail::formatReal;
using detail::kNoIndex;
using detail::requireFinite;
using detail::requireNonNegative;
using detail::requirePositive;
using detail::Subject;

namespace {

constexpr Subject kWorldSubject{"world", "", kNoIndex};

void validateMaxContactPairs(std::int64_t limit) {
    if (limit < 0 || limit > kMaxContactPairs) {
        fail(kWorldSubject, "maxContactPairs",
             "must be 0 (automatic: " + std::to_string(kAutoContactPairsPerBody) + " per body plus " +
                 std::to_string(kAutoContactPairsBase) + ") or a pair count from 1 to " +
                 std::to_string(kMaxContactPairs) + ", got " + std::to_string(limit));
    }
}

void requireCount(std::string_view field, int value, int most) {
    if (value < 1) fail(kWorldSubject, field, "must be at least 1, got " + std::to_string(value));
    if (value > most) fail(kWorldSubject, field, "must be at most " + std::to_string(most) + ", got " + std::to_string(value));
}

void validateSettings(const WorldDef& def) {
    requireFinite(kWorldSubject, "gravity", def.gravity);
    requireCount("substeps", def.substeps, kMaxSubsteps);
    requireCount("solverIterations", def.solverIterations, kMaxSolverIterations);
    requireCount("threads", def.threads, kMaxThreads);
    switch (def.integrator) {
        case Integrator::ExplicitEuler:
        case Integrator::SemiImplicitEuler:
        case Integrator::Verlet: break;
        default: fail(kWorldSubject, "integrator", "is not a known integrator");
    }
    requirePositive(kWorldSubject, "contactHertz", def.contactHertz);
    requirePositive(kWorldSubject, "contactDampingRatio", def.contactDampingRatio);
    requirePositive(kWorldSubject, "contactPushMaxVelocity", def.contactPushMaxVelocity);
    requireNonNegative(kWorldSubject, "speculativeMargin", def.speculativeMargin);
    requireNonNegative(kWorldSubject, "restitutionThreshold", def.restitutionThreshold);
    requireNonNegative(kWorldSubject, "hitEventThreshold", def.hitEventThreshold);
    requirePositive(kWorldSubject, "jointHertz", def.jointHertz);
    requirePositive(kWorldSubject, "jointDampingRatio", def.jointDampingRatio);
    if (!(def.maxRotationPerSubstep > 0)) fail(kWorldSubject, "maxRotationPerSubstep", "must be > 0 (inf: no limit), got " + detail::formatReal(def.maxRotationPerSubstep));
    if (!(def.jointProjectionSlop >= 0)) fail(kWorldSubject, "jointProjectionSlop", "must be >= 0 (inf: no projection), got " + detail::formatReal(def.jointProjectionSlop));
    requireNonNegative(kWorldSubject, "linearSleepVelocity", def.linearSleepVelocity);
    requireNonNegative(kWorldSubject, "angularSleepVelocity", def.angularSleepVelocity);
    requireNonNegative(kWorldSubject, "timeToSleep", def.timeToSleep);
    validateMaxContactPairs(def.maxContactPairs);
}

Subject subjectOf(const WorldImpl& w, std::uint32_t dense) {
    return {"body", w.cold[dense].name, w.denseToSlot[dense]};
}

}  // namespace

// ---------------------------------------------------------------- World: lifetime and settings

World::World(const WorldDef& def) : impl_(std::make_unique<WorldImpl>()) {
    validateSettings(def);
    impl_->settings = def;
}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

const WorldDef& World::settings() const { return impl_->settings; }

void World::setGravity(const Vec3& g) {
    requireFinite(kWorldSubject, "gravity", g);
    impl_->settings.gravity = g;
}
void World::setIntegrator(Integrator integrator) {
    WorldDef d = impl_->settings;
    d.integrator = integrator;
    validateSettings(d);
    impl_->settings.integrator = integrator;
}
void World::setSubsteps(int substeps) {
    requireCount("substeps", substeps, kMaxSubsteps);
    impl_->settings.substeps = substeps;
}
void World::setSolverIterations(int iterations) {
    requireCount("solverIterations", iterations, kMaxSolverIterations);
    impl_->settings.solverIterations = iterations;
}
void World::setSleepingEnabled(bool enabled) { impl_->settings.sleeping = enabled; }  // the step wakes all when off
void World::setThreadCount(int threads) {
    requireCount("threads", threads, kMaxThreads);
    impl_->settings.threads = threads;
}
void World::setParallelMinBodies(std::uint32_t minimum) { impl_->settings.parallelMinBodies = minimum; }
void World::setHitEventThreshold(Real threshold) {
    requireNonNegative(kWorldSubject, "hitEventThreshold", threshold);
    impl_->settings.hitEventThreshold = threshold;
    impl_->hitEvents.clear();  // the last step's were chosen by the old threshold: built anew when read
    impl_->hitEventsStale = !impl_->contactSolver.pairs().empty();
}
void World::setPushOutGrownOverlaps(bool enabled) { impl_->settings.pushOutGrownOverlaps = enabled; }
void World::setMaxContactPairs(std::int64_t limit) {
    validateMaxContactPairs(limit);
    impl_->settings.maxContactPairs = limit;
}
void World::setTaskSystem(TaskSystem* tasks) { impl_->userTasks = tasks; }

// ---------------------------------------------------------------- bodies

BodyId World::createBody(const BodyDef& def) {
    WorldImpl& w = *impl_;
    const std::uint32_t slotIndex =
        w.freeBodySlots.empty() ? static_cast<std::uint32_t>(w.bodySlots.size()) : w.freeBodySlots.back();
    const Subject who{"body", def.name, slotIndex};

    switch (def.type) {
        case BodyType::Static:
        case BodyType::Kinematic:
        case BodyType::Dynamic: break;
        default: fail(who, "type", "is not static, kinematic or dynamic");
    }
    if (def.type != BodyType::Static && def.shape.staticOnly()) {
        fail(who, "shape", std::string("is a ") + toString(def.shape.type()) +
                               " (or holds one), which only static bodies may have; this body is " + toString(def.type) +
                               (def.shape.type() == ShapeType::Mesh
                                    ? " (for a concave dynamic body, make a closed mesh a compound of convex hulls with "
                                      "Shape::convexDecomposition; Python: fulcrum.Compound.from_mesh)"
                                    : ""));
    }
    // Every value tested at once; field by field, so that the first bad one
    // names itself, only when that test fails (the checks one call each were
    // ~300 instructions a body of a million static boxes).
    const auto finiteNonNegative = [](Real v) { return v >= 0 && v <= std::numeric_limits<Real>::max(); };
    const bool plainValues = isFinite(def.position) && isFinite(def.linearVelocity) && isFinite(def.angularVelocity) &&
                             finiteNonNegative(def.friction) && finiteNonNegative(def.restitution) &&
                             finiteNonNegative(def.rollingResistance) && finiteNonNegative(def.linearDamping) &&
                             finiteNonNegative(def.angularDamping) && finiteNonNegative(def.linearDrag) &&
                             finiteNonNegative(def.quadraticDrag) && std::isfinite(def.gravityScale);
    if (!plainValues) {
        requireFinite(who, "position", def.position);
        detail::requireOrientation(who, "orientation", def.orientation);
        requireFinite(who, "linearVelocity", def.linearVelocity);
        requireFinite(who, "angularVelocity", def.angularVelocity);
        requireNonNegative(who, "friction", def.friction);
        requireNonNegative(who, "restitution", def.restitution);
        requireNonNegative(who, "rollingResistance", def.rollingResistance);
        requireNonNegative(who, "linearDamping", def.linearDamping);
        requireNonNegative(who, "angularDamping", def.angularDamping);
        requireNonNegative(who, "linearDrag", def.linearDrag);
        requireNonNegative(who, "quadraticDrag", def.quadraticDrag);
        requireFinite(who, "gravityScale", def.gravityScale);
    }
    const Quat q = detail::requireOrientation(who, "orientation", def.orientation);
    const detail::BodyMass mass = detail::computeBodyMass(def, who);

    // All checks passed: nothing below throws except allocation.
    const std::uint32_t dense = static_cast<std::uint32_t>(w.motion.size());
    detail::BodyMotion m;
    m.q = q;
    m.com = def.position + rotate(q, mass.localCenterOfMass);
    if (def.type != BodyType::Static) {
        m.v = def.linearVelocity;
        m.w = def.angularVelocity;
    }
    m.invMass = mass.invMass;
    detail::BodyParams p;
    p.type = def.type;
    p.awake = def.type == BodyType::Static ? false : def.awake;
    p.allowSleep = def.allowSleep;
    p.isSensor = def.isSensor;
    p.isBullet = def.isBullet;
    p.mass = mass.mass;
    p.localCom = mass.localCenterOfMass;
    p.localInertia = mass.localInertia;
    p.invLocalInertia = mass.invLocalInertia;
    p.linearDamping = def.linearDamping;
    p.angularDamping = def.angularDamping;
    p.linearDrag = def.linearDrag;
    p.quadraticDrag = def.quadraticDrag;
    p.gravityScale = def.gravityScale;
    p.friction = def.friction;
    p.restitution = def.restitution;
    p.rollingResistance = def.rollingResistance;
    p.filter = def.filter;
    if (def.type != BodyType::Static) {
        const AABB b = def.shape.localBounds();
        p.extent = length(max(abs(b.min - p.localCom), abs(b.max - p.localCom)));
    }
    detail::BodyCold c;
    c.name = def.name;
    c.shape = def.shape;
    c.creationSerial = w.nextBodySerial++;

    w.motion.push_back(m);
    w.forces.push_back({});
    w.applied.push_back({});
    w.params.push_back(p);
    w.cold.push_back(std::move(c));
    w.previous.push_back({def.position, q});
    w.denseToSlot.push_back(slotIndex);
    w.scratch.push_back({});
    // A static body's inverse inertia is zero in the body frame and in the
    // world's: the record's default (Mat3::zero()) is it. Nothing reads a
    // static record's (its solver body is entry 0 of the awake set), so the
    // rotation of a zero matrix, ~200 instructions, is left out.
    if (p.type != BodyType::Static) w.updateWorldInertia(dense);

    if (slotIndex == w.bodySlots.size()) {
        w.bodySlots.push_back({dense, 0});
    } else {
        w.freeBodySlots.pop_back();
        w.bodySlots[slotIndex].dense = dense;
    }
    w.contactManager.addBody(w, dense);
    // The new body is the last dense index: queued like a woken body, its previous[] like a teleport.
    w.reserveAwakeList(w.motion.size());
    if (!w.awakeListRebuild) {
        w.inAwakeList.push_back(0);
        if (p.awake && p.type != BodyType::Static) w.wokenBodies.push_back(dense);
    }
    w.markPreviousStale(dense);
    const std::size_t bufferBodies = w.contactManager.bufferBodyCount();
    // The buffers only grow, so reserving again for the same count, pair
    // limit and step is a no-op; static bodies made after as many moving ones
    // leave the count as it is (a million static boxes: ~550 instructions a
    // body of capacity checks saved).
    const WorldImpl::ReservedFor want{bufferBodies, w.settings.maxContactPairs, w.stepCount};
    if (!(want == w.reservedFor)) {
        w.contactManager.reserve(bufferBodies, w.settings.maxContactPairs, w.contacts);
        w.contactSolver.reserve(bufferBodies);
        w.sleepManager.reserve(bufferBodies);
        w.reservedFor = want;
    }
    return {slotIndex, w.bodySlots[slotIndex].generation};
}

void World::reserveBodies(std::size_t count) {
    WorldImpl& w = *impl_;
    if (count > std::size_t{UINT32_MAX} - 1 - w.motion.size()) {
        fail(kWorldSubject, "reserveBodies count", "exceeds the most bodies a world holds (2^32 - 2), got " + std::to_string(count));
    }
    const std::size_t total = w.motion.size() + count;
    w.motion.reserve(total);
    w.forces.reserve(total);
    w.applied.reserve(total);
    w.params.reserve(total);
    w.cold.reserve(total);
    w.previous.reserve(total);
    w.denseToSlot.reserve(total);
    w.scratch.reserve(total);
    w.bodySlots.reserve(w.bodySlots.size() + count);
    w.inAwakeList.reserve(total);
    w.contactManager.reserveBodies(w.bodySlots.capacity(), total);
}

void World::destroyBody(BodyId id) {
    WorldImpl& w = *impl_;
    const std::uint32_t dense = w.resolveBody(id, "World::destroyBody");
    for (const std::uint32_t slot : w.characters.order) {
        if (w.characters.pool[slot].body == id) {
            fail(subjectOf(w, dense), "body", "is a character's capsule: destroy the character (World::destroyCharacter) instead");
        }
    }

    // Springs and joints attached to the body go with it, so they never hold a stale handle.
    for (std::uint32_t i = 0; i < w.springs.size(); ++i) {
        detail::SpringData& s = w.springs[i];
        if (s.alive && (s.bodyA == id || s.bodyB == id)) destroySpring({i, s.generation});
    }
    // The scan of every joint slot only where the body may have joints (rain
    // destroys a ragdoll's joints first: each of its bodies scanned ~4,000
    // joint slots for none, 1 % of the step's instructions; docs/benchmarks.md,
    // the `rain10` block).
    if (w.jointSolver.graph().mayHaveJoints(w.joints.slots(), id.index)) {
        for (std::uint32_t i = 0; i < w.joints.size(); ++i) {
            detail::JointData& j = w.joints[i];
            if (j.alive && (j.def.bodyA == id || j.def.bodyB == id)) destroyJoint({i, j.generation});
        }
    }

    detail::detachParticlesFromBody(w, id.index);  // no particle keeps the slot (world/particle_coupling.hpp)
    w.ensureContactReport();  // the last step's report still names this body's contacts
    w.contactManager.removeBody(w, id.index);
    w.invalidateAwakeList();  // the swap-remove below renumbers a body

    // Swap-remove from the dense arrays.
    const std::uint32_t last = static_cast<std::uint32_t>(w.motion.size() - 1);
    if (dense != last) {
        w.motion[dense] = w.motion[last];
        w.forces[dense] = w.forces[last];
        w.applied[dense] = w.applied[last];
        w.params[dense] = w.params[last];
        w.cold[dense] = std::move(w.cold[last]);
        w.previous[dense] = w.previous[last];
        w.denseToSlot[dense] = w.denseToSlot[last];
        w.scratch[dense] = w.scratch[last];
        w.bodySlots[w.denseToSlot[dense]].dense = dense;
    }
    w.motion.pop_back();
    w.forces.pop_back();
    w.applied.pop_back();
    w.params.pop_back();
    w.cold.pop_back();
    w.previous.pop_back();
    w.denseToSlot.pop_back();
    w.scratch.pop_back();

    detail::BodySlot& slot = w.bodySlots[id.index];
    slot.dense = kNoIndex;
    ++slot.generation;
    w.freeBodySlots.push_back(id.index);
}

bool World::isValid(BodyId id) const { return impl_->isLive(id); }
std::size_t World::bodyCount() const { return impl_->motion.size(); }

std::vector<BodyId> World::bodies() const {
    const WorldImpl& w = *impl_;
    std::vector<std::uint32_t> order(w.motion.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return w.cold[a].creationSerial < w.cold[b].creationSerial; });
    std::vector<BodyId> out;
    out.reserve(order.size());
    for (std::uint32_t d : order) out.push_back(w.idOfDense(d));
    return out;
}

BodyId World::findBody(std::string_view name) const {
    const WorldImpl& w = *impl_;
    std::uint32_t best = kNoIndex;
    for (std::uint32_t i = 0; i < w.cold.size(); ++i) {
        if (w.cold[i].name == name && (best == kNoIndex || w.cold[i].creationSerial < w.cold[best].creationSerial)) best = i;
    }
    return best == kNoIndex ? BodyId{} : w.idOfDense(best);
}

const std::string& World::name(BodyId id) const { return impl_->cold[impl_->resolveBody(id, "World::name")].name; }
BodyType World::bodyType(BodyId id) const { return impl_->params[impl_->resolveBody(id, "World::bodyType")].type; }
const Shape& World::shape(BodyId id) const { return impl_->cold[impl_->resolveBody(id, "World::shape")].shape; }
Real World::mass(BodyId id) const { return impl_->params[impl_->resolveBody(id, "World::mass")].mass; }
Mat3 World::localInertia(BodyId id) const {
    return impl_->params[impl_->resolveBody(id, "World::localInertia")].localInertia;
}
Vec3 World::localCenterOfMass(BodyId id) const {
    return impl_->params[impl_->resolveBody(id, "World::localCenterOfMass")].localCom;
}
Real World::friction(BodyId id) const { return impl_->params[impl_->resolveBody(id, "World::friction")].friction; }
Real World::restitution(BodyId id) const {
    return impl_->params[impl_->resolveBody(id, "World::restitution")].restitution;
}

Transform World::transform(BodyId id) const {
    return impl_->originTransform(impl_->resolveBody(id, "World::transform"));
}
Vec3 World::position(BodyId id) const { return impl_->origin(impl_->resolveBody(id, "World::position")); }
Quat World::orientation(BodyId id) const { return impl_->motion[impl_->resolveBody(id, "World::orientation")].q; }
Vec3 World::centerOfMass(BodyId id) const { return impl_->motion[impl_->resolveBody(id, "World::centerOfMass")].com; }
Vec3 World::linearVelocity(BodyId id) const {
    return impl_->motion[impl_->resolveBody(id, "World::linearVelocity")].v;
}
Vec3 World::angularVelocity(BodyId id) const {
    return impl_->motion[impl_->resolveBody(id, "World::angularVelocity")].w;
}
Vec3 World::velocityAtPoint(BodyId id, const Vec3& worldPoint) const {
    const std::uint32_t d = impl_->resolveBody(id, "World::velocityAtPoint");
    requireFinite(subjectOf(*impl_, d), "worldPoint", worldPoint);
    const detail::BodyMotion& m = impl_->motion[d];
    return m.v + cross(m.w, worldPoint - m.com);
}
Transform World::previousTransform(BodyId id) const {
    return impl_->previous[impl_->resolveBody(id, "World::previousTransform")];
}

void World::setTransform(BodyId id, const Vec3& position, const Quat& orientation) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::setTransform");
    const Subject who = subjectOf(w, d);
    requireFinite(who, "position", position);
    const Quat q = detail::requireOrientation(who, "orientation", orientation);
    // A static or kinematic body never sleeps, so waking it alone would leave
    // sleeping bodies it left or now overlaps hanging in the air or buried:
    // wake every body near its old and new place (within the speculative margin).
    const bool movesOthers = w.params[d].type != BodyType::Dynamic;
    AABB reach;
    if (movesOthers) reach = w.cold[d].shape.bounds(w.originTransform(d));
    detail::BodyMotion& m = w.motion[d];
    m.q = q;
    m.com = position + rotate(q, w.params[d].localCom);
    w.updateWorldInertia(d);
    w.previous[d] = {position, q};  // a teleport: don't interpolate across it
    w.markPreviousStale(d);         // the next step refreshes it, as for every body
    w.wakeBody(d);
    w.contactManager.bodyTeleported(w, d);
    if (movesOthers) {
        reach = merge(reach, w.cold[d].shape.bounds(w.originTransform(d)));
        for (const BodyId other : overlapAABB(reach.fattened(w.settings.speculativeMargin))) {
            w.wakeBody(w.resolveBody(other, "World::setTransform"));
        }
    }
}

void World::setLinearVelocity(BodyId id, const Vec3& v) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::setLinearVelocity");
    requireFinite(subjectOf(w, d), "linearVelocity", v);
    if (w.params[d].type == BodyType::Static) return;  // static bodies never move
    w.motion[d].v = v;
    w.wakeBody(d);
}

void World::moveKinematic(BodyId id, const Transform& target, Real dt) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::moveKinematic");
    const Subject who = subjectOf(w, d);
    if (w.params[d].type != BodyType::Kinematic) fail(who, "moveKinematic", "needs a kinematic body");
    requireFinite(who, "target position", target.p);
    const Quat q = detail::requireOrientation(who, "target orientation", target.q);
    requirePositive(who, "dt", dt);
    detail::BodyMotion& m = w.motion[d];
    // The integrator moves a kinematic body's centre of mass by v h and turns
    // it by the exact exponential map of w h per sub-step (integrators.cpp),
    // so constant velocities over the step land on the target.
    const Vec3 targetCom = target.p + rotate(q, w.params[d].localCom);
    m.v = (targetCom - m.com) * (Real(1) / dt);
    m.w = toRotationVector(q * conjugate(m.q)) * (Real(1) / dt);
    w.wakeBody(d);
}

void World::setAngularVelocity(BodyId id, const Vec3& omega) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::setAngularVelocity");
    requireFinite(subjectOf(w, d), "angularVelocity", omega);
    if (w.params[d].type == BodyType::Static) return;
    w.motion[d].w = omega;
    w.wakeBody(d);
}

void World::setFriction(BodyId id, Real friction) {
    const std::uint32_t d = impl_->resolveBody(id, "World::setFriction");
    requireNonNegative(subjectOf(*impl_, d), "friction", friction);
    impl_->params[d].friction = friction;
}
void World::setRestitution(BodyId id, Real restitution) {
    const std::uint32_t d = impl_->resolveBody(id, "World::setRestitution");
    requireNonNegative(subjectOf(*impl_, d), "restitution", restitution);
    impl_->params[d].restitution = restitution;
}
void World::setGravityScale(BodyId id, Real scale) {
    const std::uint32_t d = impl_->resolveBody(id, "World::setGravityScale");
    requireFinite(subjectOf(*impl_, d), "gravityScale", scale);
    impl_->params[d].gravityScale = scale;
}
void World::setDamping(BodyId id, Real linear, Real angular) {
    const std::uint32_t d = impl_->resolveBody(id, "World::setDamping");
    const Subject who = subjectOf(*impl_, d);
    requireNonNegative(who, "linearDamping", linear);
    requireNonNegative(who, "angularDamping", angular);
    impl_->params[d].linearDamping = linear;
    impl_->params[d].angularDamping = angular;
}
void World::setDrag(BodyId id, Real linear, Real quadratic) {
    const std::uint32_t d = impl_->resolveBody(id, "World::setDrag");
    const Subject who = subjectOf(*impl_, d);
    requireNonNegative(who, "linearDrag", linear);
    requireNonNegative(who, "quadraticDrag", quadratic);
    impl_->params[d].linearDrag = linear;
    impl_->params[d].quadraticDrag = quadratic;
}

bool World::isAwake(BodyId id) const { return impl_->params[impl_->resolveBody(id, "World::isAwake")].awake; }
void World::wake(BodyId id) {
    const std::uint32_t d = impl_->resolveBody(id, "World::wake");
    impl_->wakeBody(d);
}

// ---------------------------------------------------------------- user forces and impulses
// Forces and impulses on static and kinematic bodies are accepted and have no
// effect (infinite mass), like in Box2D; they are still validated.

void World::applyForce(BodyId id, const Vec3& force, const Vec3& worldPoint) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::applyForce");
    const Subject who = subjectOf(w, d);
    requireFinite(who, "force", force);
    requireFinite(who, "worldPoint", worldPoint);
    if (w.params[d].type != BodyType::Dynamic) return;
    w.applied[d].force += force;
    w.applied[d].torque += cross(worldPoint - w.motion[d].com, force);
    w.wakeBody(d);
}

void World::applyForceAtCenter(BodyId id, const Vec3& force) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::applyForceAtCenter");
    requireFinite(subjectOf(w, d), "force", force);
    if (w.params[d].type != BodyType::Dynamic) return;
    w.applied[d].force += force;
    w.wakeBody(d);
}

void World::applyTorque(BodyId id, const Vec3& torque) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::applyTorque");
    requireFinite(subjectOf(w, d), "torque", torque);
    if (w.params[d].type != BodyType::Dynamic) return;
    w.applied[d].torque += torque;
    w.wakeBody(d);
}

void World::applyLinearImpulse(BodyId id, const Vec3& impulse, const Vec3& worldPoint) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::applyLinearImpulse");
    const Subject who = subjectOf(w, d);
    requireFinite(who, "impulse", impulse);
    requireFinite(who, "worldPoint", worldPoint);
    if (w.params[d].type != BodyType::Dynamic) return;
    detail::BodyMotion& m = w.motion[d];
    m.v += impulse * m.invMass;
    m.w += m.invInertiaWorld * cross(worldPoint - m.com, impulse);
    w.wakeBody(d);
}

void World::applyLinearImpulseAtCenter(BodyId id, const Vec3& impulse) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::applyLinearImpulseAtCenter");
    requireFinite(subjectOf(w, d), "impulse", impulse);
    if (w.params[d].type != BodyType::Dynamic) return;
    w.motion[d].v += impulse * w.motion[d].invMass;
    w.wakeBody(d);
}

void World::applyAngularImpulse(BodyId id, const Vec3& impulse) {
    WorldImpl& w = *impl_;
    const std::uint32_t d = w.resolveBody(id, "World::applyAngularImpulse");
    requireFinite(subjectOf(w, d), "angularImpulse", impulse);
    if (w.params[d].type != BodyType::Dynamic) return;
    w.motion[d].w += w.motion[d].invInertiaWorld * impulse;
    w.wakeBody(d);
}

void World::setForceCallback(BodyId id, ForceCallback callback) {
    const std::uint32_t d = impl_->resolveBody(id, "World::setForceCallback");
    if (callback) impl_->anyForceCallback = true;
    impl_->cold[d].callback = std::move(callback);
}

// ---------------------------------------------------------------- simulation

void World::step(Real dt) {
    if (!std::isfinite(dt) || dt <= 0) fail(kWorldSubject, "step dt", "must be a positive finite time, got " + formatReal(dt));
    WorldImpl& w = *impl_;
    if (w.nonFiniteSinceStep != 0) {
        // The previous step threw NumericalError. Stepping on would feed NaN
        // boxes to the broad phase, so refuse until every body is finite again
        // (the user set its state, destroyed it, or restored a snapshot).
        for (std::uint32_t i = 0; i < w.motion.size(); ++i) {
            const detail::BodyMotion& m = w.motion[i];
            if (w.params[i].type == BodyType::Static) continue;
            if (!isFinite(m.com) || !isFinite(m.q) || !isFinite(m.v) || !isFinite(m.w)) {
                throw NumericalError(w.describeBody(i) + " (index " + std::to_string(w.denseToSlot[i]) +
                                     "): state is still NaN/inf since step " + std::to_string(w.nonFiniteSinceStep) +
                                     "; set its state, destroy it or restore a snapshot before stepping again");
            }
        }
        w.nonFiniteSinceStep = 0;
    }
    if (w.outOfMemoryAtStep != 0) {
        throw Error("World::step: this world ran out of memory in step " + std::to_string(w.outOfMemoryAtStep) +
                    " and may be inconsistent since; restore a snapshot or build it again");
    }
    try {
        const double t0 = w.time;
        if (!w.vehicles.empty()) w.vehicles.update(*this, t0, dt);  // forces for this step (vehicle_system.hpp)
        w.step(dt);
        if (!w.characters.empty()) w.characters.update(*this, t0, dt);  // after the bodies (character_system.hpp)
    } catch (const NumericalError&) {
        w.nonFiniteSinceStep = w.stepCount;
        throw;
    } catch (const std::bad_alloc&) {
        // Half a step done: refuse further steps (above) rather than run on
        // half-updated contacts. The pairs are what grows with crowding.
        w.outOfMemoryAtStep = w.stepCount + 1;
        w.outOfMemoryReserve.reset();  // room for the message below (the world steps no more)
        const detail::ContactManager& cm = w.contactManager;
        std::size_t particles = 0;
        for (const ParticleSystemId id : w.particles.live) particles += particleCount(id);
        // Ropes and cloths hold their own buffers: name them when they may be the cause.
        const std::string particleNote =
            particles == 0 ? std::string()
                           : ", or fewer rope and cloth particles (" + std::to_string(particles) + " now)";
        throw Error("World::step: out of memory in step " + std::to_string(w.outOfMemoryAtStep) + " with " +
                    std::to_string(w.motion.size()) + " bodies and " + std::to_string(cm.liveContactCount()) +
                    " contact pairs (WorldDef::maxContactPairs allows " + std::to_string(cm.lastPairLimit()) +
                    "; a pair takes about 2 KB): lower maxContactPairs, or start the bodies apart" + particleNote);
    }
}
Real World::time() const { return static_cast<Real>(impl_->time); }
std::uint64_t World::stepCount() const { return impl_->stepCount; }
StepProfile World::lastStepProfile() const { return impl_->profile; }
std::span<const WorldWarning> World::warnings() const { return impl_->warnings; }

}  // namespace fulcrum
