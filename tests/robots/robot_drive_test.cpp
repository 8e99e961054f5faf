// Robot drives beyond the actuated joints' (docs/robots.md, "Drives"): the
// axes of floating and planar joints in the bulk dof arrays, checked against
// statics: each axis settles where its spring balances the load (k x = m g),
// and the effort read back along the vertical equals m g.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fulcrum/urdf.hpp"
#include "fulcrum/world.hpp"

namespace {

using namespace fulcrum;

World zUpWorld() {
    WorldDef def;
    def.gravity = {0, 0, Real(-9.81)};
    return World(def);
}

UrdfOptions fixedBaseOptions() {
    UrdfOptions o;
    o.warn = [](const std::string&) {};
    o.fixedBase = true;
    return o;
}

constexpr double kG = 9.81;
constexpr double kMass = 2;

std::string boxOn(const char* jointType, const char* axis) {
    return std::string(R"(<robot name="r"><link name="base"/>)"
                       R"(<link name="box"><inertial><mass value="2"/><inertia ixx="0.02" iyy="0.03" izz="0.04"/></inertial>)"
                       R"(<collision><geometry><box size="0.2 0.3 0.4"/></geometry></collision></link>)"
                       R"(<joint name="j" type=")") +
           jointType + R"("><parent link="base"/><child link="box"/><origin xyz="0 0 1"/><axis xyz=")" + axis +
           R"("/></joint></robot>)";
}

// A floating box driven on all six axes: each settles at its target, the
// vertical one m g / k below it (the spring carries the weight), and the
// effort along the vertical reads m g within 0.5 %. The angles are the joint's
// intrinsic x-y-z Euler angles, so three targets at once settle as set.
TEST(RobotDrive, FloatingJointAxesInBulkSettleAtTargets) {
    World world = zUpWorld();
    Robot r = loadUrdfFromString(world, boxOn("floating", "1 0 0"), "floating.urdf", fixedBaseOptions());
    const std::vector<std::string> names = r.dofNames();
    ASSERT_EQ(names, (std::vector<std::string>{"j/x", "j/y", "j/z", "j/rx", "j/ry", "j/rz"}));
    ASSERT_TRUE(r.actuatedJointNames().empty());
    // Critically damped: linear k 20000 N/m on 2 kg, angular 40 N m/rad on ~0.03 kg m^2.
    const double kLin = 20000, kAng = 40;
    const std::vector<Real> kp{Real(kLin), Real(kLin), Real(kLin), Real(kAng), Real(kAng), Real(kAng)};
    const std::vector<Real> kd{400, 400, 400, Real(2.2), Real(2.2), Real(2.2)};
    const std::vector<Real> target{Real(0.1), Real(-0.2), Real(0.3), Real(0.2), Real(-0.15), Real(0.3)};
    r.setDofDriveGains(world, kp, kd);
    r.setDofPositionTargets(world, target);
    for (int i = 0; i < 3 * 240; ++i) world.step(Real(1) / 240);
    const std::vector<Real> q = r.dofPositions(world), qd = r.dofVelocities(world), effort = r.dofEfforts(world);
    ASSERT_EQ(q.size(), 6u);
    const double sag = kMass * kG / kLin;  // 0.98 mm
    for (std::size_t k = 0; k < 6; ++k) {
        const double expected = double(target[k]) - (k == kAxisZ ? sag : 0);
        EXPECT_NEAR(double(q[k]), expected, k == kAxisZ ? 0.01 * sag : 1e-5) << names[k];
        EXPECT_NEAR(double(qd[k]), 0, 1e-4) << names[k];
    }
    // The frame is the joint origin's (world axes here): z is vertical.
    EXPECT_NEAR(double(effort[kAxisZ]), kMass * kG, 0.005 * kMass * kG);
    EXPECT_NEAR(double(effort[kAxisX]), 0, 1e-3);
    EXPECT_NEAR(double(effort[kAxisY]), 0, 1e-3);
    // The body is where the linear axes say.
    const Vec3 p = world.position(r.body("box"));
    EXPECT_NEAR(double(p.x), 0.1, 1e-5);
    EXPECT_NEAR(double(p.z), 1.3 - sag, 0.01 * sag);

    // One axis by name (setDrive), and velocity targets in bulk.
    r.setDrive(world, "j/z", {.position = Real(0.5), .stiffness = Real(kLin), .damping = 400});
    for (int i = 0; i < 2 * 240; ++i) world.step(Real(1) / 240);
    EXPECT_NEAR(double(r.dofPositions(world)[kAxisZ]), 0.5 - sag, 0.01 * sag);
    r.disableDrives(world);
    r.setDofVelocityTargets(world, std::vector<Real>{Real(0.5), 0, 0, 0, 0, 0});
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 240);
    EXPECT_NEAR(double(r.dofVelocities(world)[kAxisX]), 0.5, 1e-3);
    EXPECT_NEAR(double(r.dofEfforts(world)[kAxisZ]), kMass * kG, 0.005 * kMass * kG);  // the z motor (speed 0) holds it
}

