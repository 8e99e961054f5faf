// Batches (include/fulcrum/batch.hpp, fulcrum/scene_batch.hpp): a world inside a
// batch gives bit for bit its result alone, whatever the batch size and the
// thread count; resets restore bit for bit; overrides act like editing the
// scene file; bad input is a fulcrum::Error naming what is wrong.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "fulcrum/batch.hpp"
#include "fulcrum/scene_batch.hpp"
#include "fulcrum/snapshot.hpp"
#include "dynamics/test_scenes.hpp"

namespace fulcrum {
namespace {

// Contacts (a ball bouncing next to a stack of three boxes on a ground box) and a
// motorised hinge: the parts of a step whose order could depend on scheduling.
constexpr const char* kScene = R"({
  "world": { "gravity": [0, -9.81, 0], "substeps": 4 },
  "bodies": [
    { "name": "ground", "type": "static", "shape": { "type": "box", "half_extents": [5, 0.5, 5] }, "position": [0, -0.5, 0] },
    { "name": "ball", "shape": { "type": "sphere", "radius": 0.25 }, "mass": 1, "position": [2, 1.5, 0], "restitution": 0.5 },
    { "name": "box0", "shape": { "type": "box", "half_extents": [0.5, 0.5, 0.5] }, "mass": 1, "position": [0, 0.5, 0] },
    { "name": "box1", "shape": { "type": "box", "half_extents": [0.5, 0.5, 0.5] }, "mass": 1, "position": [0.1, 1.5, 0] },
    { "name": "box2", "shape": { "type": "box", "half_extents": [0.5, 0.5, 0.5] }, "mass": 1, "position": [0.2, 2.5, 0] },
    { "name": "door", "shape": { "type": "box", "half_extents": [0.5, 1, 0.05] }, "mass": 10, "position": [-3, 3, 0] }
  ],
  "joints": [
    { "name": "hinge", "type": "hinge", "body_a": null, "body_b": "door", "anchor": [-3.5, 3, 0], "axis": [0, 1, 0],
      "motor": { "speed": 1.0, "max_force": 50 } }
  ]
})";

constexpr Real kDt = Real(1) / Real(60);
constexpr int kSteps = 45;

// World w's overrides: every world differs (bounce, gravity, where the ball starts).
SceneOverrides overridesFor(std::size_t w) {
    return {{"bodies[ball].restitution", std::to_string(0.05 * static_cast<double>(w % 20))},
            {"world.gravity", "[0, " + std::to_string(-9.81 + 0.1 * static_cast<double>(w)) + ", 0]"},
            {"bodies[1].position[0]", std::to_string(1.5 + 0.01 * static_cast<double>(w))}};
}

struct State {
    std::vector<Real> positions, orientations, linear, angular;
};

// The state of one world as the batch arrays lay it out.
State stateOf(const World& world) {
    State s;
    for (BodyId id : world.bodies()) {
        const Vec3 p = world.position(id), v = world.linearVelocity(id), w = world.angularVelocity(id);
        const Quat q = world.orientation(id);
        s.positions.insert(s.positions.end(), {p.x, p.y, p.z});
        s.orientations.insert(s.orientations.end(), {q.w, q.x, q.y, q.z});
        s.linear.insert(s.linear.end(), {v.x, v.y, v.z});
        s.angular.insert(s.angular.end(), {w.x, w.y, w.z});
    }
    return s;
}

bool sameBits(const Real* a, const Real* b, std::size_t n) { return std::memcmp(a, b, n * sizeof(Real)) == 0; }

// World w run alone, as a user would without a batch.
World runAlone(std::size_t w, int steps) {
    const SceneOverrides o = overridesFor(w);
    World world = buildWorld(parseSceneWithOverrides(kScene, o));
    for (int s = 0; s < steps; ++s) world.step(kDt);
    return world;
}

std::vector<SceneOverrides> overridesOfBatch(std::size_t n) {
    std::vector<SceneOverrides> all;
    for (std::size_t w = 0; w < n; ++w) all.push_back(overridesFor(w));
    return all;
}

void expectWorldsEqualAlone(const Batch& batch, int steps) {
    const std::size_t n = batch.size(), bodies = batch.bodyCount();
    State got{std::vector<Real>(n * bodies * 3), std::vector<Real>(n * bodies * 4), std::vector<Real>(n * bodies * 3),
              std::vector<Real>(n * bodies * 3)};
    batch.positions(got.positions);
    batch.orientations(got.orientations);
    batch.linearVelocities(got.linear);
    batch.angularVelocities(got.angular);
    for (std::size_t w = 0; w < n; ++w) {
        const State alone = stateOf(runAlone(w, steps));
        ASSERT_EQ(alone.positions.size(), bodies * 3);
        EXPECT_TRUE(sameBits(&got.positions[w * bodies * 3], alone.positions.data(), bodies * 3)) << "world " << w;
        EXPECT_TRUE(sameBits(&got.orientations[w * bodies * 4], alone.orientations.data(), bodies * 4)) << "world " << w;
        EXPECT_TRUE(sameBits(&got.linear[w * bodies * 3], alone.linear.data(), bodies * 3)) << "world " << w;
        EXPECT_TRUE(sameBits(&got.angular[w * bodies * 3], alone.angular.data(), bodies * 3)) << "world " << w;
    }
}

