// URDF import (docs/robots.md): the public robot files (FULCRUM_ROBOTS_DIR,
// the shared folder beside the checkout) load and stay finite under their
// drives, and the physics of imported robots against statics and
// conservation: drive efforts against gravity torques, a double pendulum's
// energy, a slider's load. Bad input gives errors naming the file and element.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "fulcrum/urdf.hpp"
#include "fulcrum/world.hpp"
#include "support/real_eq.hpp"

namespace {

using namespace fulcrum;
namespace fs = std::filesystem;

fs::path robotsDir() { return fs::path(FULCRUM_ROBOTS_DIR); }
fs::path ownDir() { return fs::path(FULCRUM_SOURCE_DIR) / "tests" / "robots"; }

World zUpWorld(bool ground = true) {
    WorldDef def;
    def.gravity = {0, 0, Real(-9.81)};
    World world(def);
    if (ground) {
        BodyDef g;
        g.name = "ground";
        g.type = BodyType::Static;
        g.shape = Shape::plane({0, 0, 1}, 0);
        world.createBody(g);
    }
    return world;
}

UrdfOptions quietOptions() {
    UrdfOptions o;
    o.warn = [](const std::string&) {};
    return o;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

void expectFinite(const World& world) {
    for (const BodyId b : world.bodies()) {
        const Vec3 p = world.position(b);
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << world.name(b);
    }
}

TEST(Urdf, RobotsFolderIsThere) {
    ASSERT_TRUE(fs::is_directory(robotsDir())) << robotsDir() << ": the shared robot files must sit beside the checkout";
}

struct RobotCase {
    const char* file;
    bool fixedBase;
};

class EveryRobot : public ::testing::TestWithParam<RobotCase> {};

// Loads, and runs 10 s held by stiff position drives at the pose it was built
// in: no NaN, nothing flies off, nothing sinks through the ground. The robots
// without any collision element (ddbot, primitive_geometry) hang from a fixed
// base: nothing could hold them up.
TEST_P(EveryRobot, LoadsAndStandsTenSeconds) {
    const RobotCase c = GetParam();
    World world = zUpWorld();
    UrdfOptions o = quietOptions();
    o.fixedBase = c.fixedBase;
    o.position = {0, 0, Real(0.5)};
    Robot robot = loadUrdf(world, robotsDir() / c.file, o);
    ASSERT_FALSE(robot.links.empty());
    for (const RobotLink& l : robot.links) EXPECT_EQ(world.name(l.body), l.name);
    for (const RobotJoint& j : robot.joints) {
        if (!j.joint.isNull()) {  // floating, or fixed between static links: no joint
            EXPECT_EQ(world.name(j.joint), j.name);
        }
    }
    const std::size_t n = robot.actuatedJoints().size();
    robot.setDriveGains(world, std::vector<Real>(n, Real(200)), std::vector<Real>(n, Real(5)));
    robot.setPositionTargets(world, std::vector<Real>(n, Real(0)));
    for (int i = 0; i < 600; ++i) world.step(Real(1) / 60);
    expectFinite(world);
    for (const RobotLink& l : robot.links) {
        const Vec3 p = world.position(l.body);
        EXPECT_LT(length(p), Real(20)) << l.name;
        EXPECT_GT(p.z, Real(-0.2)) << l.name;
    }
    for (const Real q : robot.jointPositions(world)) EXPECT_TRUE(std::isfinite(q));
    for (const Real e : robot.jointEfforts(world)) EXPECT_TRUE(std::isfinite(e));
}

INSTANTIATE_TEST_SUITE_P(Urdf, EveryRobot,
                         ::testing::Values(RobotCase{"minitaur/minitaur.urdf", false}, RobotCase{"r2d2/07-physics.urdf", false},
                                           RobotCase{"ddbot/simple_ddbot.urdf", true},
                                           RobotCase{"dart-tests/primitive_geometry.urdf", true},
                                           RobotCase{"dart-tests/joint_properties.urdf", true},
                                           RobotCase{"dart-tests/inertiabot3.urdf", true},
                                           RobotCase{"kr5/kr5_sixx_r650.urdf", false}));

TEST(Urdf, InvalidFileNamesTheFile) {
    World world = zUpWorld();
    const std::string e = errorOf([&] { loadUrdf(world, robotsDir() / "dart-tests/invalid.urdf"); });
    EXPECT_NE(e.find("invalid.urdf"), std::string::npos) << e;
    EXPECT_TRUE(e.find("<robot>") != std::string::npos || e.find("malformed XML") != std::string::npos) << e;
    EXPECT_EQ(world.bodyCount(), 1u);  // only the ground
}

TEST(Urdf, ModelsAreReadAsWritten) {
    World world = zUpWorld();
    Robot r2d2 = loadUrdf(world, robotsDir() / "r2d2/07-physics.urdf", quietOptions());
    EXPECT_EQ(r2d2.links.size(), 16u);
    EXPECT_EQ(r2d2.joints.size(), 15u);
    const RobotJoint& grip = r2d2.jointInfo("gripper_extension");
    EXPECT_EQ(grip.type, UrdfJointType::Prismatic);
    EXPECT_REAL_EQ(grip.lower, Real(-0.38));
    EXPECT_REAL_EQ(grip.upper, 0);
    EXPECT_EQ(world.jointDef(grip.joint).type, JointType::Slider);
    EXPECT_EQ(world.jointDef(r2d2.joint("head_swivel")).type, JointType::Hinge);
    // The two missing gripper meshes used for collision are named with their link.
    bool named = false;
    for (const std::string& w : r2d2.warnings) {
        named = named || (w.find("l_finger.dae") != std::string::npos && w.find("left_gripper") != std::string::npos &&
                          w.find("collision") != std::string::npos);
    }
    EXPECT_TRUE(named);

    Robot props = loadUrdf(world, robotsDir() / "dart-tests/joint_properties.urdf", quietOptions());
    const RobotJoint& j01 = props.jointInfo("0_to_1");
    EXPECT_REAL_EQ(j01.lower, Real(-3.14159265359));
    EXPECT_REAL_EQ(j01.effortLimit, Real(2.5));
    EXPECT_REAL_EQ(j01.velocityLimit, Real(3.00545697193));
    EXPECT_REAL_EQ(j01.damping, Real(1.2));
    EXPECT_REAL_EQ(j01.friction, Real(2.3));
    EXPECT_REAL_EQ(world.jointDef(j01.joint).frictionTorque, Real(2.3));
    EXPECT_REAL_EQ(world.jointDef(j01.joint).spring.damping, Real(1.2));

    // The KR5's full inertia tensor and its centre of mass off the link origin.
    Robot kr5 = loadUrdf(world, robotsDir() / "kr5/kr5_sixx_r650.urdf", quietOptions());
    const BodyId shoulder = kr5.body("shoulder");
    EXPECT_NEAR(world.mass(shoulder), 5.77242340173648, 1e-5);
    EXPECT_NEAR(world.localCenterOfMass(shoulder).x, 0.0359968408135882, 1e-6);
    EXPECT_NEAR(world.localCenterOfMass(shoulder).z, 0.0864969937502713, 1e-6);
    // A root named "world" without an inertial is static, and so is the base welded to it.
    EXPECT_EQ(world.bodyType(kr5.body("world")), BodyType::Static);
    EXPECT_EQ(world.bodyType(kr5.body("base_link")), BodyType::Static);
    EXPECT_TRUE(kr5.jointInfo(kr5.joints[0].name).joint.isNull());
    int missingCollisionMeshes = 0;
    for (const std::string& w : kr5.warnings) {
        if (w.find("collision: mesh") != std::string::npos && w.find("not found") != std::string::npos) ++missingCollisionMeshes;
    }
    EXPECT_EQ(missingCollisionMeshes, 7);
}

// R2D2's visuals (docs/robots.md): every link keeps its <visual>, in the
// colours its materials give, whether defined inline or named; the gripper's
// two COLLADA meshes are missing from the shared copy and left out.
TEST(Urdf, R2d2VisualsKeepTheirMaterials) {
    World world = zUpWorld();
    const Robot r2d2 = loadUrdf(world, robotsDir() / "r2d2/07-physics.urdf", quietOptions());
    std::size_t visuals = 0;
    for (const RobotLink& l : r2d2.links) visuals += l.visuals.size();
    EXPECT_EQ(visuals, 16u - 4u);  // 16 <visual>, four of them the missing finger meshes
    const auto colorOf = [&](const char* link) {
        for (const RobotLink& l : r2d2.links) {
            if (l.name == link && !l.visuals.empty() && l.visuals[0].hasColor) return l.visuals[0].color;
        }
        return std::array<float, 4>{-1, -1, -1, -1};
    };
    EXPECT_EQ(colorOf("base_link"), (std::array<float, 4>{0, 0, 0.8f, 1}));    // "blue", inline
    EXPECT_EQ(colorOf("right_leg"), (std::array<float, 4>{1, 1, 1, 1}));       // "white", inline
    EXPECT_EQ(colorOf("right_base"), (std::array<float, 4>{1, 1, 1, 1}));      // "white", by name
    const RobotLink& base = r2d2.links[0];
    ASSERT_EQ(base.visuals[0].geometry, BodyVisual::Geometry::Cylinder);
    EXPECT_NEAR(base.visuals[0].radius, 0.2, 1e-7);
    EXPECT_NEAR(base.visuals[0].halfHeight, 0.3, 1e-7);
    int missingVisualMeshes = 0;
    for (const std::string& w : r2d2.warnings) {
        if (w.find("visual: mesh") != std::string::npos && w.find(".dae' not found") != std::string::npos) ++missingVisualMeshes;
    }
    EXPECT_EQ(missingVisualMeshes, 4);
}

// The gravity torque about joint j's axis of every link beyond it, from
// where the links are now: sum m (c - anchor) x g.
Real gravityTorque(const World& world, const Robot& robot, const RobotJoint& j) {
    std::vector<std::string> beyond{j.child};
    for (std::size_t k = 0; k < beyond.size(); ++k) {
        for (const RobotJoint& o : robot.joints) {
            if (o.parent == beyond[k]) beyond.push_back(o.child);
        }
    }
    const JointDef& def = world.jointDef(j.joint);
    (void)def;
    const BodyId child = robot.body(j.child);
    // The anchor and axis now: the child's origin is the joint origin.
    const Vec3 anchor = world.position(child);
    const Vec3 axis = rotate(world.orientation(child), j.axis);
    const Vec3 g = world.settings().gravity;
    Vec3 torque;
    for (const std::string& name : beyond) {
        const BodyId b = robot.body(name);
        torque += cross(world.centerOfMass(b) - anchor, g * world.mass(b));
    }
    return dot(torque, axis);
}

// A fixed-base arm held still by its drives: each joint's effort equals the
// gravity torque of the links beyond it, within 1 %.
TEST(Urdf, HeldArmEffortsEqualGravityTorques) {
    World world = zUpWorld(false);
    UrdfOptions o = quietOptions();
    o.fixedBase = true;
    Robot arm = loadUrdf(world, robotsDir() / "kr5/kr5_sixx_r650.urdf", o);
    const std::size_t n = arm.actuatedJoints().size();
    ASSERT_EQ(n, 6u);
    // A pose with every joint loaded: the shoulder forward, the elbow bent.
    const std::vector<Real> target{Real(0.3), Real(0.6), Real(-0.4), Real(0.2), Real(0.5), Real(0.1)};
    arm.setDriveGains(world, std::vector<Real>(n, Real(5000)), std::vector<Real>(n, Real(200)));
    arm.setPositionTargets(world, target);
    for (int i = 0; i < 600; ++i) world.step(Real(1) / 60);
    const std::vector<Real> effort = arm.jointEfforts(world);
    const auto act = arm.actuatedJoints();
    Real largest = 0;
    for (std::size_t k = 0; k < n; ++k) largest = std::max(largest, std::fabs(gravityTorque(world, arm, arm.joints[act[k]])));
    for (std::size_t k = 0; k < n; ++k) {
        const RobotJoint& j = arm.joints[act[k]];
        const Real expected = -gravityTorque(world, arm, j);
        // 1 % of the joint's own torque; a joint whose load is near zero
        // (the wrist roll about a near-vertical axis) within 1e-3 of the largest.
        EXPECT_NEAR(effort[k], expected, std::max(Real(0.01) * std::fabs(expected), Real(1e-3) * largest)) << j.name;
    }
}

// A double pendulum from URDF, drives off, conserves energy within 0.5 % over 10 s.
// The joint rows stiffer than the default (joint_hertz 240 instead of 60, at
// dt 1/240 s): the soft rows' own damping is what loses energy (1.4 % over
// 10 s at the defaults, 0.16 % here; docs/robots.md).
TEST(Urdf, DoublePendulumConservesEnergy) {
    WorldDef def;
    def.gravity = {0, 0, Real(-9.81)};
    def.jointHertz = 240;
    World world(def);
    UrdfOptions o = quietOptions();
    o.fixedBase = true;
    Robot p = loadUrdf(world, ownDir() / "double_pendulum.urdf", o);
    ASSERT_EQ(p.actuatedJoints().size(), 2u);
    // The scale of the motion: the energy the pendulum trades (both rods fall
    // from horizontal: 1 kg at 0.5 m and 1 kg at 1.5 m below).
    const double scale = 9.81 * (0.5 + 1.5);
    const double e0 = world.energy().total;
    double worst = 0;
    for (int i = 0; i < 2400; ++i) {
        world.step(Real(1) / 240);
        worst = std::max(worst, std::fabs(world.energy().total - e0));
    }
    expectFinite(world);
    EXPECT_LT(worst / scale, 0.005) << "energy drift " << worst << " J of " << scale << " J";
    // It did swing: the elbow moved.
    EXPECT_GT(std::fabs(p.jointVelocities(world)[1]) + std::fabs(p.jointPositions(world)[1]), Real(0.01));
}

// A vertical prismatic joint holding a load: effort = m g within 0.5 %.
TEST(Urdf, SliderHoldsItsLoad) {
    World world = zUpWorld(false);
    UrdfOptions o = quietOptions();
    o.fixedBase = true;
    Robot r = loadUrdf(world, ownDir() / "slider_load.urdf", o);
    JointDrive d;
    d.position = Real(0.1);
    d.stiffness = Real(20000);
    d.damping = Real(400);
    r.setDrive(world, "lift", d);
    for (int i = 0; i < 600; ++i) world.step(Real(1) / 60);
    const Real effort = world.jointEffort(r.joint("lift"));
    EXPECT_NEAR(effort, Real(2.5 * 9.81), Real(0.005 * 2.5 * 9.81));
    EXPECT_NEAR(world.jointPosition(r.joint("lift")), Real(0.1) - Real(2.5 * 9.81 / 20000), Real(1e-3));
    EXPECT_NEAR(world.jointVelocity(r.joint("lift")), 0, Real(1e-3));
}

// A velocity drive turns the joint at its target speed; the IMU of a body at
// rest reads +g up (specific force), of a falling body zero.
TEST(Urdf, VelocityDriveAndImu) {
    World world = zUpWorld(false);
    UrdfOptions o = quietOptions();
    o.fixedBase = true;
    Robot p = loadUrdf(world, ownDir() / "double_pendulum.urdf", o);
    p.setVelocityTargets(world, std::vector<Real>{Real(1), Real(0)});
    for (int i = 0; i < 120; ++i) world.step(Real(1) / 60);
    EXPECT_NEAR(p.jointVelocities(world)[0], 1, 1e-3);
    EXPECT_NEAR(p.jointVelocities(world)[1], 0, 1e-3);

    World fall = zUpWorld(false);
    BodyDef b;
    b.name = "free";
    const BodyId free = fall.createBody(b);
    b.name = "held";
    b.type = BodyType::Static;
    b.position = {3, 0, 0};
    const BodyId held = fall.createBody(b);
    Imu imuFree(free), imuHeld(held);
    imuFree.update(fall);
    imuHeld.update(fall);
    fall.step(Real(1) / 60);
    const ImuReading f = imuFree.update(fall), h = imuHeld.update(fall);
    EXPECT_NEAR(length(f.specificForce), 0, 1e-3);
    EXPECT_NEAR(h.specificForce.z, 9.81, 1e-4);
}

// Collision meshes in STL and OBJ: a dynamic link collides as the mesh's
// convex hull, a static one as its triangles; package:// paths resolve
// against the search path; a missing file is a warning (COLLADA meshes:
// urdf_dae_test.cpp).
TEST(Urdf, CollisionMeshesFromStlAndObj) {
    World world = zUpWorld();
    std::vector<std::string> warnings;
    UrdfOptions o;
    o.fixedBase = true;
    o.searchPath = {ownDir()};  // package://robots/meshes/... -> tests/robots/meshes/...
    o.warn = [&](const std::string& w) { warnings.push_back(w); };
    const std::string inertia = R"(<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>)";
    const Robot r = loadUrdfFromString(
        world,
        R"(<robot name="m"><link name="floor"><collision><geometry><mesh filename="meshes/wedge.stl"/></geometry></collision></link>)"
        R"(<link name="block">)" + inertia +
            R"(<collision><geometry><mesh filename="package://robots/meshes/cube.obj" scale="2 1 1"/></geometry></collision></link>)"
            R"(<link name="odd">)" + inertia +
            R"(<collision><geometry><mesh filename="meshes/absent.dae"/></geometry></collision></link>)"
            R"(<joint name="a" type="revolute"><parent link="floor"/><child link="block"/><origin xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>)"
            R"(<joint name="b" type="fixed"><parent link="block"/><child link="odd"/><origin xyz="1 0 0"/></joint></robot>)",
        (ownDir() / "inline.urdf").string(), o);
    EXPECT_EQ(world.shape(r.body("floor")).type(), ShapeType::Mesh);
    const Shape& block = world.shape(r.body("block"));
    ASSERT_EQ(block.type(), ShapeType::ConvexHull);
    EXPECT_NEAR(block.localBounds().max.x, 0.2, 1e-6);  // scaled by 2 along x
    EXPECT_NEAR(block.localBounds().max.y, 0.1, 1e-6);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("link 'odd', collision: mesh 'meshes/absent.dae' not found"), std::string::npos) << warnings[0];
}

// A binary STL (written here: a tetrahedron) beside a URDF given from memory.
TEST(Urdf, BinaryStlMesh) {
    // Its own folder (the Release and sanitizer suites may run at once).
    const fs::path dir = fs::temp_directory_path() /
                         ("fulcrum_urdf_stl_" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    fs::create_directories(dir);
    {
        std::ofstream out(dir / "tetra.stl", std::ios::binary);
        const std::string header(80, ' ');
        out.write(header.data(), 80);
        const std::uint32_t count = 4;
        out.write(reinterpret_cast<const char*>(&count), 4);
        const float v[4][3] = {{0, 0, 0}, {0.3f, 0, 0}, {0, 0.3f, 0}, {0, 0, 0.3f}};
        const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
        for (const auto& f : faces) {
            const float normal[3] = {0, 0, 0};
            out.write(reinterpret_cast<const char*>(normal), 12);
            for (const int k : f) out.write(reinterpret_cast<const char*>(v[k]), 12);
            const std::uint16_t attributes = 0;
            out.write(reinterpret_cast<const char*>(&attributes), 2);
        }
    }
    World world = zUpWorld();
    UrdfOptions o = quietOptions();
    const Robot r = loadUrdfFromString(world,
                                       R"(<robot name="t"><link name="tip"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>)"
                                       R"(<collision><geometry><mesh filename="tetra.stl"/></geometry></collision></link></robot>)",
                                       (dir / "t.urdf").string(), o);
    const Shape& tip = world.shape(r.body("tip"));
    ASSERT_EQ(tip.type(), ShapeType::ConvexHull);
    EXPECT_EQ(tip.hull().vertices.size(), 4u);
    EXPECT_NEAR(tip.localBounds().max.z, 0.3, 1e-6);
    fs::remove_all(dir);
}

// A planar joint between a fixed base and a box, its normal (1, 1, 0) off the
// box's principal axes: the box slides in the plane under gravity (-z, in
// the plane) and spins about the normal at 4 rad/s (the gyroscopic torque of
// a spin off its principal axes pulls the normal away, the joint holds it); it keeps
// its coordinate along the normal, and its normal, within 1e-4 (m and rad)
// over 2 s. A floating joint leaves its child free (it falls as in free
// fall) and reads out its pose.
TEST(Urdf, PlanarAndFloatingJointsAreSixDof) {
    World world = zUpWorld(false);
    UrdfOptions o = quietOptions();
    o.fixedBase = true;
    Robot r = loadUrdfFromString(world,
                                 R"(<robot name="p"><link name="base"/>)"
                                 R"(<link name="box"><inertial><mass value="2"/><inertia ixx="0.02" iyy="0.03" izz="0.04"/></inertial>)"
                                 R"(<collision><geometry><box size="0.2 0.3 0.4"/></geometry></collision></link>)"
                                 R"(<link name="free"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial></link>)"
                                 R"(<joint name="plane" type="planar"><parent link="base"/><child link="box"/>)"
                                 R"(<origin xyz="0 0 1"/><axis xyz="1 1 0"/></joint>)"
                                 R"(<joint name="float" type="floating"><parent link="base"/><child link="free"/>)"
                                 R"(<origin xyz="3 0 1"/></joint></robot>)",
                                 "planar.urdf", o);
    const BodyId box = r.body("box");
    const JointId plane = r.joint("plane");
    EXPECT_EQ(world.jointDef(plane).type, JointType::SixDof);
    EXPECT_EQ(world.jointDef(r.joint("float")).type, JointType::SixDof);
    const Vec3 n = normalize(Vec3{1, 1, 0});
    world.setLinearVelocity(box, {1, -1, 2});   // in the plane
    world.setAngularVelocity(box, n * Real(4));  // about the normal (at 6 rad/s the soft rows let it tilt 1.2e-4 rad)
    const Vec3 x0 = world.position(box);
    double worstOut = 0, worstTilt = 0;
    for (int i = 0; i < 120; ++i) {
        world.step(Real(1) / 60);
        worstOut = std::max(worstOut, std::fabs(double(dot(world.position(box) - x0, n))));
        worstTilt = std::max(worstTilt, double(length(rotate(world.orientation(box), n) - n)));
    }
    EXPECT_LT(worstOut, 1e-4);
    EXPECT_LT(worstTilt, 1e-4);
    EXPECT_LT(double(world.position(box).z), -5);                   // it fell in the plane
    EXPECT_NEAR(double(dot(world.angularVelocity(box), n)), 4, 0.05);  // and kept turning about the normal
    const SixDofReading s0 = world.sixDofReading(plane);
    EXPECT_NEAR(double(s0.velocity[kAxisRotZ]), 4, 0.05);
    // The floating link falls freely: z = 1 - g t^2 / 2 within 1 %.
    const BodyId free = r.body("free");
    EXPECT_NEAR(double(world.position(free).z), 1 - 0.5 * 9.81 * 4, 0.01 * 0.5 * 9.81 * 4);
    const SixDofReading s = world.sixDofReading(r.joint("float"));
    const double speed = std::sqrt(double(s.velocity[0] * s.velocity[0] + s.velocity[1] * s.velocity[1] + s.velocity[2] * s.velocity[2]));
    EXPECT_NEAR(speed, double(length(world.linearVelocity(free))), 1e-3);
}

std::string loadText(const std::string& xml) {
    World world = zUpWorld();
    return errorOf([&] { loadUrdfFromString(world, xml, "bad.urdf", quietOptions()); });
}

TEST(Urdf, BadInputNamesTheElement) {
    const std::string link = R"(<link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/></inertial></link>)";
    const std::string linkB = R"(<link name="b"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/></inertial></link>)";
    std::string e = loadText("<robot name='r'><link name='a'></robot>");
    EXPECT_NE(e.find("bad.urdf: line 1: malformed XML"), std::string::npos) << e;

    e = loadText("<robot name='r'>" + link + R"(<joint name="j" type="fixed"><parent link="a"/><child link="nope"/></joint></robot>)");
    EXPECT_NE(e.find("<joint name='j'>"), std::string::npos) << e;
    EXPECT_NE(e.find("child link 'nope' does not exist"), std::string::npos) << e;

    e = loadText("<robot name='r'>" + link + linkB +
                 R"(<joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>)"
                 R"(<joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint></robot>)");
    EXPECT_NE(e.find("loop"), std::string::npos) << e;

    e = loadText(R"(<robot name='r'><link name="z"><inertial><mass value="1"/><inertia ixx="0" iyy="0" izz="0"/></inertial></link></robot>)");
    EXPECT_NE(e.find("<link name='z'>"), std::string::npos) << e;
    EXPECT_NE(e.find("positive definite"), std::string::npos) << e;

    e = loadText(R"(<robot name='r'><link name="m"><inertial><mass value="-2"/><inertia ixx="1" iyy="1" izz="1"/></inertial></link></robot>)");
    EXPECT_NE(e.find("<mass> of <link name='m'>"), std::string::npos) << e;

    e = loadText(R"(<robot name='r'><link name="s"><collision><geometry><box size="1 x 1"/></geometry></collision></link></robot>)");
    EXPECT_NE(e.find("attribute 'size' is not"), std::string::npos) << e;

    e = loadText("<robot name='r'>" + link + link + "</robot>");
    EXPECT_NE(e.find("duplicate link name 'a'"), std::string::npos) << e;

    // A missing mesh is a warning naming the file, the link and the element, and the fallback is used.
    World world = zUpWorld();
    std::vector<std::string> warnings;
    UrdfOptions o;
    o.warn = [&](const std::string& w) { warnings.push_back(w); };
    const Robot r = loadUrdfFromString(
        world,
        R"(<robot name='r'><link name="arm"><inertial><mass value="2"/><inertia ixx="0.1" iyy="0.2" izz="0.25"/></inertial>)"
        R"(<collision><geometry><mesh filename="package://nowhere/arm.stl"/></geometry></collision></link></robot>)",
        "mesh.urdf", o);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("mesh.urdf: line 1: link 'arm', collision: mesh 'package://nowhere/arm.stl' not found"),
              std::string::npos)
        << warnings[0];
    EXPECT_EQ(world.shape(r.body("arm")).type(), ShapeType::Box);
}

}  // namespace
