// Characters in scene files: the "characters" section read, checked, written
// back and built, and scenes/character_stairs.json run to its checkpoints.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <fulcrum/fulcrum.hpp>
#include <fulcrum/scene.hpp>

namespace {

using namespace fulcrum;

std::string sceneWith(const std::string& character) {
    return R"({"bodies": [{"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0,1,0], "offset": 0}}],
              "characters": [)" + character + "]}";
}

TEST(CharacterScene, ReadsWritesAndBuilds) {
    const Scene scene = parseScene(sceneWith(R"({"name": "hero", "position": [0, 0.91, 0], "radius": 0.3, "height": 1.8,
        "mass": 80, "max_slope": 0.785, "step_height": 0.3,
        "inputs": [{"time": 0, "velocity": [1, 0, 0], "jump": false}, {"time": 0.5, "velocity": [0, 0, 0]}]})"));
    ASSERT_EQ(scene.characters.size(), 1u);
    EXPECT_EQ(scene.characters[0].def.inputs.size(), 2u);
    EXPECT_EQ(parseScene(sceneToJson(scene)), scene);
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    ASSERT_EQ(handles.characters.size(), 1u);
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
    // 0.5 s at 1 m/s, then standing: inputs hold until the next one.
    const CharacterState s = world.characterState(handles.characters[0]);
    EXPECT_NEAR(s.position.x, Real(0.5), Real(0.02));
    EXPECT_EQ(s.ground, GroundState::OnGround);
}

TEST(CharacterScene, BadValuesNameThePath) {
    const auto expectPath = [](const std::string& character, const std::string& path) {
        try {
            parseScene(sceneWith(character));
            ADD_FAILURE() << "no error for " << path;
        } catch (const SceneError& e) {
            EXPECT_EQ(e.path(), path) << e.what();
        }
    };
    expectPath(R"({"name": "a", "position": [0, 1, 0], "radius": 0})", "characters[0].radius");
    expectPath(R"({"name": "a", "position": [0, 1, 0], "radius": 0.5, "height": 0.6})", "characters[0].height");
    expectPath(R"({"name": "a"})", "characters[0]");  // "missing key 'position'"
    expectPath(R"({"name": "a", "position": [0, 1, 0], "max_slope": 2})", "characters[0].max_slope");
    expectPath(R"({"name": "a", "position": [0, 1, 0], "inputs": [{"time": 1}, {"time": 0}]})", "characters[0].inputs[1].time");
    expectPath(R"({"name": "a", "position": [0, 1, 0], "inputs": [{"time": 0, "speed": 1}]})", "characters[0].inputs[0].speed");
    expectPath(R"({"name": "a", "position": [0, 1, 0], "stepheight": 1})", "characters[0].stepheight");
}

TEST(CharacterScene, StairsAndTurntable) {
    const Scene scene = loadScene(std::string(FULCRUM_SOURCE_DIR) + "/scenes/character_stairs.json");
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    const CharacterId hero = handles.characters.at(0);
    const BodyId turntable = world.findBody("turntable");
    const Real feetAboveCentre = Real(0.9);
    // Up the stairs (1 m) and onto the turntable by t = 4.5 s.
    for (int i = 0; i < 270; ++i) world.step(scene.dt);
    CharacterState s = world.characterState(hero);
    EXPECT_EQ(s.ground, GroundState::OnGround);
    EXPECT_EQ(s.groundBody, turntable);
    EXPECT_NEAR(s.position.y - feetAboveCentre, Real(1.0), Real(0.03));
    // Riding it without input: the same spot on it until the jump at 7 s.
    const Vec3 spot = inverseTransformPoint(world.transform(turntable), s.position);
    for (int i = 270; i < 415; ++i) world.step(scene.dt);
    s = world.characterState(hero);
    EXPECT_LT(length(inverseTransformPoint(world.transform(turntable), s.position) - spot), Real(0.01));
    // The jump leaves the ground.
    for (int i = 415; i < 440; ++i) world.step(scene.dt);
    EXPECT_EQ(world.characterState(hero).ground, GroundState::InAir);
}

}  // namespace