TEST(Batch, EachWorldEqualsItsRunAloneForAnyCountAndThreads) {
    for (std::size_t n : {1u, 3u, 17u}) {
        for (int threads : {1, 2, 3}) {
            SCOPED_TRACE("N=" + std::to_string(n) + " threads=" + std::to_string(threads));
            const std::vector<SceneOverrides> overrides = overridesOfBatch(n);
            Batch batch = makeSceneBatch(kScene, n, overrides, BatchDef{threads});
            batch.step(kDt, 20);  // several calls, as a learning loop makes them
            batch.step(kDt, kSteps - 20);
            expectWorldsEqualAlone(batch, kSteps);
        }
    }
}

TEST(Batch, WorldsReallyDifferAndMove) {
    // Guards the test above against comparing worlds that never moved or are all alike.
    Batch batch = makeSceneBatch(kScene, 3, overridesOfBatch(3), BatchDef{2});
    std::vector<Real> before(3 * batch.bodyCount() * 3), after(before.size());
    batch.positions(before);
    batch.step(kDt, kSteps);
    batch.positions(after);
    const std::size_t ball = 1 * 3 + 1;  // y of body 1 (the ball) in world 0
    EXPECT_LT(after[ball], before[ball] - Real(0.5));
    const std::size_t stride = batch.bodyCount() * 3;
    EXPECT_NE(after[ball], after[stride + ball]);
}

TEST(Batch, OverrideActsLikeEditingTheFile) {
    std::string edited = kScene;
    const std::string from = "\"restitution\": 0.5", to = "\"restitution\": 0.25";
    edited.replace(edited.find(from), from.size(), to);
    const Scene byOverride = parseSceneWithOverrides(kScene, SceneOverrides{{"bodies[ball].restitution", "0.25"}});
    EXPECT_EQ(byOverride, parseScene(edited));
    EXPECT_NE(byOverride, parseScene(kScene));
    // A key the file leaves at its default is added; so are objects on the way.
    const Scene friction = parseSceneWithOverrides(kScene, SceneOverrides{{"bodies[door].friction", "0.9"}});
    EXPECT_EQ(friction.bodies[5].def.friction, Real(0.9));
    const Scene noWorld = parseSceneWithOverrides(R"({"bodies": []})", SceneOverrides{{"world.gravity", "[0,-1.6,0]"}});
    EXPECT_EQ(noWorld.world.gravity, (Vec3{0, Real(-1.6), 0}));
}

TEST(Batch, ResetRestoresTheStartAndSnapshotsBitForBit) {
    Batch batch = makeSceneBatch(kScene, 3, overridesOfBatch(3), BatchDef{2});
    const std::size_t per = batch.bodyCount() * 3;
    std::vector<Real> start(3 * per), mid(3 * per), now(3 * per);
    batch.positions(start);
    batch.step(kDt, 10);
    const std::vector<std::uint8_t> snap = batch.snapshot(1);
    batch.positions(mid);
    batch.step(kDt, 20);
    batch.reset(0);
    batch.reset(1, snap);
    batch.positions(now);
    EXPECT_TRUE(sameBits(&now[0], &start[0], per));
    EXPECT_TRUE(sameBits(&now[per], &mid[per], per));
    // And they continue as if never stepped / never interrupted.
    batch.step(kDt, kSteps - 10);
    batch.reset(1);
    batch.step(kDt, 10);
    // World 0: kSteps steps since its reset; world 1: 10 since its second; world 2, never reset: 10+20+kSteps.
    const State w0 = stateOf(runAlone(0, kSteps)), w1 = stateOf(runAlone(1, 10)), w2 = stateOf(runAlone(2, kSteps + 30));
    batch.positions(now);
    EXPECT_TRUE(sameBits(&now[0], w0.positions.data(), per));
    EXPECT_TRUE(sameBits(&now[per], w1.positions.data(), per));
    EXPECT_TRUE(sameBits(&now[2 * per], w2.positions.data(), per));
}

