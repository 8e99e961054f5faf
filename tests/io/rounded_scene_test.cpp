// Scene files and snapshots: the optional "convex_radius" of box, cylinder
// and convex_hull shapes (docs/scene-format.md, docs/shapes.md "Rounded
// shapes") read, checked with the document path in errors, written back,
// compared, built into a World and carried through a snapshot.
#include <gtest/gtest.h>

#include <string>

#include "fulcrum/scene.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"
#include "io/scene_error_expectations.hpp"
#include "world/snapshot_versions.hpp"

namespace fulcrum {
namespace {

using test::expectError;

std::string shapeScene(const std::string& shape) {
    return R"({"bodies": [{"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0]}},
        {"name": "thing", "shape": )" + shape + R"(, "mass": 1, "position": [0, 1, 0]}]})";
}

TEST(RoundedScene, ReadWrittenComparedAndBuilt) {
    const std::string shapes[] = {
        R"({"type": "box", "half_extents": [0.5, 0.25, 0.4], "convex_radius": 0.05})",
        R"({"type": "cylinder", "radius": 0.3, "half_height": 0.5, "convex_radius": 0.1})",
        R"({"type": "convex_hull", "points": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "convex_radius": 0.2})",
    };
    const Real radii[] = {Real(0.05), Real(0.1), Real(0.2)};
    for (int i = 0; i < 3; ++i) {
        SCOPED_TRACE(shapes[i]);
        const Scene scene = parseScene(shapeScene(shapes[i]), "test.json");
        EXPECT_EQ(scene.bodies[1].shape.convexRadius, radii[i]);
        const std::string saved = sceneToJson(scene);
        EXPECT_NE(saved.find("convex_radius"), std::string::npos);
        const Scene again = parseScene(saved, "saved.json");
        EXPECT_TRUE(again == scene) << saved;
        Scene changed = again;
        changed.bodies[1].shape.convexRadius = 0;
        EXPECT_FALSE(changed == scene);
        SceneHandles handles;
        World world = buildWorld(scene, &handles);
        EXPECT_EQ(world.shape(handles.bodies[1]).convexRadius(), radii[i]);

        // A snapshot keeps the radius (format version 8) and resumes bit for bit.
        for (int s = 0; s < 30; ++s) world.step(Real(1) / 60);
        World copy = loadSnapshotFromMemory(saveSnapshotToMemory(world));
        EXPECT_EQ(copy.shape(handles.bodies[1]).convexRadius(), radii[i]);
        for (int s = 0; s < 30; ++s) world.step(Real(1) / 60), copy.step(Real(1) / 60);
        EXPECT_EQ(world.position(handles.bodies[1]).y, copy.position(handles.bodies[1]).y);
        // An older format cannot hold it.
        EXPECT_THROW((void)detail::saveSnapshotAsVersion(world, 7), Error);
    }
    // A plain shape writes no convex_radius.
    const Scene plain = parseScene(shapeScene(R"({"type": "box", "half_extents": [0.5, 0.5, 0.5]})"), "test.json");
    EXPECT_EQ(sceneToJson(plain).find("convex_radius"), std::string::npos);
}

TEST(RoundedScene, ErrorsNameTheField) {
    expectError(shapeScene(R"({"type": "box", "half_extents": [0.5, 0.25, 0.4], "convex_radius": -0.1})"),
                "bodies[1].shape.convex_radius", "convex_radius must be in [0, the smallest half extent = 0.25]");
    expectError(shapeScene(R"({"type": "box", "half_extents": [0.5, 0.25, 0.4], "convex_radius": 0.3})"),
                "bodies[1].shape.convex_radius", "got 0.3");
    expectError(shapeScene(R"({"type": "cylinder", "radius": 0.2, "half_height": 0.5, "convex_radius": 0.25})"),
                "bodies[1].shape.convex_radius", "min(radius, half_height) = 0.2");
    expectError(shapeScene(R"({"type": "convex_hull", "points": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "convex_radius": "x"})"),
                "bodies[1].shape.convex_radius", "expected a number");
    expectError(shapeScene(R"({"type": "sphere", "radius": 0.5, "convex_radius": 0.1})"), "bodies[1].shape.convex_radius",
                "unknown key");
    expectError(shapeScene(R"({"type": "capsule", "radius": 0.5, "half_height": 1, "convex_radius": 0.1})"),
                "bodies[1].shape.convex_radius", "unknown key");
}

}  // namespace
}  // namespace fulcrum
