// Scene files: the joint solver settings of the world (joint_hertz,
// joint_damping_ratio, joint_projection_slop, joint_direct_solve) and the
// joints' friction_torque: read, validated with path and line, written only
// when not default, round-tripped, and built into the World.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"
#include "io/scene_error_expectations.hpp"

namespace fulcrum {
namespace {

// A lever: a 1 kg ball 0.5 m out from a hinge (axis z) or ball joint on the
// static world, so gravity pulls on it with m g L = 4.905 N m about the joint.
std::string leverScene(const std::string& world, const std::string& jointExtra, bool hinge = true) {
    return R"({"world": {"dt": 0.0166667)" + world + R"(},
  "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.05}, "mass": 1, "position": [0.5, 1, 0]}],
  "joints": [{"name": "pivot", "type": ")" +
           std::string(hinge ? R"(hinge", "axis": [0, 0, 1])" : R"(ball")") + R"(, "body_b": "ball", "anchor": [0, 1, 0])" + jointExtra +
           "}]}";
}

using test::expectError;
using test::parseError;

TEST(JointSettingsScene, ReadIntoWorldDefAndJointDef) {
    const Scene s = parseScene(leverScene(R"(, "joint_hertz": 30, "joint_damping_ratio": 0.7, "joint_projection_slop": 0.02,
                                              "joint_direct_solve": false)",
                                          R"(, "friction_torque": 2.5)"),
                               "lever.json");
    EXPECT_EQ(s.world.jointHertz, Real(30));
    EXPECT_EQ(s.world.jointDampingRatio, Real(0.7));
    EXPECT_EQ(s.world.jointProjectionSlop, Real(0.02));
    EXPECT_FALSE(s.world.jointDirectSolve);
    ASSERT_EQ(s.joints.size(), 1u);
    EXPECT_EQ(s.joints[0].def.frictionTorque, Real(2.5));
    // "off": no projection (infinity, which JSON cannot write).
    const Scene off = parseScene(leverScene(R"(, "joint_projection_slop": "off")", ""), "off.json");
    EXPECT_TRUE(std::isinf(off.world.jointProjectionSlop));
    // Absent keys: the WorldDef / JointDef defaults.
    const Scene plain = parseScene(leverScene("", ""), "plain.json");
    const WorldDef defaults;
    EXPECT_EQ(plain.world.jointHertz, defaults.jointHertz);
    EXPECT_EQ(plain.world.jointDampingRatio, defaults.jointDampingRatio);
    EXPECT_EQ(plain.world.jointProjectionSlop, defaults.jointProjectionSlop);
    EXPECT_EQ(plain.world.jointDirectSolve, defaults.jointDirectSolve);
    EXPECT_EQ(plain.joints[0].def.frictionTorque, JointDef{}.frictionTorque);
    // Ball and cone-twist joints take friction too.
    const Scene kinds = parseScene(R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1},
        {"name": "b", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1, "position": [0, -1, 0]}],
      "joints": [{"type": "ball", "body_b": "a", "anchor": [0, 0, 0], "friction_torque": 0.5},
                 {"type": "cone_twist", "body_a": "a", "body_b": "b", "anchor": [0, -0.5, 0], "friction_torque": 0}]})",
                                   "kinds.json");
    EXPECT_EQ(kinds.joints[0].def.frictionTorque, Real(0.5));
    EXPECT_EQ(kinds.joints[1].def.frictionTorque, Real(0));
    // A slider's is a force along its axis (N; a URDF prismatic joint's <dynamics friction>), and round-trips.
    const Scene slider = parseScene(R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1}],
      "joints": [{"type": "slider", "body_b": "a", "anchor": [0, 0, 0], "axis": [1, 0, 0], "friction_torque": 7}]})",
                                    "slider.json");
    EXPECT_EQ(slider.joints[0].def.frictionTorque, Real(7));
    EXPECT_TRUE(parseScene(sceneToJson(slider), "saved.json") == slider);
}

TEST(JointSettingsScene, RoundTripAndDefaultsAreNotWritten) {
    const Scene scene = parseScene(leverScene(R"(, "joint_hertz": 90, "joint_damping_ratio": 1.25, "joint_projection_slop": "off",
                                                  "joint_direct_solve": false)",
                                              R"(, "friction_torque": 0.125)"),
                                   "lever.json");
    const std::string saved = sceneToJson(scene);
    const Scene again = parseScene(saved, "saved.json");
    EXPECT_TRUE(again == scene) << saved;
    EXPECT_NE(saved.find("\"joint_projection_slop\": \"off\""), std::string::npos) << saved;
    // The comparison sees every new field (one-ulp changes are differences).
    Scene changed = again;
    changed.joints[0].def.frictionTorque = std::nextafter(changed.joints[0].def.frictionTorque, Real(1));
    EXPECT_FALSE(changed == scene);
    changed = again;
    changed.world.jointHertz = std::nextafter(changed.world.jointHertz, Real(100));
    EXPECT_FALSE(changed == scene);
    changed = again;
    changed.world.jointDirectSolve = true;
    EXPECT_FALSE(changed == scene);
    // A finite slop round-trips too.
    Scene finite = scene;
    finite.world.jointProjectionSlop = Real(0.0125);
    EXPECT_TRUE(parseScene(sceneToJson(finite), "finite.json") == finite);

    // Defaults are not written, so files of scenes without joint tuning stay as they were.
    const std::string plain = sceneToJson(parseScene(leverScene("", ""), "plain.json"));
    for (const char* key : {"joint_hertz", "joint_damping_ratio", "joint_projection_slop", "joint_direct_solve", "friction_torque"}) {
        EXPECT_EQ(plain.find(key), std::string::npos) << key << " written at its default:\n" << plain;
    }
}

