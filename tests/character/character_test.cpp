// Character controller (World::createCharacter, docs/characters.md) against
// the behaviour issue 23 asks for: slopes, stairs, platforms, pushing,
// jumping, character-vs-character, determinism and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <fulcrum/fulcrum.hpp>

namespace {

using namespace fulcrum;

constexpr Real kDt = Real(1) / Real(60);
constexpr Real kRadius = Real(0.3), kHeight = Real(1.8);

BodyId addStatic(World& world, const Shape& shape, const Vec3& position, const Quat& q = {}) {
    BodyDef def;
    def.type = BodyType::Static;
    def.shape = shape;
    def.position = position;
    def.orientation = q;
    return world.createBody(def);
}

// A character standing on y = ground (its centre half its height and the skin above).
CharacterDef standing(const std::string& name, Real x, Real z, Real ground = 0) {
    CharacterDef def;
    def.name = name;
    def.position = {x, ground + kHeight / 2 + Real(0.01), z};
    def.radius = kRadius;
    def.height = kHeight;
    return def;
}

Real feet(const World& world, CharacterId c) { return world.characterState(c).position.y - kHeight / 2; }

// A ramp rising along +x at `angle`, its top face starting at (x0, 0).
void addRamp(World& world, Real angle, Real x0) {
    const Real halfLength = 10, halfThickness = Real(0.5);
    const Quat q = Quat::fromAxisAngle({0, 0, 1}, angle);
    const Vec3 startOfTop = rotate(q, Vec3{-halfLength, halfThickness, 0});
    addStatic(world, Shape::box({halfLength, halfThickness, 3}), Vec3{x0, 0, 0} - startOfTop, q);
}

Real climbAfter(Real slope, Real seconds) {
    World world;
    addStatic(world, Shape::plane({0, 1, 0}, 0), {});
    addRamp(world, slope, 1);
    CharacterDef def = standing("walker", 0, 0);
    def.maxSlope = Real(std::numbers::pi / 4);
    def.inputs = {{0, {2, 0, 0}, false}};
    const CharacterId c = world.createCharacter(def);
    for (int i = 0; i < int(seconds / kDt); ++i) world.step(kDt);
    return feet(world, c);
}

TEST(Character, WalksUpThirtyDegreesNotFifty) {
    // 4 s at 2 m/s: up a 30 degree ramp (walkable under 45) it rises metres;
    // a 50 degree one stops it at the foot (within the capsule's rounded bottom).
    const Real up30 = climbAfter(Real(30 * std::numbers::pi / 180), 4);
    const Real up50 = climbAfter(Real(50 * std::numbers::pi / 180), 4);
    EXPECT_GT(up30, Real(2.0));
    EXPECT_LT(up50, Real(0.1));
}

struct StairResult {
    Real feet, x;
};
StairResult climbStairs(Real stepHeight) {
    // Five 0.3 m steps, 0.4 m deep, from x = 1.
    World world;
    addStatic(world, Shape::plane({0, 1, 0}, 0), {});
    constexpr int kSteps = 5;
    constexpr Real kRise = Real(0.3), kRun = Real(0.4), kStart = 1;
    for (int i = 0; i < kSteps; ++i) {
        const Real x0 = kStart + Real(i) * kRun, x1 = kStart + kSteps * kRun + 20;
        const Real top = Real(i + 1) * kRise;
        addStatic(world, Shape::box({(x1 - x0) / 2, top / 2, 2}), {(x0 + x1) / 2, top / 2, 0});
    }
    CharacterDef def = standing("climber", 0, 0);
    def.stepHeight = stepHeight;
    def.inputs = {{0, {Real(1.5), 0, 0}, false}};
    const CharacterId c = world.createCharacter(def);
    for (int i = 0; i < 300; ++i) world.step(kDt);
    return {feet(world, c), world.characterState(c).position.x};
}

TEST(Character, ClimbsStairsWithinStepHeight) {
    const StairResult high = climbStairs(Real(0.35));
    EXPECT_NEAR(high.feet, Real(1.5), Real(0.05));  // on the top step
    EXPECT_GT(high.x, Real(3.0));
    const StairResult low = climbStairs(Real(0.25));
    EXPECT_LT(low.feet, Real(0.05));                // stopped at the first riser
    EXPECT_LT(low.x, Real(1.0) - kRadius + Real(0.02));
}

TEST(Character, RidesMovingRotatingPlatformWithoutDrift) {
    // A kinematic platform moving at 2 m/s and turning at 0.5 rad/s; the
    // character stands off its axis with no input for 10 s.
    World world(WorldDef{.gravity = {0, Real(-9.81), 0}});
    BodyDef platform;
    platform.type = BodyType::Kinematic;
    platform.shape = Shape::box({3, Real(0.2), 3});
    platform.position = {0, 1, 0};
    platform.linearVelocity = {2, 0, 0};
    platform.angularVelocity = {0, Real(0.5), 0};
    const BodyId p = world.createBody(platform);
    const CharacterId c = world.createCharacter(standing("rider", Real(1.2), Real(0.7), Real(1.2)));
    for (int i = 0; i < 10; ++i) world.step(kDt);
    ASSERT_EQ(world.characterState(c).ground, GroundState::OnGround);
    const Vec3 spot = inverseTransformPoint(world.transform(p), world.characterState(c).position);
    for (int i = 0; i < 600; ++i) world.step(kDt);
    const CharacterState s = world.characterState(c);
    const Vec3 now = inverseTransformPoint(world.transform(p), s.position);
    EXPECT_LT(length(now - spot), Real(0.01));
    EXPECT_EQ(s.ground, GroundState::OnGround);
    EXPECT_EQ(s.groundBody, p);
    // The platform travelled 20 m, so the ride was real.
    EXPECT_GT(world.position(p).x, Real(19.9));
    // Ground velocity: the platform's at the character's place.
    const Vec3 expected = world.velocityAtPoint(p, s.position);
    EXPECT_LT(length(s.groundVelocity - expected), Real(1e-4));
}

TEST(Character, RidesDynamicPlatformAndWeighsOnIt) {
    // A 200 kg slab sliding at 2 m/s and spinning at 0.5 rad/s on ice (no
    // friction): the character rides it within 1 cm, and the slab carries its
    // weight to the ground.
    World world;
    BodyDef ice;
    ice.type = BodyType::Static;
    ice.shape = Shape::plane({0, 1, 0}, 0);
    ice.friction = 0;
    world.createBody(ice);
    BodyDef slab;
    slab.shape = Shape::box({3, Real(0.2), 3});
    slab.mass = 200;
    slab.friction = 0;
    slab.position = {0, Real(0.2), 0};
    slab.linearVelocity = {2, 0, 0};
    slab.angularVelocity = {0, Real(0.5), 0};
    slab.allowSleep = false;
    const BodyId p = world.createBody(slab);
    const CharacterId c = world.createCharacter(standing("rider", Real(1.2), Real(0.7), Real(0.4)));
    for (int i = 0; i < 10; ++i) world.step(kDt);
    ASSERT_EQ(world.characterState(c).groundBody, p);
    const Vec3 spot = inverseTransformPoint(world.transform(p), world.characterState(c).position);
    for (int i = 0; i < 300; ++i) world.step(kDt);
    const Vec3 now = inverseTransformPoint(world.transform(p), world.characterState(c).position);
    EXPECT_LT(length(now - spot), Real(0.01));
    EXPECT_GT(world.position(p).x, Real(9));
    Real normal = 0;
    for (const ContactReport& r : world.contacts()) normal += r.normalImpulse;
    EXPECT_NEAR(normal / kDt, (200 + 80) * Real(9.81), Real(0.02) * (200 + 80) * Real(9.81));
}

Real pushedDistance(Real boxMass) {
    World world;
    addStatic(world, Shape::plane({0, 1, 0}, 0), {});
    BodyDef box;
    box.shape = Shape::box({Real(0.4), Real(0.4), Real(0.4)});
    box.mass = boxMass;
    box.position = {Real(1.5), Real(0.4), 0};
    const BodyId b = world.createBody(box);
    for (int i = 0; i < 30; ++i) world.step(kDt);  // settle
    const Real x0 = world.position(b).x;
    CharacterDef def = standing("pusher", 0, 0);
    def.inputs = {{0, {1, 0, 0}, false}};
    world.createCharacter(def);
    for (int i = 0; i < 180; ++i) world.step(kDt);
    return world.position(b).x - x0;
}

TEST(Character, PushesLightBoxNotHeavyOne) {
    // 3 s at 1 m/s; the box starts 0.8 m ahead. A 10 kg box (friction 59 N
    // under the 500 N push limit) keeps ahead of the character; 10 t (friction
    // 59 kN) does not move.
    EXPECT_GT(pushedDistance(10), Real(1.5));
    EXPECT_LT(std::abs(pushedDistance(10000)), Real(1e-3));
}

TEST(Character, JumpApexIsVSquaredOverTwoG) {
    World world;
    addStatic(world, Shape::plane({0, 1, 0}, 0), {});
    CharacterDef def = standing("jumper", 0, 0);
    def.jumpSpeed = 5;
    const CharacterId c = world.createCharacter(def);
    for (int i = 0; i < 5; ++i) world.step(kDt);
    const Real y0 = world.characterState(c).position.y;
    world.setCharacterInput(c, {}, true);
    world.step(kDt);
    world.setCharacterInput(c, {}, false);
    Real apex = y0;
    bool landed = false;
    for (int i = 0; i < 120; ++i) {
        world.step(kDt);
        apex = std::max(apex, world.characterState(c).position.y);
        if (i > 10 && world.characterState(c).ground == GroundState::OnGround) landed = true;
    }
    const Real expected = Real(25 / (2 * 9.81));
    EXPECT_NEAR(apex - y0, expected, Real(0.01) * expected);
    EXPECT_TRUE(landed);
    EXPECT_NEAR(world.characterState(c).position.y, y0, Real(1e-3));
}

TEST(Character, CharactersBlockEachOther) {
    World world;
    addStatic(world, Shape::plane({0, 1, 0}, 0), {});
    CharacterDef a = standing("a", -2, 0), b = standing("b", 2, 0);
    a.inputs = {{0, {1, 0, 0}, false}};
    b.inputs = {{0, {-1, 0, 0}, false}};
    const CharacterId ca = world.createCharacter(a), cb = world.createCharacter(b);
    for (int i = 0; i < 300; ++i) world.step(kDt);
    const Real gap = world.characterState(cb).position.x - world.characterState(ca).position.x;
    EXPECT_GT(gap, 2 * kRadius);
    EXPECT_LT(gap, 2 * kRadius + Real(0.05));
}

TEST(Character, SlidesDownSteepGround) {
    // Standing on a 60 degree ramp (max 45): steep ground, sliding down.
    World world;
    addStatic(world, Shape::plane({0, 1, 0}, 0), {});
    addRamp(world, Real(60 * std::numbers::pi / 180), 0);
    CharacterDef def = standing("slider", Real(1.5), 0, Real(1.5 * std::tan(60 * std::numbers::pi / 180)) + Real(0.3));
    const CharacterId c = world.createCharacter(def);
    world.step(kDt);
    world.step(kDt);
    const Real y0 = world.characterState(c).position.y;
    bool steep = false;
    for (int i = 0; i < 30; ++i) {
        world.step(kDt);
        steep = steep || world.characterState(c).ground == GroundState::OnSteepGround;
    }
    EXPECT_TRUE(steep);
    EXPECT_LT(world.characterState(c).position.y, y0 - Real(0.3));
}

// A walk with boxes pushed about, for determinism.
World walkWorld(int threads) {
    World world(WorldDef{.threads = threads});
    world.setParallelMinBodies(0);
    addStatic(world, Shape::plane({0, 1, 0}, 0), {});
    for (int i = 0; i < 6; ++i) {
        BodyDef box;
        box.shape = Shape::box({Real(0.3), Real(0.3), Real(0.3)});
        box.mass = 5;
        box.position = {Real(1 + 0.7 * i), Real(0.3), Real(0.2 * (i % 3) - 0.2)};
        world.createBody(box);
    }
    CharacterDef def = standing("walker", 0, 0);
    def.inputs = {{0, {Real(1.5), 0, Real(0.1)}, false}, {1, {Real(1.5), 0, -Real(0.3)}, true}, {Real(1.6), {1, 0, 0}, false}};
    world.createCharacter(def);
    return world;
}

TEST(Character, SameBitsForEveryThreadCount) {
    World one = walkWorld(1), four = walkWorld(4);
    for (int i = 0; i < 240; ++i) {
        one.step(kDt);
        four.step(kDt);
    }
    const CharacterState a = one.characterState(one.characters()[0]);
    const CharacterState b = four.characterState(four.characters()[0]);
    EXPECT_EQ(a.position, b.position);
    const std::vector<BodyId> ba = one.bodies(), bb = four.bodies();
    for (std::size_t i = 0; i < ba.size(); ++i) EXPECT_EQ(one.position(ba[i]), four.position(bb[i]));
}

TEST(Character, BadInputNamesTheField) {
    World world;
    auto expectError = [&](CharacterDef def, const std::string& field) {
        try {
            world.createCharacter(def);
            ADD_FAILURE() << "no error for " << field;
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("character 'bad'"), std::string::npos) << what;
            EXPECT_NE(what.find(field), std::string::npos) << what;
        }
    };
    CharacterDef def = standing("bad", 0, 0);
    CharacterDef d = def;
    d.radius = 0;
    expectError(d, "radius");
    d = def;
    d.position.x = std::numeric_limits<Real>::quiet_NaN();
    expectError(d, "position");
    d = def;
    d.height = Real(0.4);
    expectError(d, "height");
    d = def;
    d.maxSlope = 2;
    expectError(d, "maxSlope");
    d = def;
    d.stepHeight = -1;
    expectError(d, "stepHeight");
    d = def;
    d.mass = std::numeric_limits<Real>::quiet_NaN();
    expectError(d, "mass");
    d = def;
    d.inputs = {{1, {}, false}, {0, {}, false}};
    expectError(d, "inputs[1].time");
    d = def;
    d.inputs = {{0, {std::numeric_limits<Real>::quiet_NaN(), 0, 0}, false}};
    expectError(d, "inputs[0].velocity");

    const CharacterId c = world.createCharacter(def);
    EXPECT_THROW(world.setCharacterInput(c, {0, std::numeric_limits<Real>::quiet_NaN(), 0}, false), Error);
    EXPECT_THROW(world.destroyBody(world.characterBody(c)), Error);
    world.destroyCharacter(c);
    EXPECT_FALSE(world.isValid(c));
    EXPECT_THROW(world.characterState(c), Error);
    EXPECT_EQ(world.bodyCount(), 0u);
}

}  // namespace
