#include "particles/particle_world.hpp"

#include <algorithm>
#include <cmath>

#include "particles/particle_builders.hpp"
#include "dynamics/validation.hpp"
#include "particles/xpbd_distance.hpp"

namespace fulcrum {

namespace {

void validateSettings(const ParticleWorldSettings& s) {
    const std::string label = "particle world";
    detail::requireFinite(label, "gravity", s.gravity);
    detail::requireFinite(label, "wind", s.wind);
    detail::requireNonNegative(label, "air_density", s.airDensity);
    if (s.substeps < 1) detail::fail(label, "substeps", "must be at least 1, got " + std::to_string(s.substeps));
    if (s.iterations < 1) {
        detail::fail(label, "iterations", "must be at least 1, got " + std::to_string(s.iterations));
    }
}

// Everything the step trusts, checked once when a system joins the world
// (systems assembled by hand, not by the builders, come through here too).
void validateSystem(const ParticleSystem& s) {
    const std::string label = detail::particleSystemLabel(toString(s.kind), s.name);
    const std::size_t n = s.particleCount();
    if (s.displacement.size() != n || s.restPosition.size() != n || s.force.size() != n ||
        s.inverseMass.size() != n || s.radius.size() != n) {
        detail::fail(label, "particles", "arrays have different lengths");
    }
    for (std::size_t i = 0; i < n; ++i) {
        const std::string field = "particles[" + std::to_string(i) + "]";
        detail::requireFinite(label, field + ".position", s.position[i]);
        detail::requireFinite(label, field + ".displacement", s.displacement[i]);
        detail::requireNonNegative(label, field + ".inverse_mass", s.inverseMass[i]);
        detail::requirePositive(label, field + ".radius", s.radius[i]);
    }
    const auto checkGroup = [&](const DistanceConstraintGroup& g, const char* name) {
        detail::requireNonNegative(label, std::string(name) + "_compliance", g.compliance);
        if (g.lambda.size() != g.constraints.size()) detail::fail(label, name, "multiplier array has the wrong length");
        for (std::size_t k = 0; k < g.size(); ++k) {
            const DistanceConstraint& c = g.constraints[k];
            if (c.a >= n || c.b >= n) {
                detail::fail(label, std::string(name) + "[" + std::to_string(k) + "]",
                             "refers to a particle outside the system (" + std::to_string(n) + " particles)");
            }
            if (!(c.restLength > 0) || !std::isfinite(c.restLength)) {
                detail::fail(label, std::string(name) + "[" + std::to_string(k) + "].rest_length",
                             "must be positive, got " + detail::formatReal(c.restLength));
            }
        }
    };
    checkGroup(s.stretch, "stretch");
    checkGroup(s.shear, "shear");
    checkGroup(s.bend, "bend");
    checkGroup(s.tethers, "tether");
    for (std::size_t k = 0; k < s.pins.size(); ++k) {
        if (s.pins[k].particle >= n) {
            detail::fail(label, "pins[" + std::to_string(k) + "]", "refers to particle " +
                         std::to_string(s.pins[k].particle) + " outside the system");
        }
        detail::requireFinite(label, "pins[" + std::to_string(k) + "].target", s.pins[k].target);
    }
    for (const ParticleTriangle& t : s.triangles) {
        if (t.a >= n || t.b >= n || t.c >= n) detail::fail(label, "triangles", "refer to a particle outside the system");
    }
    detail::requireNonNegative(label, "damping", s.damping);
    detail::requireNonNegative(label, "linear_drag", s.linearDrag);
    detail::requireNonNegative(label, "friction", s.friction);
    detail::requireNonNegative(label, "drag_coefficient", s.dragCoefficient);
    detail::requireFinite(label, "lift_coefficient", s.liftCoefficient);
    detail::requireNonNegative(label, "self_collision_exclusion", s.selfCollisionExclusion);
}

// Ropes are swept one constraint after another from the end that holds them
// (xpbd_distance.hpp, "Chains are solved in order"): from the start unless
// only the last particle is held (pinned or tied to a body). Cloths keep the
// coloured SIMD sweep.
detail::DistanceOrder distanceOrder(const ParticleSystem& s) {
    if (s.kind != ParticleSystemKind::Rope || s.particleCount() < 2) return detail::DistanceOrder::Coloured;
    const auto held = [&s](std::uint32_t i) {
        if (s.inverseMass[i] == 0) return true;
        return std::any_of(s.attachments.begin(), s.attachments.end(),
                           [i](const ParticleAttachment& a) { return a.particle == i; });
    };
    const auto last = static_cast<std::uint32_t>(s.particleCount() - 1);
    return !held(0) && held(last) ? detail::DistanceOrder::Backward : detail::DistanceOrder::Forward;
}

}  // namespace

ParticleWorld::ParticleWorld(const ParticleWorldSettings& settings) : settings_(settings) { validateSettings(settings); }
ParticleWorld::~ParticleWorld() = default;
ParticleWorld::ParticleWorld(ParticleWorld&&) noexcept = default;
ParticleWorld& ParticleWorld::operator=(ParticleWorld&&) noexcept = default;

void ParticleWorld::setSettings(const ParticleWorldSettings& settings) {
    validateSettings(settings);
    settings_ = settings;
}

ParticleSystemId ParticleWorld::add(ParticleSystem system, const RigidCollider* collider) {
    validateSystem(system);
    const std::string label = detail::particleSystemLabel(toString(system.kind), system.name);
    for (ParticleAttachment& a : system.attachments) {
        if (a.particle >= system.particleCount()) {
            detail::fail(label, a.field, "refers to particle " + std::to_string(a.particle) + " outside the system");
        }
        if (collider == nullptr) {
            detail::fail(label, a.field, "ties a particle to body index " + std::to_string(a.body) +
                         ", but no rigid world was given to resolve it");
        }
        if (!collider->isValidBody(a.body)) {
            detail::fail(label, a.field, "refers to unknown body index " + std::to_string(a.body));
        }
        if (!a.resolved) {
            a.localAnchor = inverseTransformPoint(collider->bodyState(a.body).transform, system.position[a.particle]);
            a.resolved = true;
        }
    }
    for (const Slot& s : slots_) {
        if (s.system && !system.name.empty() && s.system->name == system.name) {
            detail::fail(label, "name", "is already used by another particle system");
        }
    }
    const std::uint32_t index = slots_.nextSlot();
    Slot& slot = slots_.add();
    slot.system = std::make_unique<ParticleSystem>(std::move(system));
    slot.order = nextOrder_++;
    slot.accel.clear();
    return slots_.handleOf(index);
}

ParticleSystemId ParticleWorld::addRope(const RopeDef& def, const RigidCollider* collider) {
    return add(buildRope(def), collider);
}

ParticleSystemId ParticleWorld::addCloth(const ClothDef& def, const RigidCollider* collider) {
    return add(buildCloth(def), collider);
}

ParticleWorld::Slot& ParticleWorld::slotOf(ParticleSystemId id) {
    return const_cast<Slot&>(static_cast<const ParticleWorld*>(this)->slotOf(id));
}

const ParticleWorld::Slot& ParticleWorld::slotOf(ParticleSystemId id) const {
    const detail::HandleState state = slots_.lookup(id);
    if (state == detail::HandleState::Null) throw Error("particle system handle: is null");
    if (state != detail::HandleState::Live) {
        throw Error("particle system handle {" + std::to_string(id.index) + ", " + std::to_string(id.generation) +
                    "}: is stale or was never created");
    }
    return slots_[id.index];
}

void ParticleWorld::remove(ParticleSystemId id) {
    Slot& slot = slotOf(id);
    slot.system.reset();
    slots_.remove(id.index);
}

bool ParticleWorld::isValid(ParticleSystemId id) const { return slots_.isLive(id); }

ParticleSystem& ParticleWorld::system(ParticleSystemId id) { return *slotOf(id).system; }
const ParticleSystem& ParticleWorld::system(ParticleSystemId id) const { return *slotOf(id).system; }

std::vector<ParticleSystemId> ParticleWorld::systems() const {
    std::vector<std::pair<std::uint64_t, ParticleSystemId>> live;
    for (std::uint32_t i = 0; i < slots_.size(); ++i) {
        if (slots_[i].alive) live.push_back({slots_[i].order, slots_.handleOf(i)});
    }
    std::sort(live.begin(), live.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<ParticleSystemId> out;
    for (const auto& l : live) out.push_back(l.second);
    return out;
}

std::size_t ParticleWorld::systemCount() const { return slots_.liveCount(); }

void ParticleWorld::step(Real dt, RigidCollider* collider, TaskSystem* tasks) {
    if (!std::isfinite(dt) || !(dt > 0)) throw Error("particle world: step dt must be positive and finite, got " + detail::formatReal(dt));
    const int substeps = settings_.substeps;
    const Real h = dt / static_cast<Real>(substeps);
    const detail::AirSettings air{settings_.wind, settings_.airDensity};

    // Live systems in creation order (slots are reused, so index order is not creation order).
    active_.clear();
    for (Slot& s : slots_) {
        if (s.system) active_.push_back(&s);
    }
    std::sort(active_.begin(), active_.end(), [](const Slot* a, const Slot* b) { return a->order < b->order; });
    activeSystems_.clear();
    travel_.clear();
    extraForces_.assign(active_.size(), 0);
    const Real gravityTravel = length(settings_.gravity) * dt * dt;
    for (Slot* s : active_) {
        ParticleSystem& sys = *s->system;
        activeSystems_.push_back(&sys);
        // How far a particle can get this step: its current speed, plus what
        // gravity adds; rigid contacts within that margin are gathered.
        // (Self-collision keeps its own neighbour list: self_collision.hpp.)
        Real maxMove2 = 0;
        for (std::size_t i = 0; i < sys.particleCount(); ++i) {
            maxMove2 = std::max(maxMove2, lengthSquared(sys.displacement[i]));
        }
        const Real perSecond = sys.previousSubstep > 0 ? dt / sys.previousSubstep : 0;
        travel_.push_back(std::sqrt(maxMove2) * perSecond + gravityTravel);
    }
    if (collider) coupling_.beginStep(*collider, activeSystems_, travel_);
    for (std::size_t k = 0; k < active_.size(); ++k) {
        Slot& slot = *active_[k];
        ParticleSystem& s = *slot.system;
        slot.particles.load(s);
        const detail::DistanceOrder order = distanceOrder(s);
        slot.stretch.prepare(s.stretch, s.inverseMass, h, order);
        slot.shear.prepare(s.shear, s.inverseMass, h, order);
        slot.bend.prepare(s.bend, s.inverseMass, h, order);
        slot.tethers.prepare(s.tethers, s.inverseMass, h, order);
        extraForces_[k] = detail::hasExtraForces(s, air) ? 1 : 0;
        // With several workers, a sweep of every group in one StagedParallel
        // run per iteration: 12 colours of a 64 x 64 cloth as separate
        // parallel calls cost as much in hand-overs as they saved (1.35 against
        // 1.37 ms per step, 2 threads, colours serial and split); as stages a
        // hand-over is a few cache-line trips (docs/threading.md).
        slot.useStages = false;
        if (tasks != nullptr && tasks->workerCount() > 1) {
            slot.stages.clear();
            slot.stretch.addSweepStages(slot.stages, 0);
            slot.shear.addSweepStages(slot.stages, 1);
            slot.bend.addSweepStages(slot.stages, 2);
            slot.tethers.addSweepStages(slot.stages, 3);
            for (const detail::Stage& st : slot.stages.stages()) slot.useStages = slot.useStages || st.count > 1;
        }
    }

    for (int sub = 0; sub < substeps; ++sub) {
        if (collider) coupling_.beginSubstep(sub, substeps, h);
        for (std::size_t k = 0; k < active_.size(); ++k) {
            Slot& slot = *active_[k];
            ParticleSystem& s = *slot.system;
            detail::ParticleSoA& p = slot.particles;
            detail::DriftRange drift;
            if (s.selfCollision) slot.selfCollision.requestDrift(p, drift);
            if (extraForces_[k]) {
                p.store(s);  // forces read the system's positions (rare path: springs, drag, wind, user forces)
                detail::computeForceAccelerations(s, air, h, slot.accel);
                detail::predictPositions(s, p, settings_.gravity, slot.accel, h, &drift);
            } else {
                static const std::vector<Vec3> kNone;
                detail::predictPositions(s, p, settings_.gravity, kNone, h, &drift);
            }
            slot.selfCollision.update(s, p, drift, tasks);
            coupling_.resetAttachmentMultipliers(s);
            for (int it = 0; it < settings_.iterations; ++it) {
                const bool first = it == 0, last = it + 1 == settings_.iterations;
                if (slot.useStages) {
                    detail::DistanceBatches* groups[4] = {&slot.stretch, &slot.shear, &slot.bend, &slot.tethers};
                    ++stagedSweeps_;
                    slot.stages.run(*tasks, [&](const detail::Stage& stage, std::uint32_t begin, std::uint32_t end) noexcept {
                        groups[stage.kind]->runSweepStage(p, first, last, stage.arg, begin, end);
                    });
                } else {
                    slot.stretch.solve(p, first, last);
                    slot.shear.solve(p, first, last);
                    slot.bend.solve(p, first, last);
                    slot.tethers.solve(p, first, last);
                }
                if (collider) coupling_.solveAttachments(s, p, h);
                slot.selfCollision.solve(p);
                if (collider) coupling_.solveContacts(k, s, p, h);
            }
        }
    }
    for (Slot* slot : active_) slot->particles.store(*slot->system);
    if (collider) coupling_.endStep(*collider);
    for (ParticleSystem* s : activeSystems_) std::fill(s->force.begin(), s->force.end(), Vec3::zero());
}

}  // namespace fulcrum
