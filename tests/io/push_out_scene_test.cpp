// Scene files: world.push_out_grown_overlaps (WorldDef::pushOutGrownOverlaps;
// docs/scene-format.md, docs/solver.md "Grown overlaps"): read, validated
// with the file and the path, written only when not the default (false),
// round-tripped, and built into the World, where it steps as the C++ world
// with the setting does, bit for bit.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"
#include "io/scene_error_expectations.hpp"
#include "support/same_motion.hpp"

namespace fulcrum {
namespace {

using test::expectError;
using test::sameMotion;

// No gravity: a row of five unit boxes (1 kg, frictionless) touching face to
// face along x, at rest, struck end-on by a 10 kg box at 20 m/s: the blow
// drives each box into the next within a step, which the push-out undoes
// (tests/solver/grown_overlap_test.cpp, GrownOverlap.StruckRowIsPushedApartWithoutAddingEnergy).
std::string struckRowScene(const std::string& worldKeys) {
    std::string bodies;
    for (int i = 0; i < 5; ++i) {
        bodies += R"({"shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 1, "friction": 0, "position": [)" +
                  std::to_string(i) + ", 0, 0]},\n";
    }
    bodies += R"({"shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 10, "friction": 0, "position": [-1.5, 0, 0],
              "linear_velocity": [20, 0, 0]})";
    return R"({"world": {"gravity": [0, 0, 0], "dt": 0.016666666666666666)" + worldKeys + "},\n\"bodies\": [" + bodies + "]}";
}

// The same row built through the C++ API.
World struckRowWorld(bool pushOut, std::vector<BodyId>& ids) {
    WorldDef def;
    def.gravity = {0, 0, 0};
    def.pushOutGrownOverlaps = pushOut;
    World world(def);
    const auto box = [&](Real x, Real mass, Real vx) {
        BodyDef d;
        d.shape = Shape::box(Vec3::splat(Real(0.5)));
        d.mass = mass;
        d.friction = 0;
        d.position = {x, 0, 0};
        d.linearVelocity = {vx, 0, 0};
        ids.push_back(world.createBody(d));
    };
    for (int i = 0; i < 5; ++i) box(Real(i), 1, 0);
    box(Real(-1.5), 10, 20);
    return world;
}

TEST(PushOutScene, ReadWrittenOnlyWhenOnAndRoundTripped) {
    EXPECT_TRUE(parseScene(struckRowScene(R"(, "push_out_grown_overlaps": true)"), "on.json").world.pushOutGrownOverlaps);
    EXPECT_FALSE(parseScene(struckRowScene(R"(, "push_out_grown_overlaps": false)"), "off.json").world.pushOutGrownOverlaps);
    EXPECT_FALSE(parseScene(struckRowScene(""), "plain.json").world.pushOutGrownOverlaps);  // WorldDef's default

    const Scene on = parseScene(struckRowScene(R"(, "push_out_grown_overlaps": true)"), "on.json");
    const std::string saved = sceneToJson(on);
    EXPECT_NE(saved.find("\"push_out_grown_overlaps\": true"), std::string::npos) << saved;
    EXPECT_TRUE(parseScene(saved, "saved.json") == on);
    // The comparison sees the field.
    Scene changed = on;
    changed.world.pushOutGrownOverlaps = false;
    EXPECT_FALSE(changed == on);
    // The default is not written: files of scenes without it stay as they were.
    const std::string plain = sceneToJson(parseScene(struckRowScene(R"(, "push_out_grown_overlaps": false)"), "off.json"));
    EXPECT_EQ(plain.find("push_out_grown_overlaps"), std::string::npos) << "written at its default:\n" << plain;
}

TEST(PushOutScene, BadValuesNameTheFileAndPath) {
    // expectError checks the file name (test.json), the path, the reason and one line.
    expectError(struckRowScene(R"(, "push_out_grown_overlaps": 1)"), "world.push_out_grown_overlaps", "expected true or false, got a number");
    expectError(struckRowScene(R"(, "push_out_grown_overlaps": "true")"), "world.push_out_grown_overlaps", "expected true or false, got a string");
    expectError(struckRowScene(R"(, "push_out_grown_overlaps": null)"), "world.push_out_grown_overlaps", "expected true or false");
    expectError(struckRowScene(R"(, "push_out_grown_overlap": true)"), "world.push_out_grown_overlap", "did you mean 'push_out_grown_overlaps'?");
}

// The key reaches the solver: the scene with it on steps as the C++ world
// with WorldDef::pushOutGrownOverlaps on, and the scene with it off as the
// C++ world with it off, bit for bit every step; and the push-out does act
// here (on and off part within the 60 steps), so the comparison would see a
// key that was read but not applied.
TEST(PushOutScene, SceneWorldStepsAsTheCppWorldBitForBit) {
    for (const bool pushOut : {true, false}) {
        const Scene scene = parseScene(struckRowScene(std::string(R"(, "push_out_grown_overlaps": )") + (pushOut ? "true" : "false")),
                                       "row.json");
        SceneHandles handles;
        World fromFile = buildWorld(scene, &handles);
        EXPECT_EQ(fromFile.settings().pushOutGrownOverlaps, pushOut);
        std::vector<BodyId> ids;
        World direct = struckRowWorld(pushOut, ids);
        ASSERT_EQ(handles.bodies.size(), ids.size());
        for (int s = 0; s < 60; ++s) {
            fromFile.step(scene.dt);
            direct.step(scene.dt);
            for (std::size_t i = 0; i < ids.size(); ++i) {
                ASSERT_TRUE(sameMotion(fromFile, handles.bodies[i], direct, ids[i])) << "push-out " << pushOut << ", step " << s << ", body " << i;
            }
        }
    }
    std::vector<BodyId> onIds, offIds;
    World on = struckRowWorld(true, onIds), off = struckRowWorld(false, offIds);
    bool parted = false;
    for (int s = 0; s < 60 && !parted; ++s) {
        on.step(Real(1) / 60);
        off.step(Real(1) / 60);
        for (std::size_t i = 0; i < onIds.size(); ++i) parted = parted || !sameMotion(on, onIds[i], off, offIds[i]);
    }
    EXPECT_TRUE(parted) << "the push-out never acted: the test does not test the key";
}

}  // namespace
}  // namespace fulcrum