// A planar joint whose plane is vertical (normal y): its free axes x, y (in
// the plane) and rz (about the normal) are the dofs; driven, the box settles
// at the targets with the weight's sag along the vertical, and the in-plane
// efforts add up to m g up.
TEST(RobotDrive, PlanarJointAxesInBulkSettleAtTargets) {
    World world = zUpWorld();
    Robot r = loadUrdfFromString(world, boxOn("planar", "0 1 0"), "planar.urdf", fixedBaseOptions());
    ASSERT_EQ(r.dofNames(), (std::vector<std::string>{"j/x", "j/y", "j/rz"}));
    const JointDef& def = world.jointDef(r.joint("j"));
    const Vec3 ex = def.axis, ey = normalize(def.axisY - def.axis * dot(def.axisY, def.axis));
    const double kLin = 20000;
    r.setDofDriveGains(world, std::vector<Real>{Real(kLin), Real(kLin), 60}, std::vector<Real>{400, 400, 3});
    const std::vector<Real> target{Real(0.2), Real(-0.1), Real(0.4)};
    r.setDofPositionTargets(world, target);
    for (int i = 0; i < 3 * 240; ++i) world.step(Real(1) / 240);
    const std::vector<Real> q = r.dofPositions(world), effort = r.dofEfforts(world);
    // The weight's sag along each in-plane axis: m g_axis / k.
    const Vec3 g{0, 0, Real(-kG)};
    EXPECT_NEAR(double(q[0]), double(target[0]) + kMass * double(dot(g, ex)) / kLin, 1e-5);
    EXPECT_NEAR(double(q[1]), double(target[1]) + kMass * double(dot(g, ey)) / kLin, 1e-5);
    EXPECT_NEAR(double(q[2]), double(target[2]), 1e-4);
    const Vec3 up = ex * effort[0] + ey * effort[1];
    EXPECT_NEAR(double(up.z), kMass * kG, 0.005 * kMass * kG);
    EXPECT_NEAR(double(length(Vec3{up.x, up.y, 0})), 0, 1e-3);
}

