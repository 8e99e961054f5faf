// The scene file's "urdf" entry and `fulcrum run ROBOT.urdf` (docs/robots.md):
// the robot's links and joints join the scene with their names and drives;
// bad entries are SceneErrors naming the entry.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "fulcrum/scene.hpp"
#include "fulcrum/urdf.hpp"
#include "io/run.hpp"
#include "support/real_eq.hpp"

namespace {

using namespace fulcrum;

std::string sceneIn(const char* folder) { return (std::filesystem::path(FULCRUM_SOURCE_DIR) / folder / "scene.json").string(); }

std::string sceneError(const std::string& json) {
    try {
        parseScene(json, sceneIn("tests/robots"));
    } catch (const SceneError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(UrdfScene, EntryAddsLinksJointsAndDrives) {
    const Scene scene = parseScene(R"({
      "world": {"gravity": [0, 0, -9.81]},
      "bodies": [{"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0, 0, 1]}}],
      "urdf": [{"file": "slider_load.urdf", "position": [1, 2, 0], "fixed_base": true,
                "drives": {"lift": {"position": 0.1, "stiffness": 20000, "damping": 400}}}]})",
                                   sceneIn("tests/robots"));
    ASSERT_EQ(scene.bodies.size(), 3u);
    EXPECT_EQ(scene.bodies[1].def.name, "frame");
    EXPECT_EQ(scene.bodies[1].def.type, BodyType::Static);
    EXPECT_EQ(scene.bodies[2].def.name, "load");
    EXPECT_EQ(scene.bodies[2].def.position, (Vec3{1, 2, 1}));
    ASSERT_EQ(scene.joints.size(), 1u);
    const JointDef& lift = scene.joints[0].def;
    EXPECT_EQ(lift.type, JointType::Slider);
    EXPECT_TRUE(lift.spring.enabled);
    EXPECT_REAL_EQ(lift.spring.target, Real(0.1));
    EXPECT_REAL_EQ(lift.spring.stiffness, 20000);
    // Saved and read back: the same scene (the robot as plain bodies and joints).
    EXPECT_TRUE(parseScene(sceneToJson(scene), "saved") == scene);

    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    for (int i = 0; i < 600; ++i) world.step(Real(1) / 60);
    EXPECT_NEAR(world.jointEffort(handles.joints[0]), Real(2.5 * 9.81), Real(0.005 * 2.5 * 9.81));
}

// A floating joint's axes driven from the scene file ("joint/z"): the box
// hangs m g / k below its target, and the vertical effort reads m g (0.5 %).
TEST(UrdfScene, DrivesNameSixDofAxes) {
    const Scene scene = parseScene(R"({
      "world": {"gravity": [0, 0, -9.81]},
      "urdf": [{"file": "floating_box.urdf", "fixed_base": true,
                "drives": {"float/x": {"position": 0.1, "stiffness": 20000, "damping": 400},
                           "float/y": {"stiffness": 20000, "damping": 400},
                           "float/z": {"position": 0.3, "stiffness": 20000, "damping": 400},
                           "float/rx": {"stiffness": 40, "damping": 2.2}, "float/ry": {"stiffness": 40, "damping": 2.2},
                           "float/rz": {"position": 0.2, "stiffness": 40, "damping": 2.2}}}]})",
                                   sceneIn("tests/robots"));
    ASSERT_EQ(scene.joints.size(), 1u);
    const JointDef& j = scene.joints[0].def;
    EXPECT_EQ(j.type, JointType::SixDof);
    EXPECT_REAL_EQ(j.axes[kAxisZ].spring.target, Real(0.3));
    EXPECT_TRUE(parseScene(sceneToJson(scene), "saved") == scene);
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    for (int i = 0; i < 3 * 240; ++i) world.step(Real(1) / 240);
    const SixDofReading r = world.sixDofReading(handles.joints[0]);
    const double mg = 2 * 9.81;
    EXPECT_NEAR(double(r.position[kAxisX]), 0.1, 1e-5);
    EXPECT_NEAR(double(r.position[kAxisZ]), 0.3 - mg / 20000, 0.01 * mg / 20000);
    EXPECT_NEAR(double(r.position[kAxisRotZ]), 0.2, 1e-5);
    EXPECT_NEAR(double(r.effort[kAxisZ]), mg, 0.005 * mg);

    const std::string e = sceneError(R"({"bodies": [], "urdf": [{"file": "floating_box.urdf", "drives": {"float/q": {"stiffness": 1}}}]})");
    EXPECT_NE(e.find("'float/q', which is no free axis of a floating or planar joint"), std::string::npos) << e;
}

TEST(UrdfScene, BadEntriesNameThePath) {
    std::string e = sceneError(R"({"bodies": [], "urdf": [{"file": "nowhere.urdf"}]})");
    EXPECT_NE(e.find("urdf[0].file"), std::string::npos) << e;
    EXPECT_NE(e.find("nowhere.urdf"), std::string::npos) << e;

    e = sceneError(R"({"bodies": [], "urdf": [{"file": "slider_load.urdf", "drives": {"elbow": {"stiffness": 1}}}]})");
    EXPECT_NE(e.find("joint 'elbow', which the robot does not have"), std::string::npos) << e;

    e = sceneError(R"({"bodies": [], "urdf": [{"file": "slider_load.urdf", "drives": {"lift": {"stifness": 1}}}]})");
    EXPECT_NE(e.find("urdf[0].drives.lift"), std::string::npos) << e;

    e = sceneError(R"({"bodies": [{"name": "load", "shape": {"type": "sphere", "radius": 1}}], "urdf": [{"file": "slider_load.urdf"}]})");
    EXPECT_NE(e.find("link 'load' has the name of bodies[0]"), std::string::npos) << e;
}

TEST(UrdfScene, CommandLineSceneStandsTheRobotOnTheGround) {
    const std::string file = (std::filesystem::path(FULCRUM_SOURCE_DIR) / "scenes" / "robot_arm.urdf").string();
    ASSERT_TRUE(detail::isUrdfPath(file));
    EXPECT_FALSE(detail::isUrdfPath("scene.json"));
    const Scene scene = detail::urdfRunScene(file, true);
    EXPECT_EQ(scene.world.gravity, (Vec3{0, 0, Real(-9.81)}));
    EXPECT_EQ(scene.bodies[0].shape.type, ShapeType::Plane);
    // The lowest collider (the base's cylinder, from z = 0) 1 mm above the ground.
    EXPECT_NEAR(scene.bodies[1].def.position.z, 0.001, 1e-6);
    EXPECT_EQ(scene.joints.size(), 6u);
}

}  // namespace
