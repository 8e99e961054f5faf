// A character's move at the end of a step (character_system.hpp says why
// there; docs/characters.md describes the model). All geometry goes through
// the World's public queries (castShape, castRay, overlapShape) and the narrow
// phase's collide(), so every shape the engine collides (planes, boxes,
// meshes, heightfields) is ground a character walks on.
#include <algorithm>
#include <cmath>
#include <optional>

#include "character/character_system.hpp"
#include "collision/narrow_phase.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum::detail {
namespace {

// The gap a character keeps to every surface ("padding"): a shape cast that
// starts in contact reports a hit at once whatever its direction, so the
// capsule never rests touching anything.
constexpr Real kSkin = Real(0.01);
// How far below the capsule ground still counts (beyond the skin).
constexpr Real kGroundReach = Real(0.03);
constexpr int kSlideIterations = 5;
constexpr int kDepenetrationIterations = 4;
constexpr Real kMinMove = Real(1e-6);
// Above this upward speed relative to the ground the character has left it (a jump).
constexpr Real kLeavingSpeed = Real(0.1);
const Vec3 kUp{0, 1, 0};

Vec3 horizontal(const Vec3& v) { return {v.x, 0, v.z}; }

struct Mover {
    World& world;
    CharacterData& c;
    const Shape& capsule;
    QueryFilter filter;
    Real cosMaxSlope;
    Real halfSegment;  // the capsule's half height minus its radius

    std::optional<ShapeCastHit> cast(const Vec3& from, const Vec3& translation) const {
        if (lengthSquared(translation) < kMinMove * kMinMove) return std::nullopt;
        return world.castShape(capsule, Transform{from, Quat{}}, translation, filter);
    }

    // Moves from `from` along `delta`, stopping kSkin short of the first body
    // in the way; returns the hit (its normal out of the body) if any.
    std::optional<ShapeCastHit> sweep(Vec3& from, const Vec3& delta) const {
        const Real len = length(delta);
        if (len < kMinMove) return std::nullopt;
        const Vec3 dir = delta / len;
        const std::optional<ShapeCastHit> hit = cast(from, dir * (len + kSkin));
        if (!hit) {
            from += delta;
            return std::nullopt;
        }
        const Real travel = std::max(Real(0), hit->fraction * (len + kSkin) - kSkin);
        from += dir * std::min(travel, len);
        return hit;
    }

    // The normal of the surface that holds the character up at a contact.
    // A capsule resting on an edge (a stair's nose) touches it with a normal
    // tilted by where the edge meets the sphere, not by the surface: a short
    // ray down just past the contact, into the obstacle, finds the top face
    // (walkable) of a step and the face itself of a slope or a wall.
    Vec3 supportNormal(const Vec3& point, const Vec3& normal) const {
        if (normal.y >= cosMaxSlope) return normal;
        const Vec3 into = horizontal(-normal);
        const Real l = length(into);
        if (l < Real(1e-6)) return normal;
        constexpr Real kInset = Real(0.02), kAbove = Real(0.05), kTolerance = Real(0.03);
        const Vec3 origin = point + into * (kInset / l) + kUp * kAbove;
        const std::optional<RayCastHit> r = world.castRay(Ray{origin, kUp * -(kAbove + kTolerance), 1}, filter);
        if (!r || r->fraction <= 0 || std::abs(r->point.y - point.y) > kTolerance) return normal;
        return r->normal.y >= cosMaxSlope ? r->normal : normal;
    }
    bool walkable(const ShapeCastHit& hit) const { return supportNormal(hit.point, hit.normal).y >= cosMaxSlope; }

    Real footHeight(const Vec3& centre) const { return centre.y - halfSegment - capsule.radius(); }

    // Pushes a dynamic body hit while moving at `velocity`: an impulse along
    // the contact bringing its contact point up to the character's speed
    // into it, shared by the two masses, at most maxPushForce over the step.
    void push(const ShapeCastHit& hit, const Vec3& velocity, Real dt) const {
        if (world.bodyType(hit.body) != BodyType::Dynamic) return;
        const Vec3 into = -hit.normal;
        const Real want = dot(velocity, into);
        if (want <= 0) return;
        const Real has = dot(world.velocityAtPoint(hit.body, hit.point), into);
        if (want <= has) return;
        const Real m = world.mass(hit.body), mc = c.def.mass;
        const Real impulse = std::min((want - has) * m * mc / (m + mc), c.def.maxPushForce * dt);
        if (impulse > 0) world.applyLinearImpulse(hit.body, into * impulse, hit.point);
    }

