// Robot::inverseDynamics (recursive Newton-Euler, src/io/urdf_dynamics.cpp)
// against closed forms and the simulation: a double pendulum's two-link
// equations of motion along a sine trajectory; the KR5's gravity-holding
// efforts against the efforts its drives are measured to deliver holding
// the same pose, and against the sum of m g x lever of the links beyond each
// joint; a slider's load against m g; the URDF damping and friction against
// their definition and a simulated spin-down; a floating two-body system
// against its closed form (momentum and angular momentum balance).
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

// A URDF of a base and one link on a revolute joint about z through the
// base's centre of mass (the base's origin): the link's centre L = 0.4 m out
// along its x. Diagonal inertias, so z is principal for both: the motion
// about z is planar.
std::string twoBodies(const char* dynamics = "") {
    return std::string(R"(<robot name="two"><link name="base"><inertial><mass value="2"/>)"
                       R"(<inertia ixx="0.03" iyy="0.04" izz="0.05"/></inertial></link>)"
                       R"(<link name="arm"><inertial><origin xyz="0.4 0 0"/><mass value="1"/>)"
                       R"(<inertia ixx="0.002" iyy="0.01" izz="0.01"/></inertial></link>)"
                       R"(<joint name="j" type="continuous"><parent link="base"/><child link="arm"/>)"
                       R"(<axis xyz="0 0 1"/>)") +
           dynamics + R"(</joint></robot>)";
}

UrdfOptions floatingBase() {
    UrdfOptions o;
    o.warn = [](const std::string&) {};
    return o;
}

// The URDF damping d and Coulomb friction f add d qd + f sgn(qd) (at qd = 0:
// f sgn(qdd), and 0 at rest) to the rigid tree's efforts; options leave them out.
TEST(InverseDynamics, DampingAndFriction) {
    World world = zUpWorld();
    const Robot r = loadUrdfFromString(world, twoBodies(R"(<dynamics damping="0.3" friction="0.7"/>)"), "two.urdf", fixedBase());
    const auto tau = [&](Real qd, Real qdd, InverseDynamicsOptions o = {}) {
        return double(r.inverseDynamics(world, std::vector<Real>{Real(0.2)}, std::vector<Real>{qd}, std::vector<Real>{qdd}, o)[0]);
    };
    const InverseDynamicsOptions none{false, false};
    const double rigid = tau(Real(1.5), 2, none);
    EXPECT_NEAR(rigid, (0.01 + 1 * 0.4 * 0.4) * 2, 1e-5);  // (I_cm + m L^2) qdd about the static base
    EXPECT_NEAR(tau(Real(1.5), 2) - rigid, 0.3 * 1.5 + 0.7, 1e-5);
    EXPECT_NEAR(tau(Real(-1.5), 2) - rigid, -0.3 * 1.5 - 0.7, 1e-5);
    EXPECT_NEAR(tau(Real(1.5), 2, {true, false}) - rigid, 0.3 * 1.5, 1e-5);
    EXPECT_NEAR(tau(0, 2) - tau(0, 2, none), 0.7, 1e-5);    // breaking away forwards
    EXPECT_NEAR(tau(0, -2) - tau(0, -2, none), -0.7, 1e-5);  // and backwards
    EXPECT_NEAR(tau(0, 0), 0, 1e-6);                         // at rest: no friction, no load (z is vertical)
}

// The same joint spinning down in the simulation (drives off: the URDF
// damping and friction act), its axis vertical so gravity exerts no torque:
// the inverse dynamics of its measured motion is the effort of no actuator,
// 0 within 2 % of the losses d qd + f.
TEST(InverseDynamics, LossesMatchTheSimulatedSpinDown) {
    WorldDef def;
    def.gravity = {0, 0, Real(-kG)};
    def.substeps = 8;
    World world(def);
    Robot r = loadUrdfFromString(world, twoBodies(R"(<dynamics damping="0.3" friction="0.7"/>)"), "two.urdf", fixedBase());
    const BodyId arm = r.body("arm");
    const Vec3 spin{0, 0, 6};
    world.setAngularVelocity(arm, spin);
    world.setLinearVelocity(arm, cross(spin, world.centerOfMass(arm)));
    const Real dt = Real(1) / 480;
    for (int i = 0; i < 48; ++i) world.step(dt);
    const Real q0 = r.jointPositions(world)[0], v0 = r.jointVelocities(world)[0];
    world.step(dt);
    const Real v1 = r.jointVelocities(world)[0];
    const Real qdd = (v1 - v0) / dt, qd = (v0 + v1) / 2;
    const double losses = 0.3 * double(qd) + 0.7;
    const double tau = double(r.inverseDynamics(world, std::vector<Real>{q0}, std::vector<Real>{qd}, std::vector<Real>{qdd})[0]);
    EXPECT_GT(double(qd), 3);
    EXPECT_NEAR(tau, 0, 0.02 * losses) << "qd " << qd << " qdd " << qdd;
}