TEST(JointSettingsScene, InvalidValuesNameThePathAndLine) {
    expectError(leverScene(R"(, "joint_hertz": 0)", ""), "world.joint_hertz", "joint_hertz must be positive, got 0");
    expectError(leverScene(R"(, "joint_damping_ratio": -1)", ""), "world.joint_damping_ratio", "joint_damping_ratio must be positive");
    expectError(leverScene(R"(, "joint_projection_slop": -0.001)", ""), "world.joint_projection_slop",
                "joint_projection_slop must not be negative");
    expectError(leverScene(R"(, "joint_projection_slop": "none")", ""), "world.joint_projection_slop",
                "must be a number >= 0 (m) or \"off\", got \"none\"");
    expectError(leverScene(R"(, "joint_projection_slop": true)", ""), "world.joint_projection_slop", "expected a number >= 0 (m) or \"off\"");
    expectError(leverScene(R"(, "joint_direct_solve": 1)", ""), "world.joint_direct_solve", "expected true or false");
    expectError(leverScene(R"(, "joint_hertx": 60)", ""), "world.joint_hertx", "did you mean 'joint_hertz'?");
    // friction_torque: finite, >= 0, on its line (line 3 of leverScene).
    expectError(leverScene("", R"(, "friction_torque": -0.5)"), "joints[0].friction_torque",
                "friction_torque must not be negative, got -0.5", 3);
    // Beyond Real: 1e300 in the float build; the double build's JSON numbers all fit, so 1e999 there.
    const std::string beyondReal = sizeof(Real) == sizeof(float) ? "1e300" : "1e999";
    expectError(leverScene("", R"(, "friction_torque": )" + beyondReal), "joints[0].friction_torque", "out of range", 3);
    expectError(leverScene("", R"(, "friction_torque": "high")"), "joints[0].friction_torque", "expected a number, got a string");
    // Only ball, hinge, slider and cone-twist joints have friction.
    for (const char* type : {"fixed"}) {
        expectError(std::string(R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1}],
  "joints": [{"type": ")") + type + R"(", "body_b": "a", "anchor": [0, 0, 0],
              "friction_torque": 1}]})",
                    "joints[0].friction_torque",
                    std::string("friction_torque applies only to ball, hinge, slider and cone_twist joints, not to a ") + type + " joint", 3);
    }
    expectError(R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1}],
  "joints": [{"type": "distance", "body_b": "a", "anchor": [0, 0, 0], "anchor_b": [0, -1, 0], "friction_torque": 1}]})",
                "joints[0].friction_torque", "not to a distance joint", 2);
}

TEST(JointSettingsScene, BuiltIntoTheWorld) {
    SceneHandles handles;
    const World w = buildWorld(parseScene(leverScene(R"(, "joint_hertz": 30, "joint_damping_ratio": 0.7,
        "joint_projection_slop": "off", "joint_direct_solve": false)",
                                                     R"(, "friction_torque": 2.5)"),
                                          "lever.json"),
                               &handles);
    EXPECT_EQ(w.settings().jointHertz, Real(30));
    EXPECT_EQ(w.settings().jointDampingRatio, Real(0.7));
    EXPECT_TRUE(std::isinf(w.settings().jointProjectionSlop));
    EXPECT_FALSE(w.settings().jointDirectSolve);
    ASSERT_EQ(handles.joints.size(), 1u);
    EXPECT_EQ(w.jointDef(handles.joints[0]).frictionTorque, Real(2.5));
}

// The friction reaches the solver: gravity's torque on the lever (a ball
// joint: docs/joints.md says hinge friction is weak for a light body far from
// its hinge) is m g L = 4.905 N m. Friction 6 N m holds it horizontal (it may
// sag by the soft joint's deflection only: under 1 cm in 1 s); friction 2 N m
// lets it swing down (net 2.9 N m on I ~ 0.25 kg m^2: it drops over 0.1 m
// within 1 s).
TEST(JointSettingsScene, FrictionTorqueFromTheFileHoldsOrSlipsAtMgL) {
    const auto dropAfterOneSecond = [](const char* friction) {
        const Scene s = parseScene(leverScene("", std::string(R"(, "friction_torque": )") + friction, false), "lever.json");
        SceneHandles handles;
        World w = buildWorld(s, &handles);
        for (int i = 0; i < 60; ++i) w.step(s.dt);
        return Real(1) - w.position(handles.bodies[0]).y;
    };
    EXPECT_LT(std::fabs(dropAfterOneSecond("6")), Real(0.01));
    EXPECT_GT(dropAfterOneSecond("2"), Real(0.1));
}

