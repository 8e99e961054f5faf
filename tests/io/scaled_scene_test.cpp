// Scene files: "scale" on any shape and "decompose" on a mesh (docs/scene-format.md),
// read with the document path in errors, written back as given, compared, and
// built into the shapes Shape::scaled and Shape::convexDecomposition make.
#include <gtest/gtest.h>

#include <string>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"
#include "io/scene_error_expectations.hpp"

namespace fulcrum {
namespace {

using test::expectError;

std::string bodyScene(const std::string& shape, const std::string& type = "dynamic") {
    return R"({"bodies": [{"name": "b", "type": ")" + type + R"(", "shape": )" + shape + "}]}";
}

// An L of three unit cubes as a closed mesh: the (x, y) cells (0, 0), (1, 0), (0, 1), z in [0, 1].
const std::string kL = R"({"type": "mesh", "decompose": true, "vertices": [
    [0,0,0],[2,0,0],[2,1,0],[1,1,0],[1,2,0],[0,2,0],
    [0,0,1],[2,0,1],[2,1,1],[1,1,1],[1,2,1],[0,2,1]],
  "triangles": [
    [0,3,1],[1,3,2],[0,5,3],[3,5,4],
    [6,7,9],[7,8,9],[6,9,11],[9,10,11],
    [0,1,7],[0,7,6],[1,2,8],[1,8,7],[2,3,9],[2,9,8],[3,4,10],[3,10,9],[4,5,11],[4,11,10],[5,0,6],[5,6,11]]})";

TEST(ScaledScene, ScaleIsReadWrittenAndBuilt) {
    const Scene scene = parseScene(bodyScene(R"({"type": "box", "half_extents": [0.5, 0.5, 0.5], "scale": [2, 0.5, -1]})"));
    EXPECT_EQ(scene.bodies[0].shape.scale, (Vec3{2, Real(0.5), -1}));
    const std::string saved = sceneToJson(scene);
    EXPECT_NE(saved.find(R"("scale")"), std::string::npos) << saved;
    EXPECT_TRUE(parseScene(saved) == scene);
    Scene changed = scene;
    changed.bodies[0].shape.scale.y = 1;
    EXPECT_FALSE(changed == scene);
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    EXPECT_EQ(world.shape(handles.bodies[0]).halfExtents(), (Vec3{1, Real(0.25), Real(0.5)}));

    // A uniform scale is one number; children scale inside a scaled compound.
    const Scene compound = parseScene(bodyScene(R"({"type": "compound", "scale": 2, "children": [
        {"shape": {"type": "sphere", "radius": 0.5, "scale": 3}, "position": [1, 0, 0]}]})"));
    const std::string again = sceneToJson(compound);
    EXPECT_NE(again.find(R"("scale": 2)"), std::string::npos) << again;  // a uniform scale: one number
    EXPECT_TRUE(parseScene(again) == compound);
    World w2 = buildWorld(compound, &handles);
    const auto kids = w2.shape(handles.bodies[0]).children();
    ASSERT_EQ(kids.size(), 1u);
    EXPECT_EQ(kids[0].shape.radius(), 3);
    EXPECT_EQ(kids[0].transform.p.x, 2);
}

TEST(ScaledScene, BadScalesNameThePath) {
    expectError(bodyScene(R"({"type": "box", "half_extents": [1, 1, 1], "scale": [1, 0, 1]})"), "bodies[0].shape.scale[1]",
                "must not be zero");
    expectError(bodyScene(R"({"type": "box", "half_extents": [1, 1, 1], "scale": 0})"), "bodies[0].shape.scale", "must not be zero");
    expectError(bodyScene(R"({"type": "box", "half_extents": [1, 1, 1], "scale": [1, 1]})"), "bodies[0].shape.scale",
                "expected an array of 3 numbers");
    expectError(bodyScene(R"({"type": "sphere", "radius": 1, "scale": [1, 2, 1]})"), "bodies[0].shape",
                "a sphere only takes a uniform scale");
    expectError(bodyScene(R"({"type": "box", "half_extents": [1, 1, 1], "decompose": true})"), "bodies[0].shape.decompose",
                "only a mesh can be decomposed");
    expectError(bodyScene(R"({"type": "mesh", "vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]]})"),
                "bodies[0].shape.type", "add \"decompose\": true");
}

TEST(ScaledScene, DecomposedMeshIsADynamicCompoundOfHulls) {
    const Scene scene = parseScene(bodyScene(kL));
    EXPECT_TRUE(scene.bodies[0].shape.decompose);
    const std::string saved = sceneToJson(scene);
    EXPECT_NE(saved.find(R"("decompose": true)"), std::string::npos) << saved;
    EXPECT_TRUE(parseScene(saved) == scene);
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    const Shape& shape = world.shape(handles.bodies[0]);
    ASSERT_EQ(shape.type(), ShapeType::Compound);
    EXPECT_EQ(shape.children().size(), 2u);
    EXPECT_NEAR(shape.volume(), 3, 1e-5);
    // Not closed: the error names the body's shape and says why.
    const Scene open = parseScene(bodyScene(R"({"type": "mesh", "decompose": true, "vertices": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]],
        "triangles": [[0,2,1],[0,1,3],[1,2,3]]})"));
    try {
        (void)buildWorld(open);
        ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("bodies[0].shape"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace fulcrum