// The two-body system floating (Featherstone's floating-base inverse
// dynamics) against its closed form. The hinge is at the base's centre P, so
// the arm's centre is c = P + L e_r(phi), phi = theta0 + q. The hinge force
// on the arm is mu a_rel (mu = m1 m2 / (m1 + m2), a_rel = L phi'' e_t -
// L phi'^2 e_r: linear momentum has rate (m1 + m2) g); about the arm's centre
// it has the moment -mu L^2 phi'', so tau = (I2 + mu L^2) phi'' = J phi'',
// and the base turns with theta0'' = -tau / I1: tau = J I1 q'' / (I1 + J),
// theta0'' = -J q'' / (I1 + J), a_P = g - (m2 / (m1 + m2)) a_rel.
TEST(InverseDynamics, FloatingTwoBodiesMatchClosedForm) {
    World world = zUpWorld();
    const Robot r = loadUrdfFromString(world, twoBodies(), "two.urdf", floatingBase());
    const double m1 = 2, m2 = 1, I1 = 0.05, I2 = 0.01, L = 0.4, mu = m1 * m2 / (m1 + m2), J = I2 + mu * L * L;
    const double q = 0.3, qd = -0.7, qdd = 2, w0 = 1.5;
    RobotBaseState base;
    base.position = {1, 2, 3};
    base.angularVelocity = {0, 0, Real(w0)};
    const std::vector<Real> Q{Real(q)}, Qd{Real(qd)}, Qdd{Real(qdd)};
    const FloatingBaseDynamics d = r.freeBaseInverseDynamics(world, base, Q, Qd, Qdd);
    const double tau = J * I1 * qdd / (I1 + J), theta0dd = -J * qdd / (I1 + J);
    const double phi = q, phid = w0 + qd, phidd = theta0dd + qdd;
    const double er[2] = {std::cos(phi), std::sin(phi)}, et[2] = {-std::sin(phi), std::cos(phi)};
    const double arel[2] = {L * phidd * et[0] - L * phid * phid * er[0], L * phidd * et[1] - L * phid * phid * er[1]};
    const double k = m2 / (m1 + m2);
    ASSERT_EQ(d.efforts.size(), 1u);
    EXPECT_NEAR(double(d.efforts[0]), tau, 1e-5);
    EXPECT_NEAR(double(d.angularAcceleration.z), theta0dd, 1e-5);
    EXPECT_NEAR(double(d.angularAcceleration.x), 0, 1e-5);
    EXPECT_NEAR(double(d.angularAcceleration.y), 0, 1e-5);
    EXPECT_NEAR(double(d.linearAcceleration.x), -k * arel[0], 1e-5);
    EXPECT_NEAR(double(d.linearAcceleration.y), -k * arel[1], 1e-5);
    EXPECT_NEAR(double(d.linearAcceleration.z), -kG, 1e-5);
    EXPECT_EQ(d.force, Vec3{});
    // The prescribed-base form with that acceleration needs no wrench, and the same effort.
    const FloatingBaseDynamics p =
        r.prescribedBaseInverseDynamics(world, base, d.linearAcceleration, d.angularAcceleration, Q, Qd, Qdd);
    EXPECT_NEAR(double(length(p.force)), 0, 1e-4);
    EXPECT_NEAR(double(length(p.torque)), 0, 1e-5);
    EXPECT_NEAR(double(p.efforts[0]), tau, 1e-5);
    // Holding the base still instead (the arm starting from rest) takes the
    // arm's m2 L q'' e_t and the weight (m1 + m2) g as force, and
    // (I2 + m2 L^2) q'' about z as torque; the effort is that torque.
    base.angularVelocity = {};
    const FloatingBaseDynamics held = r.prescribedBaseInverseDynamics(world, base, {}, {}, Q, std::vector<Real>{0}, Qdd);
    EXPECT_NEAR(double(held.force.x), m2 * L * qdd * et[0], 1e-5);
    EXPECT_NEAR(double(held.force.y), m2 * L * qdd * et[1], 1e-5);
    EXPECT_NEAR(double(held.force.z), (m1 + m2) * kG, 1e-4);  // and the weight
    EXPECT_NEAR(double(held.torque.z), (I2 + m2 * L * L) * qdd, 1e-5);
    EXPECT_NEAR(double(held.efforts[0]), (I2 + m2 * L * L) * qdd, 1e-5);
}

// A free tree at rest, joints still: it falls with g and needs no effort;
// the base state read from the world is the root link's; a static root or a
// fixed-base call on a floating robot is an error.
TEST(InverseDynamics, FloatingTreeFallsFreely) {
    World world = zUpWorld();
    const Robot r = loadUrdfFromString(world, twoBodies(), "two.urdf", floatingBase());
    const RobotBaseState base = r.baseState(world);
    EXPECT_EQ(base.position, world.position(r.body("base")));
    const std::vector<Real> z{0};
    const FloatingBaseDynamics d = r.freeBaseInverseDynamics(world, base, z, z, z);
    EXPECT_NEAR(double(d.linearAcceleration.z), -kG, 1e-5);
    EXPECT_NEAR(double(length(d.angularAcceleration)), 0, 1e-5);  // float rounding of the 6x6 solve
    EXPECT_NEAR(double(d.efforts[0]), 0, 1e-6);
    EXPECT_THROW((void)r.inverseDynamics(world, z, z, z), Error);
    World fixedWorld = zUpWorld();
    const Robot fixed = loadUrdfFromString(fixedWorld, twoBodies(), "two.urdf", fixedBase());
    try {
        (void)fixed.freeBaseInverseDynamics(fixedWorld, base, z, z, z);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is static"), std::string::npos) << e.what();
    }
}

}  // namespace