// max_rotation_per_substep (WorldDef::maxRotationPerSubstep, the spin limit):
// read, "off" for no limit, written only when not the default, round-trips,
// built into the world; bad values name the path.
// A joint spring's max_force (the position drive's force limit): read,
// absent = unlimited and not written, round-tripped, on six-DOF axes too;
// negative is an error naming the path. The lever (m g L = 4.905 N m) under
// a stiff drive with max_force 2 falls, with 8 it is held.
TEST(JointSettingsScene, SpringMaxForce) {
    const Scene s = parseScene(leverScene("", R"(, "spring": {"stiffness": 5000, "damping": 50, "max_force": 2})"), "lever.json");
    EXPECT_EQ(s.joints[0].def.spring.maxForce, Real(2));
    EXPECT_TRUE(parseScene(sceneToJson(s), "saved.json") == s);
    const Scene plain = parseScene(leverScene("", R"(, "spring": {"stiffness": 5000})"), "plain.json");
    EXPECT_TRUE(std::isinf(plain.joints[0].def.spring.maxForce));
    EXPECT_EQ(sceneToJson(plain).find("max_force"), std::string::npos);
    const Scene six = parseScene(R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1}],
      "joints": [{"type": "six_dof", "body_b": "a", "anchor": [0, 0, 0],
                  "axes": {"y": {"spring": {"stiffness": 100, "max_force": 3}}}}]})",
                                 "six.json");
    EXPECT_EQ(six.joints[0].def.axes[kAxisY].spring.maxForce, Real(3));
    EXPECT_EQ(parseScene(sceneToJson(six), "saved.json").joints[0].def.axes[kAxisY].spring.maxForce, Real(3));
    expectError(leverScene("", R"(, "spring": {"stiffness": 5000, "max_force": -1})"), "joints[0].spring.max_force", "must not be negative");
    for (const double limit : {2.0, 8.0}) {
        World w = buildWorld(parseScene(
            leverScene("", R"(, "spring": {"stiffness": 5000, "damping": 50, "max_force": )" + std::to_string(limit) + "}"), "lever.json"));
        for (int i = 0; i < 60; ++i) w.step(Real(1) / 60);
        const double drop = 1 - double(w.position(w.findBody("ball")).y);
        if (limit < 4.905) {
            EXPECT_GT(drop, 0.1) << limit;
        } else {
            EXPECT_LT(drop, 0.01) << limit;
        }
    }
}

TEST(JointSettingsScene, SpinLimitKey) {
    const Scene s = parseScene(leverScene(R"(, "max_rotation_per_substep": 0.5)", ""), "spin.json");
    EXPECT_EQ(s.world.maxRotationPerSubstep, Real(0.5));
    const Scene off = parseScene(leverScene(R"(, "max_rotation_per_substep": "off")", ""), "off.json");
    EXPECT_TRUE(std::isinf(off.world.maxRotationPerSubstep));
    const std::string saved = sceneToJson(off);
    EXPECT_NE(saved.find("\"max_rotation_per_substep\": \"off\""), std::string::npos) << saved;
    EXPECT_TRUE(parseScene(saved, "saved.json") == off);
    EXPECT_TRUE(parseScene(sceneToJson(s), "saved.json") == s);
    Scene changed = s;
    changed.world.maxRotationPerSubstep = std::nextafter(changed.world.maxRotationPerSubstep, Real(1));
    EXPECT_FALSE(changed == s);
    const std::string plain = sceneToJson(parseScene(leverScene("", ""), "plain.json"));
    EXPECT_EQ(plain.find("max_rotation_per_substep"), std::string::npos) << plain;
    EXPECT_EQ(buildWorld(s).settings().maxRotationPerSubstep, Real(0.5));
    expectError(leverScene(R"(, "max_rotation_per_substep": 0)", ""), "world.max_rotation_per_substep",
                "max_rotation_per_substep must be positive, got 0");
    expectError(leverScene(R"(, "max_rotation_per_substep": "none")", ""), "world.max_rotation_per_substep",
                "must be a number > 0 (rad) or \"off\", got \"none\"");
    // The API boundary: WorldDef validation names the field.
    WorldDef def;
    def.maxRotationPerSubstep = 0;
    try {
        World w(def);
        ADD_FAILURE() << "maxRotationPerSubstep 0 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("maxRotationPerSubstep"), std::string::npos) << e.what();
    }
    def.maxRotationPerSubstep = std::numeric_limits<Real>::quiet_NaN();
    EXPECT_THROW(World{def}, Error);
}

}  // namespace
}  // namespace fulcrum
