// The scene format's optional top-level "version" key: 1 is read, any other
// version is refused with a message naming the key and both versions (before
// the key check, so a newer file is not refused for its new keys).
#include <gtest/gtest.h>

#include "fulcrum/scene.hpp"

namespace fulcrum {
namespace {

std::string errorOf(const char* json) {
    try {
        (void)parseScene(json, "s.json");
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

TEST(SceneVersion, VersionOneAndNoVersionAreRead) {
    const Scene a = parseScene(R"({"version": 1, "bodies": [{"name": "b", "shape": {"type": "sphere", "radius": 0.5}, "mass": 1, "position": [0, 2, 0]}]})", "a");
    const Scene b = parseScene(R"({"bodies": [{"name": "b", "shape": {"type": "sphere", "radius": 0.5}, "mass": 1, "position": [0, 2, 0]}]})", "b");
    ASSERT_EQ(a.bodies.size(), 1u);
    EXPECT_EQ(a.bodies[0].def.position, b.bodies[0].def.position);
}

TEST(SceneVersion, OtherVersionsAreRefusedClearly) {
    EXPECT_EQ(errorOf(R"({"version": 2, "bodies": [], "a_future_key": {}})"),
              "s.json:1: version: unsupported scene format version 2 (this build reads version 1)");
    EXPECT_NE(errorOf(R"({"version": "1"})").find("version: expected an integer"), std::string::npos);
    EXPECT_NE(errorOf(R"({"version": 0})").find("version must be between 1 and"), std::string::npos);
}

}  // namespace
}  // namespace fulcrum
