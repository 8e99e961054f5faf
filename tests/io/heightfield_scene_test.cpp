// Scene files: the heightfield shape ({"type": "heightfield", "rows", "columns",
// "spacing", "heights", "holes"}; docs/terrain.md) read with the document path
// in errors, written back, compared, and built into a World.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"
#include "io/scene_error_expectations.hpp"

namespace fulcrum {
namespace {

using test::expectError;

std::string fieldScene(const std::string& shapeKeys, const std::string& type = "static") {
    return R"({"bodies": [{"name": "terrain", "type": ")" + type + R"(", "shape": {"type": "heightfield")" + shapeKeys +
           R"(}}, {"name": "ball", "shape": {"type": "sphere", "radius": 0.25}, "mass": 1, "position": [0.75, 2, 0.5]}]})";
}

const std::string kGood = R"(, "rows": 3, "columns": 4, "spacing": [0.5, 0.75],
    "heights": [0.3, 0, 0, 0.3, 0.3, 0, 0, 0.3, 0.3, 0, 0, 0.3], "holes": [5])";

TEST(HeightFieldScene, ReadWrittenComparedAndBuilt) {
    const Scene scene = parseScene(fieldScene(kGood), "terrain.json");
    const ShapeDesc& s = scene.bodies[0].shape;
    EXPECT_EQ(s.type, ShapeType::HeightField);
    EXPECT_EQ(s.rows, 3u);
    EXPECT_EQ(s.columns, 4u);
    EXPECT_EQ(s.spacingX, Real(0.5));
    EXPECT_EQ(s.spacingZ, Real(0.75));
    ASSERT_EQ(s.heights.size(), 12u);
    EXPECT_EQ(s.heights[3], Real(0.3));
    EXPECT_EQ(s.heights[5], Real(0));
    EXPECT_EQ(s.holes, std::vector<std::uint32_t>{5});

    const std::string saved = sceneToJson(scene);
    const Scene again = parseScene(saved, "saved.json");
    EXPECT_TRUE(again == scene) << saved;
    Scene changed = again;
    changed.bodies[0].shape.heights[7] = std::nextafter(changed.bodies[0].shape.heights[7], Real(1));
    EXPECT_FALSE(changed == scene);
    changed = again;
    changed.bodies[0].shape.holes.clear();
    EXPECT_FALSE(changed == scene);

    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    const Shape& shape = world.shape(handles.bodies[0]);
    ASSERT_EQ(shape.type(), ShapeType::HeightField);
    EXPECT_EQ(shape.heightField().columns, 4u);
    EXPECT_EQ(shape.heightField().holes, std::vector<std::uint32_t>{5});
    for (int i = 0; i < 120; ++i) world.step(Real(1) / 60);
    // The ball rests in the field's flat valley (height 0 between x = 0.5 and 1) instead of falling through.
    EXPECT_NEAR(world.position(handles.bodies[1]).y, Real(0.25), Real(0.01));
}

TEST(HeightFieldScene, ErrorsNameThePath) {
    expectError(fieldScene(R"(, "rows": 1, "columns": 2, "spacing": [1, 1], "heights": [0, 0])"), "bodies[0].shape.rows",
                "between 2 and 4097");
    expectError(fieldScene(R"(, "rows": 2, "columns": 5000, "spacing": [1, 1], "heights": [])"), "bodies[0].shape.columns",
                "between 2 and 4097");
    expectError(fieldScene(R"(, "rows": 2, "columns": 2, "spacing": [1, 0], "heights": [0, 0, 0, 0])"),
                "bodies[0].shape.spacing[1]", "must be positive");
    expectError(fieldScene(R"(, "rows": 2, "columns": 2, "spacing": [-1, 1], "heights": [0, 0, 0, 0])"),
                "bodies[0].shape.spacing[0]", "must be positive");
    expectError(fieldScene(R"(, "rows": 2, "columns": 2, "spacing": [1], "heights": [0, 0, 0, 0])"), "bodies[0].shape.spacing",
                "expected [dx, dz]");
    expectError(fieldScene(R"(, "rows": 2, "columns": 2, "spacing": [1, 1], "heights": [0, 0, 0])"), "bodies[0].shape.heights",
                "expected rows * columns = 2 * 2 = 4 heights, got 3");
    expectError(fieldScene(R"(, "rows": 2, "columns": 2, "spacing": [1, 1], "heights": [0, 0, "x", 0])"),
                "bodies[0].shape.heights[2]", "expected a number");
    // Beyond Real: 1e300 in the float build; the double build's JSON numbers all fit, so 1e999 there.
    const std::string beyondReal = sizeof(Real) == sizeof(float) ? "1e300" : "1e999";
    expectError(fieldScene(R"(, "rows": 2, "columns": 2, "spacing": [1, 1], "heights": [0, 0, )" + beyondReal + ", 0]"),
                "bodies[0].shape.heights[2]", "out of range");
    expectError(fieldScene(R"(, "rows": 2, "columns": 2, "spacing": [1, 1], "heights": [0, 0, 0, 0], "holes": [1])"),
                "bodies[0].shape.holes[0]", "between 0 and 0");
    expectError(fieldScene(R"(, "columns": 2, "spacing": [1, 1], "heights": [0, 0, 0, 0])"), "bodies[0].shape", "missing key 'rows'");
    expectError(fieldScene(R"(, "rows": 2, "columns": 2, "spacing": [1, 1], "heights": [0, 0, 0, 0], "hole": [0])"),
                "bodies[0].shape.hole", "unknown key");
    expectError(fieldScene(kGood, "dynamic"), "bodies[0].shape.type", "a heightfield shape can only belong to a static body");
    // What only the builder sees (every cell a hole) is reported at the body's shape when the world is built.
    const Scene allHoles =
        parseScene(fieldScene(R"(, "rows": 2, "columns": 2, "spacing": [1, 1], "heights": [0, 0, 0, 0], "holes": [0])"), "holes.json");
    try {
        (void)buildWorld(allHoles);
        ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("holes.json"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bodies[0].shape"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("every cell is a hole"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace fulcrum
