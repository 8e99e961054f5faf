// World's character API (world.hpp, "characters"): creation with validation,
// destruction, state and inputs. The move itself is character_move.cpp.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "character/character_system.hpp"
#include "dynamics/validation.hpp"
#include "fulcrum/math/deterministic_math.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

using detail::CharacterData;
using detail::Subject;

const char* toString(GroundState state) {
    switch (state) {
        case GroundState::OnGround: return "on_ground";
        case GroundState::OnSteepGround: return "on_steep_ground";
        case GroundState::InAir: return "in_air";
    }
    return "in_air";
}

namespace {

const CharacterData& resolve(const WorldImpl& w, CharacterId id, const char* where) {
    return detail::resolveHandle(w.characters.pool, id, where, "CharacterId", "character");
}
CharacterData& resolve(WorldImpl& w, CharacterId id, const char* where) {
    return const_cast<CharacterData&>(resolve(std::as_const(w), id, where));
}

void validate(const CharacterDef& def) {
    const Subject who{"character", def.name};
    detail::requireFinite(who, "position", def.position);
    detail::requirePositive(who, "radius", def.radius);
    detail::requirePositive(who, "height", def.height);
    if (def.height < 2 * def.radius) {
        detail::fail(who, "height", "must be at least twice the radius (" + detail::formatReal(2 * def.radius) +
                                        "), got " + detail::formatReal(def.height));
    }
    detail::requirePositive(who, "mass", def.mass);
    detail::requireFinite(who, "maxSlope", def.maxSlope);
    if (!(def.maxSlope > 0 && def.maxSlope < Real(std::numbers::pi / 2))) {
        detail::fail(who, "maxSlope", "must be between 0 and pi/2 radians (exclusive), got " + detail::formatReal(def.maxSlope));
    }
    detail::requireNonNegative(who, "stepHeight", def.stepHeight);
    detail::requireNonNegative(who, "jumpSpeed", def.jumpSpeed);
    detail::requireNonNegative(who, "maxPushForce", def.maxPushForce);
    detail::requireNonNegative(who, "stickDistance", def.stickDistance);
    for (std::size_t i = 0; i < def.inputs.size(); ++i) {
        const std::string field = "inputs[" + std::to_string(i) + "]";
        detail::requireFinite(who, field + ".time", def.inputs[i].time);
        detail::requireFinite(who, field + ".velocity", def.inputs[i].velocity);
        if (i > 0 && def.inputs[i].time < def.inputs[i - 1].time) {
            detail::fail(who, field + ".time", "must not be before the previous input's (" +
                                                   detail::formatReal(def.inputs[i - 1].time) + "), got " +
                                                   detail::formatReal(def.inputs[i].time));
        }
    }
}

}  // namespace

namespace detail {

void placeCharacterBody(World& world, BodyId body, const Vec3& centre) {
    WorldImpl& w = implOf(world);
    const std::uint32_t d = w.resolveBody(body, "character");
    const Transform old = w.originTransform(d);
    BodyMotion& m = w.motion[d];
    m.com = centre + rotate(m.q, w.params[d].localCom);
    w.previous[d] = old;  // interpolation runs from where the step found it
    w.markPreviousStale(d);
    w.wakeBody(d);
    w.contactManager.bodyTeleported(w, d);
}

}  // namespace detail

CharacterId World::createCharacter(const CharacterDef& def) {
    WorldImpl& w = *impl_;
    validate(def);
    BodyDef body;
    body.name = def.name;
    body.type = BodyType::Kinematic;
    body.shape = Shape::capsule(def.radius, def.height / 2 - def.radius);
    body.position = def.position;
    body.filter.category = kCharacterCategory;
    body.filter.mask = kCharacterCategory;
    const BodyId bodyId = createBody(body);

    const std::uint32_t slot = w.characters.pool.nextSlot();
    CharacterData& c = w.characters.pool.add();
    const std::uint32_t generation = c.generation;
    c = CharacterData{};
    c.alive = true;
    c.generation = generation;
    c.def = def;
    c.cosMaxSlope = dmath::cos(def.maxSlope);
    c.body = bodyId;
    c.position = def.position;
    w.characters.order.push_back(slot);
    return w.characters.pool.handleOf(slot);
}

void World::destroyCharacter(CharacterId id) {
    WorldImpl& w = *impl_;
    CharacterData& c = resolve(w, id, "World::destroyCharacter");
    const BodyId body = c.body;
    c.def = CharacterDef{};
    std::erase(w.characters.order, id.index);
    w.characters.pool.remove(id.index);
    if (isValid(body)) destroyBody(body);
}

bool World::isValid(CharacterId id) const { return impl_->characters.pool.isLive(id); }

std::vector<CharacterId> World::characters() const {
    std::vector<CharacterId> out;
    for (const std::uint32_t slot : impl_->characters.order) out.push_back(impl_->characters.pool.handleOf(slot));
    return out;
}

const std::string& World::name(CharacterId id) const { return resolve(*impl_, id, "World::name").def.name; }
const CharacterDef& World::characterDef(CharacterId id) const { return resolve(*impl_, id, "World::characterDef").def; }
BodyId World::characterBody(CharacterId id) const { return resolve(*impl_, id, "World::characterBody").body; }

CharacterState World::characterState(CharacterId id) const {
    const CharacterData& c = resolve(*impl_, id, "World::characterState");
    CharacterState s;
    s.position = c.position;
    s.velocity = c.reportedVelocity;
    s.ground = c.ground;
    s.groundNormal = c.groundNormal;
    s.groundVelocity = c.groundVelocity;
    s.groundBody = c.groundBody;
    return s;
}

void World::setCharacterInput(CharacterId id, const Vec3& velocity, bool jump) {
    CharacterData& c = resolve(*impl_, id, "World::setCharacterInput");
    detail::requireFinite(Subject{"character", c.def.name}, "velocity", velocity);
    c.inputVelocity = velocity;
    c.inputJump = jump;
}

void World::setCharacterPosition(CharacterId id, const Vec3& position) {
    CharacterData& c = resolve(*impl_, id, "World::setCharacterPosition");
    detail::requireFinite(Subject{"character", c.def.name}, "position", position);
    c.position = position;
    c.ground = GroundState::InAir;
    c.groundBody = BodyId{};
    detail::placeCharacterBody(*this, c.body, position);
}

}  // namespace fulcrum