TEST(Batch, ActionsFromArraysActLikeTheWorldCalls) {
    Batch batch = makeSceneBatch(kScene, 2, {}, BatchDef{2});
    World alone = buildWorld(parseScene(kScene));
    const std::size_t bodies = batch.bodyCount();
    std::vector<Real> velocities(2 * bodies * 3, 0), forces(2 * bodies * 3, 0), speeds(2 * batch.jointCount(), 0);
    velocities[1 * 3 + 0] = 3;  // world 0's ball moves along +x
    forces[bodies * 3 + 1 * 3 + 1] = 50;  // world 1's ball is pushed up
    speeds[0] = -2;            // world 0's hinge motor turns the other way
    batch.setLinearVelocities(velocities);
    batch.applyForces(forces);
    batch.setJointMotorSpeeds(speeds);
    batch.step(kDt, 1);

    const auto ids = alone.bodies();
    for (std::size_t b = 0; b < bodies; ++b) {
        if (alone.bodyType(ids[b]) != BodyType::Static) alone.setLinearVelocity(ids[b], Vec3{});
    }
    alone.setLinearVelocity(ids[1], Vec3{3, 0, 0});
    JointMotor motor = alone.jointDef(alone.joints()[0]).motor;
    motor.speed = -2;
    alone.setJointMotor(alone.joints()[0], motor);
    alone.step(kDt);
    std::vector<Real> got(2 * bodies * 3);
    batch.positions(got);
    EXPECT_TRUE(sameBits(got.data(), stateOf(alone).positions.data(), bodies * 3));
    // The pushed ball: 50 N on 1 kg beats gravity, so it rises.
    EXPECT_GT(got[bodies * 3 + 1 * 3 + 1], Real(1.5));
}

using test::errorOf;

TEST(Batch, BadInputIsAnErrorNamingIt) {
    Batch batch = makeSceneBatch(kScene, 2, {}, BatchDef{1});
    std::vector<Real> wrong(5);
    EXPECT_NE(errorOf([&] { batch.positions(wrong); }).find("positions: array of 5 values, expected 36"), std::string::npos);
    EXPECT_NE(errorOf([&] { batch.setLinearVelocities(wrong); }).find("setLinearVelocities"), std::string::npos);
    EXPECT_NE(errorOf([&] { batch.setJointMotorSpeeds(wrong); }).find("expected 2 (2 worlds x 1 joints)"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { batch.reset(2); }).find("world index 2 out of range"), std::string::npos);
    const std::vector<std::uint8_t> junk(40, 7);
    EXPECT_NE(errorOf([&] { batch.reset(0, junk); }).find("snapshot"), std::string::npos);
    EXPECT_NE(errorOf([] { Batch b(std::vector<World>{}); }).find("no worlds"), std::string::npos);

    const auto overrideError = [](const char* path, const char* value) {
        return errorOf([&] { (void)parseSceneWithOverrides(kScene, SceneOverrides{{path, value}}, "s.json"); });
    };
    EXPECT_EQ(overrideError("bodies[bal].restitution", "0.3"),
              "s.json: bodies[bal].restitution: no element named 'bal' in 'bodies' (names: ground, ball, box0, box1, box2, door)");
    EXPECT_NE(overrideError("bodies[9].mass", "1").find("s.json: bodies[9].mass: index 9 out of range: 'bodies' has 6 elements"),
              std::string::npos);
    EXPECT_NE(overrideError("bodies[ball].restitutoin", "0.3").find("bodies[ball].restitutoin: value 0.3 refused: bodies[1].restitutoin: unknown key"),
              std::string::npos);
    EXPECT_NE(overrideError("bodies[ball].restitution", "-2").find("bodies[ball].restitution: value -2 refused: bodies[1].restitution"),
              std::string::npos);
    EXPECT_NE(overrideError("bodies[ball].restitution", "0.3x").find("value is not valid JSON: 0.3x"), std::string::npos);
    EXPECT_NE(overrideError("bodies[ball", "1").find("malformed path"), std::string::npos);
    // Found by fuzz/overrides_fuzz.cpp: a path that is not UTF-8 (its key
    // went into the document, and writing that threw nlohmann's type_error).
    EXPECT_NE(overrideError("bodies[1].shape\xf0" "9.radius", "0.5").find("the path is not UTF-8 text"), std::string::npos);
    EXPECT_NE(overrideError("world.gravity.x", "1").find("'gravity' is an array, not an object"), std::string::npos);
    // Checked before any world is built: world 2 of 3 is wrong.
    std::vector<SceneOverrides> sets = overridesOfBatch(3);
    sets[2].push_back({"bodies[nobody].mass", "1"});
    EXPECT_NE(errorOf([&] { (void)makeSceneBatch(kScene, 3, sets); }).find("bodies[nobody].mass"), std::string::npos);
    EXPECT_NE(errorOf([&] { (void)makeSceneBatch(kScene, 4, sets); }).find("3 sets of overrides for 4 worlds"),
              std::string::npos);
}

TEST(Batch, WorldsOfDifferentScenesGiveTheirOwnResultsAndRefuseCommonArrays) {
    const std::string second = R"({"bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.5}, "mass": 2, "position": [0, 3, 0]}]})";
    const std::vector<std::string> scenes{kScene, second};
    Batch batch = makeSceneBatch(scenes, BatchDef{2});
    batch.step(kDt, 10);
    World alone = buildWorld(parseScene(second));
    for (int s = 0; s < 10; ++s) alone.step(kDt);
    EXPECT_EQ(stateOf(batch.world(1)).positions, stateOf(alone).positions);
    EXPECT_NE(errorOf([&] { (void)batch.bodyCount(); }).find("world 1 has 1 bodies, world 0 has 6"), std::string::npos);
}

}  // namespace
}  // namespace fulcrum