    // Collide and slide: up to kSlideIterations casts, each leaving the rest
    // of the motion along the planes hit so far (one plane: its tangent plane;
    // two: their crease; three: stop). Walking, surfaces steeper than
    // maxSlope act as vertical walls so that sliding along them never climbs.
    // Returns whether a steep surface stopped part of a walking motion.
    bool slide(Vec3& pos, Vec3 delta, Vec3& velocity, bool walking, Real dt, bool pushBodies) const {
        Vec3 planes[2];
        int planeCount = 0;
        bool blockedBySteep = false;
        for (int i = 0; i < kSlideIterations; ++i) {
            const std::optional<ShapeCastHit> hit = sweep(pos, delta);
            if (!hit) break;
            const Real len = length(delta);
            const Real travel = hit->fraction * (len + kSkin) - kSkin;
            delta = delta * (Real(1) - std::clamp(travel / len, Real(0), Real(1)));
            if (pushBodies) push(*hit, velocity, dt);
            Vec3 n = hit->normal;
            // The contact's own normal, not the support under it: the top edge
            // of a riser met from the side is a wall (stepUp decides on steps).
            if (walking && n.y < cosMaxSlope) {
                const Vec3 h = horizontal(n);
                const Real hl = length(h);
                if (hl > Real(1e-6)) n = h / hl;
                if (dot(delta, n) < 0) blockedBySteep = true;
            }
            const Real into = dot(delta, n);
            if (into < 0) delta -= n * into;
            const Real vinto = dot(velocity, n);
            if (vinto < 0) velocity -= n * vinto;
            if (planeCount == 1 && dot(delta, planes[0]) < -Real(1e-7)) {
                Vec3 crease = cross(planes[0], n);
                const Real cl = length(crease);
                if (cl < Real(1e-6)) {
                    delta = Vec3::zero();
                } else {
                    crease = crease / cl;
                    delta = crease * dot(delta, crease);
                }
            } else if (planeCount == 2) {
                delta = Vec3::zero();
            }
            if (planeCount < 2) planes[planeCount++] = n;
            if (lengthSquared(delta) < kMinMove * kMinMove) break;
        }
        return blockedBySteep;
    }

    // Moves the capsule out of whatever overlaps it (a body that moved into
    // it, another character) to kSkin away, along the contacts' normals.
    // This is how a body moving into the character pushes it back.
    void depenetrate(Vec3& pos, std::vector<BodyId>& nearby, ManifoldBuffer& manifolds) const {
        const Shape probe = Shape::capsule(capsule.radius() + kSkin, halfSegment);
        for (int iter = 0; iter < kDepenetrationIterations; ++iter) {
            world.overlapShape(probe, Transform{pos, Quat{}}, nearby, filter);
            Vec3 moved = Vec3::zero();
            for (const BodyId b : nearby) {
                collide(capsule, Transform{pos, Quat{}}, world.shape(b), world.transform(b), kSkin, manifolds);
                for (const Manifold& m : manifolds) {
                    const Real need = m.maxDepth() + kSkin - dot(moved, -m.normal);
                    if (need > Real(1e-5)) moved += -m.normal * need;
                }
            }
            if (lengthSquared(moved) < Real(1e-10)) return;
            pos += moved;
        }
    }

    // Stair stepping (after a walking move that a steep surface stopped): up
    // by stepHeight, along the wanted horizontal motion, down onto walkable
    // ground at most stepHeight above the feet. Kept only if it got further.
    bool stepUp(Vec3& pos, const Vec3& start, const Vec3& wanted, Real dt) const {
        const Real stepHeight = c.def.stepHeight;
        if (stepHeight <= 0) return false;
        const Vec3 wantedH = horizontal(wanted);
        const Real wl = length(wantedH);
        if (wl < kMinMove) return false;
        Vec3 p = start;
        sweep(p, kUp * stepHeight);
        const Real lifted = p.y - start.y;
        if (lifted <= kMinMove) return false;
        Vec3 scratchVelocity = wantedH / dt;
        slide(p, wantedH, scratchVelocity, true, dt, false);
        const std::optional<ShapeCastHit> down = sweep(p, kUp * -(lifted + kSkin));
        if (!down || !walkable(*down)) return false;
        if (down->point.y - footHeight(start) > stepHeight + kSkin) return false;
        const Vec3 dirH = wantedH / wl;
        if (dot(p - start, dirH) <= dot(pos - start, dirH) + Real(1e-5)) return false;
        pos = p;
        return true;
    }

