// Scene files: world.max_contact_pairs (WorldDef::maxContactPairs; docs/
// scene-format.md): read ("auto" or 0 for the automatic limit), validated
// with the path, written only when not the default, round-tripped, and built
// into the World.
#include <gtest/gtest.h>

#include <string>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"
#include "io/scene_error_expectations.hpp"

namespace fulcrum {
namespace {

std::string sceneWith(const std::string& worldKeys) {
    return R"({"world": {"dt": 0.0166667)" + worldKeys + R"(},
  "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.5}, "mass": 1}]})";
}

using test::expectError;

TEST(PairLimitScene, ReadWrittenAndBuilt) {
    EXPECT_EQ(parseScene(sceneWith(R"(, "max_contact_pairs": 5000)"), "a.json").world.maxContactPairs, 5000);
    EXPECT_EQ(parseScene(sceneWith(R"(, "max_contact_pairs": "auto")"), "b.json").world.maxContactPairs, 0);
    EXPECT_EQ(parseScene(sceneWith(R"(, "max_contact_pairs": 0)"), "c.json").world.maxContactPairs, 0);
    EXPECT_EQ(parseScene(sceneWith(""), "d.json").world.maxContactPairs, WorldDef{}.maxContactPairs);
    EXPECT_EQ(parseScene(sceneWith(R"(, "max_contact_pairs": 2147483647)"), "e.json").world.maxContactPairs,
              kMaxContactPairs);

    const Scene limited = parseScene(sceneWith(R"(, "max_contact_pairs": 123)"), "limited.json");
    const std::string saved = sceneToJson(limited);
    EXPECT_NE(saved.find("\"max_contact_pairs\": 123"), std::string::npos) << saved;
    EXPECT_TRUE(parseScene(saved, "saved.json") == limited);
    Scene changed = limited;
    changed.world.maxContactPairs = 124;
    EXPECT_FALSE(changed == limited);
    const std::string plain = sceneToJson(parseScene(sceneWith(""), "plain.json"));
    EXPECT_EQ(plain.find("max_contact_pairs"), std::string::npos) << "written at its default:\n" << plain;

    EXPECT_EQ(buildWorld(limited).settings().maxContactPairs, 123);
}

TEST(PairLimitScene, InvalidValuesNameThePath) {
    expectError(sceneWith(R"(, "max_contact_pairs": -1)"), "world.max_contact_pairs",
                "max_contact_pairs must be between 0 and 2147483647 (0 or \"auto\": automatic), got -1");
    expectError(sceneWith(R"(, "max_contact_pairs": 3000000000)"), "world.max_contact_pairs",
                "must be between 0 and 2147483647 (0 or \"auto\": automatic), got 3e+09");
    expectError(sceneWith(R"(, "max_contact_pairs": 10.5)"), "world.max_contact_pairs", "max_contact_pairs must be an integer, got 10.5");
    expectError(sceneWith(R"(, "max_contact_pairs": "lots")"), "world.max_contact_pairs",
                "expected a pair count (an integer) or \"auto\", got \"lots\"");
    expectError(sceneWith(R"(, "max_contact_pairs": null)"), "world.max_contact_pairs", "or \"auto\", got null");
}

// world.hit_event_threshold (WorldDef::hitEventThreshold): read, validated
// with the path, written only when not the default, round-tripped, built.
TEST(HitEventThresholdScene, ReadWrittenAndBuilt) {
    const Scene quiet = parseScene(sceneWith(R"(, "hit_event_threshold": 2.5)"), "quiet.json");
    EXPECT_EQ(quiet.world.hitEventThreshold, Real(2.5));
    EXPECT_EQ(parseScene(sceneWith(""), "d.json").world.hitEventThreshold, WorldDef{}.hitEventThreshold);
    const std::string saved = sceneToJson(quiet);
    EXPECT_NE(saved.find("\"hit_event_threshold\": 2.5"), std::string::npos) << saved;
    EXPECT_TRUE(parseScene(saved, "saved.json") == quiet);
    Scene changed = quiet;
    changed.world.hitEventThreshold = 3;
    EXPECT_FALSE(changed == quiet);
    EXPECT_EQ(sceneToJson(parseScene(sceneWith(""), "plain.json")).find("hit_event_threshold"), std::string::npos);
    EXPECT_EQ(buildWorld(quiet).settings().hitEventThreshold, Real(2.5));
    expectError(sceneWith(R"(, "hit_event_threshold": -1)"), "world.hit_event_threshold", "hit_event_threshold");
    expectError(sceneWith(R"(, "hit_event_threshold": "fast")"), "world.hit_event_threshold", "expected a number, got a string");
}

}  // namespace
}  // namespace fulcrum
