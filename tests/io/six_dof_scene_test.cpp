// Scene files: the six-DOF joint (type "six_dof", axis, axis_y, axes) and the
// cone-twist drive: read, checked with the path, written back and read to
// the same definition, built into the World.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"
#include "io/scene_error_expectations.hpp"

namespace fulcrum {
namespace {

std::string scene(const std::string& joint) {
    return R"({"bodies": [{"name": "box", "shape": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}, "mass": 1, "position": [0, 1, 0]}],
  "joints": [{"name": "j", "body_b": "box", "anchor": [0, 1, 0], )" +
           joint + "}]}";
}

TEST(SixDofScene, ReadWrittenAndBuilt) {
    const Scene s = parseScene(scene(R"("type": "six_dof", "axis": [0, 0, 1], "axis_y": [1, 0, 0],
        "axes": {"x": "free", "y": {"limits": [-0.5, 0.25], "motor": {"speed": 1, "max_force": 10}},
                 "rz": {"spring": {"target": 0.1, "stiffness": 5, "damping": 0.5}}, "ry": "locked"})"),
                               "six.json");
    ASSERT_EQ(s.joints.size(), 1u);
    const JointDef& d = s.joints[0].def;
    EXPECT_EQ(d.type, JointType::SixDof);
    EXPECT_EQ(d.axes[kAxisX].mode, AxisMode::Free);
    EXPECT_EQ(d.axes[kAxisY].mode, AxisMode::Limited);
    EXPECT_EQ(d.axes[kAxisY].lower, Real(-0.5));
    EXPECT_TRUE(d.axes[kAxisY].motor.enabled);
    EXPECT_EQ(d.axes[kAxisZ].mode, AxisMode::Locked);
    EXPECT_EQ(d.axes[kAxisRotZ].mode, AxisMode::Free);
    EXPECT_EQ(d.axes[kAxisRotZ].spring.stiffness, Real(5));
    EXPECT_EQ(d.axisY.x, Real(1));

    const Scene again = parseScene(sceneToJson(s), "again.json");
    const JointDef& e = again.joints[0].def;
    for (std::size_t k = 0; k < kSixDofAxes; ++k) {
        EXPECT_EQ(e.axes[k].mode, d.axes[k].mode) << k;
        EXPECT_EQ(e.axes[k].lower, d.axes[k].lower) << k;
        EXPECT_EQ(e.axes[k].upper, d.axes[k].upper) << k;
        EXPECT_EQ(e.axes[k].motor.enabled, d.axes[k].motor.enabled) << k;
        EXPECT_EQ(e.axes[k].spring.target, d.axes[k].spring.target) << k;
    }
    EXPECT_EQ(e.axis.z, d.axis.z);

    SceneHandles handles;
    World world = buildWorld(s, &handles);
    ASSERT_EQ(handles.joints.size(), 1u);
    EXPECT_EQ(world.jointDef(handles.joints[0]).type, JointType::SixDof);
    // The frame: linear x is world z, y world x.
    world.setLinearVelocity(handles.bodies[0], {Real(0.5), 0, Real(0.25)});
    world.step(Real(1) / 60);
    const SixDofReading r = world.sixDofReading(handles.joints[0]);
    EXPECT_NEAR(r.velocity[kAxisX], Real(0.25), Real(0.02));
}

TEST(SixDofScene, BadAxesNameThePath) {
    test::expectError(scene(R"("type": "six_dof", "axes": {"w": "free"})"), "joints[0].axes.w", "unknown key for the six-DOF axes");
    test::expectError(scene(R"("type": "six_dof", "axes": {"x": "loose"})"), "joints[0].axes.x", "unknown axis mode 'loose'");
    test::expectError(scene(R"("type": "six_dof", "axes": {"x": {"limits": [1, -1]}})"), "joints[0].axes.x.limits", "lower must not exceed upper");
    test::expectError(scene(R"("type": "six_dof", "axes": {"x": "limited"})"), "joints[0].axes.x", "needs its limits");
    test::expectError(scene(R"("type": "six_dof", "swing_limit": 1)"), "joints[0].swing_limit", "unknown key for a six_dof joint");
}

TEST(ConeTwistDriveScene, ReadWrittenAndBuilt) {
    const Scene s = parseScene(scene(R"("type": "cone_twist", "drive": {"target": [1, 0, 0, 0], "damping": 2, "max_torque": 50})"),
                               "drive.json");
    const ConeTwistDrive& d = s.joints[0].def.coneDrive;
    EXPECT_TRUE(d.enabled);
    EXPECT_TRUE(std::isinf(d.stiffness));  // absent: rigid
    EXPECT_EQ(d.maxTorque, Real(50));
    const Scene again = parseScene(sceneToJson(s), "again.json");
    EXPECT_TRUE(std::isinf(again.joints[0].def.coneDrive.stiffness));
    EXPECT_EQ(again.joints[0].def.coneDrive.damping, Real(2));
    World world = buildWorld(s);
    EXPECT_TRUE(world.jointDef(world.joints()[0]).coneDrive.enabled);
}

}  // namespace
}  // namespace fulcrum