    // The ground below `pos` within reach: its state, normal and body.
    void probeGround(Vec3& pos) {
        c.ground = GroundState::InAir;
        c.groundNormal = Vec3::zero();
        c.groundBody = BodyId{};
        c.groundVelocity = Vec3::zero();
        if (c.velocity.y > kLeavingSpeed) return;  // jumping away from it
        Vec3 below = pos;
        const std::optional<ShapeCastHit> hit = sweep(below, kUp * -kGroundReach);
        if (!hit || hit->normal.y <= 0) return;
        pos = below;  // down to the skin's distance: no hovering after a landing
        const Vec3 n = supportNormal(hit->point, hit->normal);
        c.ground = n.y >= cosMaxSlope ? GroundState::OnGround : GroundState::OnSteepGround;
        c.groundNormal = n;
        c.groundBody = hit->body;
        c.groundPoint = hit->point;
        if (world.bodyType(hit->body) != BodyType::Static) c.groundVelocity = world.velocityAtPoint(hit->body, pos);
    }
};

}  // namespace

void CharacterSystem::update(World& world, double t0, Real dt) {
    const Vec3 gravity = world.settings().gravity;
    for (const std::uint32_t slot : order) {
        CharacterData& c = pool[slot];
        // The script: the last entry whose time has come holds.
        const std::vector<CharacterInput>& script = c.def.inputs;
        while (c.nextInput < script.size() && double(script[c.nextInput].time) <= t0 + 1e-9) {
            c.inputVelocity = script[c.nextInput].velocity;
            c.inputJump = script[c.nextInput].jump;
            ++c.nextInput;
        }
        const Shape& capsule = world.shape(c.body);
        Mover mv{world, c, capsule, QueryFilter{}, c.cosMaxSlope, capsule.halfHeight()};
        mv.filter.excludeBody = c.body;
        const Vec3 before = c.position;
        Vec3 pos = c.position;

        // Ride the ground body: where the point of it the character stood on went.
        const bool supported = c.ground != GroundState::InAir;
        if (supported && world.isValid(c.groundBody) && world.bodyType(c.groundBody) != BodyType::Static) {
            pos = transformPoint(world.transform(c.groundBody), c.groundLocal);
        }
        mv.depenetrate(pos, nearby_, manifolds_);

        // The velocity of this step.
        // In the air (and on steep ground) gravity acts; the move takes the
        // step's mean velocity, exact for constant acceleration, so a jump's
        // apex is v^2 / (2 g) whatever the step.
        const Vec3 wanted = horizontal(c.inputVelocity);
        bool jumped = false;
        Vec3 v, vStart;
        if (c.ground == GroundState::OnGround && !c.inputJump) {
            v = vStart = wanted;
            c.airVelocity = Vec3::zero();
        } else {
            if (c.ground == GroundState::OnGround) {
                c.airVelocity = c.groundVelocity;
                c.velocity = kUp * (c.def.jumpSpeed + c.groundVelocity.y);
                jumped = true;
            }
            // In the air the input steers (plus the ground's velocity at take-off);
            // on steep ground the character only slides, keeping its speed.
            v = c.ground == GroundState::OnSteepGround ? c.velocity
                                                       : wanted + horizontal(c.airVelocity) + kUp * c.velocity.y;
            vStart = v;
            v += gravity * dt;
        }

        // Collide and slide, then stairs.
        const Vec3 start = pos;
        const bool walking = c.ground == GroundState::OnGround && !jumped;
        Vec3 velocity = v;
        const bool blocked = mv.slide(pos, (vStart + v) * (Real(0.5) * dt), velocity, walking, dt, true);
        if (walking && blocked) mv.stepUp(pos, start, wanted * dt, dt);
        c.velocity = velocity;

        // Ground, and sticking to it down stairs and slopes.
        mv.probeGround(pos);
        if (walking && c.ground != GroundState::OnGround && c.def.stickDistance > 0) {
            Vec3 p = pos;
            const std::optional<ShapeCastHit> down = mv.sweep(p, kUp * -c.def.stickDistance);
            if (down && mv.walkable(*down)) {
                pos = p;
                mv.probeGround(pos);
            }
        }
        if (c.ground == GroundState::OnGround) {
            c.velocity.y = 0;
            c.airVelocity = Vec3::zero();
        }
        if (c.ground != GroundState::InAir && world.isValid(c.groundBody)) {
            c.groundLocal = inverseTransformPoint(world.transform(c.groundBody), pos);
            // Standing on a dynamic body, the character weighs on it over the next step.
            if (c.ground == GroundState::OnGround && world.bodyType(c.groundBody) == BodyType::Dynamic) {
                world.applyForce(c.groundBody, gravity * c.def.mass, c.groundPoint);
            }
        }
        c.position = pos;
        c.reportedVelocity = (pos - before) / dt;
        placeCharacterBody(world, c.body, pos);
    }
}

}  // namespace fulcrum::detail