TEST(RobotDrive, DofCountsAndNamesAreChecked) {
    World world = zUpWorld();
    Robot r = loadUrdfFromString(world, boxOn("planar", "0 1 0"), "planar.urdf", fixedBaseOptions());
    const auto message = [&](auto f) {
        try {
            f();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    std::string e = message([&] { r.setDofPositionTargets(world, std::vector<Real>{1, 2}); });
    EXPECT_NE(e.find("2 position targets for 3 degrees of freedom"), std::string::npos) << e;
    e = message([&] { r.setDrive(world, "j/z", {.stiffness = 1}); });  // locked in a planar joint
    EXPECT_NE(e.find("'j/z' names no free axis"), std::string::npos) << e;
    e = message([&] { r.setDrive(world, "j", {.stiffness = 1}); });
    EXPECT_NE(e.find("joint 'j' is planar"), std::string::npos) << e;
}

// URDF <dynamics friction> on a prismatic joint: dry friction F_f along the
// slider. A 2 kg load on a slider inclined by theta stays still while
// m g sin(theta) < F_f (its effort then reads that load), and slides with
// a = g sin(theta) - F_f / m otherwise (1 %).
struct InclinedSlide {
    double x = 0, v = 0, effort = 0;
};

InclinedSlide slideOnIncline(double thetaDeg, double friction, double seconds) {
    World world = zUpWorld();
    const double theta = thetaDeg * 3.14159265358979323846 / 180;
    const std::string axis = std::to_string(std::cos(theta)) + " 0 " + std::to_string(-std::sin(theta));
    const std::string xml =
        R"(<robot name="r"><link name="base"/>)"
        R"(<link name="load"><inertial><mass value="2"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial></link>)"
        R"(<joint name="slide" type="prismatic"><parent link="base"/><child link="load"/><origin xyz="0 0 1"/>)"
        R"(<axis xyz=")" + axis + R"("/><limit lower="-10" upper="10" effort="100" velocity="10"/>)"
        R"(<dynamics friction=")" + std::to_string(friction) + R"("/></joint></robot>)";
    Robot r = loadUrdfFromString(world, xml, "incline.urdf", fixedBaseOptions());
    EXPECT_TRUE(r.warnings.empty());
    const int steps = static_cast<int>(seconds * 240 + 0.5);
    for (int i = 0; i < steps; ++i) world.step(Real(1) / 240);
    return {double(r.jointPositions(world)[0]), double(r.jointVelocities(world)[0]), double(r.jointEfforts(world)[0])};
}

TEST(RobotDrive, SliderFrictionHoldsOrSlides) {
    const double friction = 10;
    // 20 degrees: m g sin(theta) = 6.71 N < 10 N: it stays, friction carries the load.
    const InclinedSlide still = slideOnIncline(20, friction, 2);
    EXPECT_LT(std::fabs(still.x), 1e-5);
    EXPECT_LT(std::fabs(still.v), 1e-5);
    const double load = kMass * kG * std::sin(20 * 3.14159265358979323846 / 180);
    EXPECT_NEAR(-still.effort, load, 0.005 * load);  // the joint pushes the load back up the axis
    // 45 degrees: 13.87 N > 10 N: it slides with a = g sin(theta) - F_f / m = 1.937 m/s^2.
    const double a = kG * std::sin(3.14159265358979323846 / 4) - friction / kMass;
    const InclinedSlide moving = slideOnIncline(45, friction, 1);
    EXPECT_NEAR(moving.v, a * 1, 0.01 * a);
    EXPECT_NEAR(moving.x, 0.5 * a * 1, 0.01 * 0.5 * a);
    EXPECT_NEAR(-moving.effort, friction, 0.005 * friction);
    // Without friction, the full g sin(theta).
    const InclinedSlide free = slideOnIncline(45, 0, 1);
    EXPECT_NEAR(free.v, kG * std::sin(3.14159265358979323846 / 4), 0.01 * kG);
}

}  // namespace

namespace {

// A 2 kg point-like ball on a massless-looking 0.5 m arm (a thin box) on a
// revolute joint about y, the arm horizontal along x: gravity's moment
// m g l about the joint, with <limit effort> `effort` (0: none).
std::string armWithEffort(const char* effort) {
    return std::string(R"(<robot name="arm"><link name="base"/>)"
                       R"(<link name="arm"><inertial><origin xyz="0.5 0 0"/><mass value="2"/>)"
                       R"(<inertia ixx="0.001" iyy="0.001" izz="0.001"/></inertial></link>)"
                       R"(<joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>)"
                       R"(<origin xyz="0 0 1"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort=")") +
           effort + R"(" velocity="5"/></joint></robot>)";
}

constexpr double kArm = 0.5, kArmInertia = 0.001 + kMass * kArm * kArm;  // about the joint

// The arm's angular acceleration from 0.05 s to 0.1 s after it starts from
// rest, held at 0 by a stiff position drive (the sign: falling is positive):
// the soft joint rows' first transient (the arm's centre settling onto the
// hinge) is over by then. `angle`: its angle at the window's middle (gravity's
// moment is m g l cos angle).
double fallAcceleration(World& world, const Robot& r, double& angle) {
    const BodyId arm = r.body("arm");
    for (int i = 0; i < 12; ++i) world.step(Real(1) / 240);
    const double w0 = double(world.angularVelocity(arm).y);
    for (int i = 0; i < 6; ++i) world.step(Real(1) / 240);
    angle = double(r.jointPositions(world)[0]);
    for (int i = 0; i < 6; ++i) world.step(Real(1) / 240);
    return (double(world.angularVelocity(arm).y) - w0) / 0.05;
}

}  // namespace

