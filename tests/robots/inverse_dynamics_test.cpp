// Robot::inverseDynamics (recursive Newton-Euler, src/io/urdf_dynamics.cpp)
// against closed forms and the simulation: a double pendulum's two-link
// equations of motion along a sine trajectory; the KR5's gravity-holding
// efforts against the efforts its drives are measured to deliver holding
// the same pose, and against the sum of m g x lever of the links beyond each
// joint; a slider's load against m g.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "fulcrum/urdf.hpp"
#include "fulcrum/world.hpp"

namespace {

using namespace fulcrum;
namespace fs = std::filesystem;

constexpr double kG = 9.81;

World zUpWorld(Real jointHertz = 0, int substeps = 0) {
    WorldDef def;
    def.gravity = {0, 0, Real(-kG)};
    if (jointHertz > 0) def.jointHertz = jointHertz;
    if (substeps > 0) def.substeps = substeps;
    return World(def);
}

UrdfOptions fixedBase() {
    UrdfOptions o;
    o.warn = [](const std::string&) {};
    o.fixedBase = true;
    return o;
}

// The planar two-link arm's equations of motion (uniform rods: length l,
// mass m, centre at l/2, I = m l^2 / 12), in angles phi counter-clockwise
// in the x-z plane (x right, z up) with gravity -z: tau = M(phi) phi'' +
// c(phi, phi') + g(phi). The URDF's joints turn about +y, which takes x
// towards -z: q = -phi, and a torque about +y is minus a counter-clockwise one.
std::array<double, 2> twoLinkEfforts(const std::array<double, 3>& q1, const std::array<double, 3>& q2) {
    const double m = 1, l = 1, lc = 0.5, I = m * l * l / 12;
    const double p1 = -q1[0], p2 = -q2[0], d1 = -q1[1], d2 = -q2[1], a1 = -q1[2], a2 = -q2[2];
    const double c2 = std::cos(p2);
    const double m11 = 2 * I + m * lc * lc + m * (l * l + lc * lc + 2 * l * lc * c2);
    const double m12 = I + m * (lc * lc + l * lc * c2);
    const double m22 = I + m * lc * lc;
    const double h = -m * l * lc * std::sin(p2);
    const double g1 = (m * lc + m * l) * kG * std::cos(p1) + m * lc * kG * std::cos(p1 + p2);
    const double g2 = m * lc * kG * std::cos(p1 + p2);
    const double t1 = m11 * a1 + m12 * a2 + h * d2 * d2 + 2 * h * d1 * d2 + g1;
    const double t2 = m12 * a1 + m22 * a2 - h * d1 * d1 + g2;
    return {-t1, -t2};
}

TEST(InverseDynamics, DoublePendulumMatchesTwoLinkEquations) {
    World world = zUpWorld();
    const Robot p = loadUrdf(world, fs::path(FULCRUM_SOURCE_DIR) / "tests/robots/double_pendulum.urdf", fixedBase());
    // Horizontal and still: both rods' weight on the shoulder, the outer one's on the elbow.
    std::vector<Real> zero{0, 0};
    std::vector<Real> hold = p.inverseDynamics(world, zero, zero, zero);
    EXPECT_NEAR(double(hold[0]), -kG * (0.5 + 1.5), 1e-4);
    EXPECT_NEAR(double(hold[1]), -kG * 0.5, 1e-4);
    // A sine trajectory for each joint, sampled over two seconds.
    double worst = 0;
    for (int i = 0; i <= 40; ++i) {
        const double t = 0.05 * i;
        const std::array<double, 3> q1{0.8 * std::sin(2 * t) + 0.3, 1.6 * std::cos(2 * t), -3.2 * std::sin(2 * t)};
        const std::array<double, 3> q2{1.1 * std::sin(3 * t + 0.5), 3.3 * std::cos(3 * t + 0.5), -9.9 * std::sin(3 * t + 0.5)};
        const std::vector<Real> q{Real(q1[0]), Real(q2[0])}, qd{Real(q1[1]), Real(q2[1])}, qdd{Real(q1[2]), Real(q2[2])};
        const std::vector<Real> tau = p.inverseDynamics(world, q, qd, qdd);
        const std::array<double, 2> expected = twoLinkEfforts(q1, q2);
        for (int k = 0; k < 2; ++k) {
            EXPECT_NEAR(double(tau[static_cast<std::size_t>(k)]), expected[static_cast<std::size_t>(k)],
                        1e-4 * (1 + std::fabs(expected[static_cast<std::size_t>(k)])))
                << "t " << t << " joint " << k;
            worst = std::max(worst, std::fabs(double(tau[static_cast<std::size_t>(k)]) - expected[static_cast<std::size_t>(k)]));
        }
    }
    RecordProperty("worst_abs_difference_Nm", std::to_string(worst));
}

// The gravity torque about joint j's axis of every link beyond it, from
// where the links are now: sum m (c - anchor) x g.
double gravityTorque(const World& world, const Robot& robot, const RobotJoint& j) {
    std::vector<std::string> beyond{j.child};
    for (std::size_t k = 0; k < beyond.size(); ++k) {
        for (const RobotJoint& o : robot.joints) {
            if (o.parent == beyond[k]) beyond.push_back(o.child);
        }
    }
    const BodyId child = robot.body(j.child);
    const Vec3 anchor = world.position(child), axis = rotate(world.orientation(child), j.axis);
    Vec3 torque;
    for (const std::string& name : beyond) {
        const BodyId b = robot.body(name);
        torque += cross(world.centerOfMass(b) - anchor, world.settings().gravity * world.mass(b));
    }
    return double(dot(torque, axis));
}

// The KR5 held still by stiff drives (1/240 s steps, 8 sub-steps, joint rows
// at 480 Hz, as scripts/compare_dart.py): the gravity-holding efforts of
// inverse dynamics at the angles it settled at equal the efforts its drives
// deliver and the sum of m g x lever, within 0.1 % of each joint's own
// torque (the two wrist joints, loaded under 0.002 N m, within 1e-4 of the largest).
TEST(InverseDynamics, Kr5GravityCompensationEqualsHeldEfforts) {
    World world = zUpWorld(480, 8);
    Robot arm = loadUrdf(world, fs::path(FULCRUM_ROBOTS_DIR) / "kr5/kr5_sixx_r650.urdf", fixedBase());
    const std::size_t n = arm.actuatedJoints().size();
    ASSERT_EQ(n, 6u);
    const std::vector<Real> target{Real(0.3), Real(0.6), Real(-0.4), Real(0.2), Real(0.5), Real(0.1)};
    arm.setDriveGains(world, std::vector<Real>(n, Real(20000)), std::vector<Real>(n, Real(400)));
    arm.setPositionTargets(world, target);
    for (int i = 0; i < 3 * 240; ++i) world.step(Real(1) / 240);
    const std::vector<Real> q = arm.jointPositions(world), held = arm.jointEfforts(world);
    const std::vector<Real> zero(n, 0);
    const std::vector<Real> tau = arm.inverseDynamics(world, q, zero, zero);
    const auto act = arm.actuatedJoints();
    double largest = 0;
    for (std::size_t k = 0; k < n; ++k) largest = std::max(largest, std::fabs(double(tau[k])));
    std::string measured;
    for (std::size_t k = 0; k < n; ++k) {
        const double tol = std::max(1e-3 * std::fabs(double(tau[k])), 1e-4 * largest);
        const double lever = -gravityTorque(world, arm, arm.joints[act[k]]);
        EXPECT_NEAR(double(held[k]), double(tau[k]), tol) << arm.joints[act[k]].name;
        EXPECT_NEAR(lever, double(tau[k]), tol) << arm.joints[act[k]].name;
        measured += std::to_string(double(tau[k])) + " held " + std::to_string(double(held[k])) + " lever " + std::to_string(lever) + "; ";
    }
    RecordProperty("inverse_dynamics_held_lever", measured);
}

TEST(InverseDynamics, SliderLoadAndBadInput) {
    World world = zUpWorld();
    const Robot r = loadUrdf(world, fs::path(FULCRUM_SOURCE_DIR) / "tests/robots/slider_load.urdf", fixedBase());
    ASSERT_EQ(r.actuatedJoints().size(), 1u);
    const RobotJoint& j = r.joints[r.actuatedJoints()[0]];
    const double mass = double(world.mass(r.body(j.child)));
    const std::vector<Real> zero{0};
    // Held still, the slider carries the load's weight along its (vertical) axis.
    const double axisUp = double(normalize(j.axis).z);
    EXPECT_NEAR(double(r.inverseDynamics(world, zero, zero, zero)[0]), mass * kG * axisUp, 1e-5 * mass * kG);
    // Accelerating it up the axis at 2 m/s^2 takes m (g + 2).
    const std::vector<Real> up{Real(2)};
    EXPECT_NEAR(double(r.inverseDynamics(world, zero, zero, up)[0]), mass * (kG * axisUp + 2), 1e-5 * mass * kG);
    try {
        (void)r.inverseDynamics(world, std::vector<Real>{0, 0}, zero, zero);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("2 positions for 1 actuated joints"), std::string::npos) << e.what();
    }
    World free = zUpWorld();
    UrdfOptions o = fixedBase();
    o.fixedBase = false;
    const Robot loose = loadUrdf(free, fs::path(FULCRUM_SOURCE_DIR) / "tests/robots/double_pendulum.urdf", o);
    try {
        const std::vector<Real> z2{0, 0};
        (void)loose.inverseDynamics(free, z2, z2, z2);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is not static"), std::string::npos) << e.what();
    }
}

}  // namespace