// The URDF effort limit caps the position drive (as MuJoCo's actuator force
// range): with effort 6 N m < m g l = 9.81 N m, a stiff drive holding the arm
// level lets it fall with (m g l - 6) / I (1 %), its effort never above 6;
// a drive's own max_force overrides it; without an effort limit, or with a
// bulk limit above m g l, the drive holds the arm.
TEST(RobotDrive, EffortLimitCapsThePositionDrive) {
    const double mgl = kMass * kG * kArm;
    {
        World world = zUpWorld();
        Robot r = loadUrdfFromString(world, armWithEffort("6"), "arm.urdf", fixedBaseOptions());
        EXPECT_EQ(world.jointDef(r.joint("shoulder")).spring.maxForce, Real(6));
        r.setDriveGains(world, std::vector<Real>{20000}, std::vector<Real>{200});
        EXPECT_EQ(world.jointDef(r.joint("shoulder")).spring.maxForce, Real(6));  // kept by the bulk calls
        double angle = 0;
        const double alpha = fallAcceleration(world, r, angle);
        const double expected = (mgl * std::cos(angle) - 6) / kArmInertia;
        EXPECT_NEAR(alpha, expected, 0.01 * expected) << "angle " << angle;
        EXPECT_NEAR(std::fabs(double(r.jointEfforts(world)[0])), 6, 1e-4 * 6);
    }
    {
        // setDrive's maxForce overrides the effort limit (4 N m).
        World world = zUpWorld();
        Robot r = loadUrdfFromString(world, armWithEffort("6"), "arm.urdf", fixedBaseOptions());
        r.setDrive(world, "shoulder", {.position = 0, .stiffness = 20000, .damping = 200, .maxForce = 4});
        double angle = 0;
        const double alpha = fallAcceleration(world, r, angle);
        const double expected = (mgl * std::cos(angle) - 4) / kArmInertia;
        EXPECT_NEAR(alpha, expected, 0.01 * expected);
        EXPECT_LE(std::fabs(double(r.jointEfforts(world)[0])), 4 * (1 + 1e-5));
    }
    for (const char* effort : {"0", "20"}) {
        World world = zUpWorld();
        Robot r = loadUrdfFromString(world, armWithEffort(effort), "arm.urdf", fixedBaseOptions());
        r.setDriveGains(world, std::vector<Real>{20000}, std::vector<Real>{200});
        for (int i = 0; i < 240; ++i) world.step(Real(1) / 240);
        EXPECT_NEAR(double(r.jointPositions(world)[0]), 0, 2e-3) << "effort " << effort;
        EXPECT_NEAR(std::fabs(double(r.jointEfforts(world)[0])), mgl, 0.01 * mgl) << "effort " << effort;
    }
    {
        // The bulk limit (and disableDrives keeps it for the next gains).
        World world = zUpWorld();
        Robot r = loadUrdfFromString(world, armWithEffort("0"), "arm.urdf", fixedBaseOptions());
        r.setDriveMaxForces(world, std::vector<Real>{5});
        r.disableDrives(world);
        r.setDriveGains(world, std::vector<Real>{20000}, std::vector<Real>{200});
        double angle = 0;
        const double alpha = fallAcceleration(world, r, angle);
        const double expected = (mgl * std::cos(angle) - 5) / kArmInertia;
        EXPECT_NEAR(alpha, expected, 0.01 * expected);
        EXPECT_THROW(r.setDriveMaxForces(world, std::vector<Real>{-1}), Error);
        EXPECT_THROW(r.setDriveMaxForces(world, std::vector<Real>{1, 2}), Error);
    }
}

// A floating box's vertical axis driven with a force limit below its weight
// (dof bulk call): it sinks with g - F / m.
TEST(RobotDrive, DofForceLimitLetsTheLoadSink) {
    World world = zUpWorld();
    Robot r = loadUrdfFromString(world, boxOn("floating", "1 0 0"), "floating.urdf", fixedBaseOptions());
    const std::vector<Real> kp(6, Real(20000)), kd(6, Real(400));
    std::vector<Real> limit(6, std::numeric_limits<Real>::infinity());
    limit[2] = Real(0.5 * kMass * kG);  // z
    r.setDofDriveGains(world, kp, kd);
    r.setDofDriveMaxForces(world, limit);
    // From 0.05 s to 0.1 s (the soft rows' first transient over, as above).
    for (int i = 0; i < 12; ++i) world.step(Real(1) / 240);
    const double v0 = double(world.linearVelocity(r.body("box")).z);
    for (int i = 0; i < 12; ++i) world.step(Real(1) / 240);
    const double a = kG - 0.5 * kG;
    EXPECT_NEAR(-(double(world.linearVelocity(r.body("box")).z) - v0) / 0.05, a, 0.01 * a);
    EXPECT_LE(std::fabs(double(r.dofEfforts(world)[2])), 0.5 * kMass * kG * (1 + 1e-5));
}
