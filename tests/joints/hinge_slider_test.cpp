// Hinges and sliders: the free motion they allow, limits, motors and springs.
#include <algorithm>

#include "joints/joint_test_util.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

// A cube (isotropic inertia) hinged to the world about z at its centre, spun
// about (1, 2, 3) in zero gravity: the off-axis spin is removed (< 1e-3 rad/s)
// and the spin about z is kept (within 1 %); the anchor stays put (< 1 mm).
TEST(Hinge, AllowsOnlyRotationAboutItsAxis) {
    World world(worldDef(4, {0, 0, 0}));
    BodyDef d = boxBody(1, {0, 0, 0}, {Real(0.5), Real(0.5), Real(0.5)});
    d.angularVelocity = {1, 2, 3};
    const BodyId box = world.createBody(d);
    const JointId hinge = world.createJoint(jointDef(JointType::Hinge, kWorldBody, box, {0, 0, 0}, {0, 0, 1}));
    double worst = 0;
    for (int i = 0; i < 120; ++i) {
        world.step(kDt);
        worst = std::max(worst, double(world.jointError(hinge)));
    }
    const Vec3 w = world.angularVelocity(box);
    EXPECT_LT(std::hypot(w.x, w.y), 1e-3);
    EXPECT_NEAR(w.z, 3, 0.03);
    EXPECT_LT(worst, 1e-3);
    // The hinge angle follows the spin: 3 rad/s for 2 s, wrapped to (-pi, pi].
    EXPECT_NEAR(std::remainder(double(world.jointPosition(hinge)) - 6.0, 2 * kPi), 0, 0.1);
}

// A block on a frictionless slider tilted 45 degrees accelerates at g sin 45
// (within 1 % over 1 s); it doesn't turn (an initial spin is removed) and stays on the axis (1 mm).
TEST(Slider, AllowsOnlyTranslationAlongItsAxis) {
    World world(worldDef());
    BodyDef d = boxBody(2, {0, 0, 0}, {Real(0.2), Real(0.1), Real(0.1)});
    d.angularVelocity = {0.5, -1, 2};
    const BodyId block = world.createBody(d);
    const Vec3 axis = normalize(Vec3{1, -1, 0});
    const JointId slider = world.createJoint(jointDef(JointType::Slider, kWorldBody, block, {0, 0, 0}, axis));
    double worst = 0;
    for (int i = 0; i < 60; ++i) {
        world.step(kDt);
        worst = std::max(worst, double(world.jointError(slider)));
    }
    const double expected = 0.5 * kG * std::sin(kPi / 4) * 1.0;
    EXPECT_NEAR(world.jointPosition(slider) / expected, 1, 0.01);
    EXPECT_NEAR(dot(world.linearVelocity(block), axis) / (kG * std::sin(kPi / 4)), 1, 0.01);
    EXPECT_LT(length(world.angularVelocity(block)), 1e-3);
    EXPECT_LT(worst, 1e-3);
}

// A horizontal bar (1 m, hinged at one end about z) falls under gravity onto
// its lower limit of -0.5 rad and stays there: never more than 0.02 rad past it.
TEST(Hinge, LimitsHold) {
    World world(worldDef());
    const BodyId bar = world.createBody(boxBody(1, {Real(0.5), 0, 0}, {Real(0.5), Real(0.05), Real(0.05)}));
    JointDef j = jointDef(JointType::Hinge, kWorldBody, bar, {0, 0, 0}, {0, 0, 1});
    j.hasLimits = true;
    j.lowerLimit = Real(-0.5);
    j.upperLimit = Real(0.5);
    const JointId hinge = world.createJoint(j);
    double lowest = 0;
    for (int i = 0; i < 180; ++i) {
        world.step(kDt);
        lowest = std::min(lowest, double(world.jointPosition(hinge)));
    }
    EXPECT_GT(lowest, -0.52);
    EXPECT_NEAR(world.jointPosition(hinge), -0.5, 0.01);
    EXPECT_LT(world.jointError(hinge), 1e-3);
}

// A block on a vertical slider with limits [-1, 0] falls 1 m and stops: within 1 cm.
TEST(Slider, LimitsHold) {
    World world(worldDef());
    const BodyId block = world.createBody(boxBody(1, {0, 0, 0}, {Real(0.1), Real(0.1), Real(0.1)}));
    JointDef j = jointDef(JointType::Slider, kWorldBody, block, {0, 0, 0}, {0, 1, 0});
    j.hasLimits = true;
    j.lowerLimit = -1;
    j.upperLimit = 0;
    const JointId slider = world.createJoint(j);
    double lowest = 0;
    for (int i = 0; i < 120; ++i) {
        world.step(kDt);
        lowest = std::min(lowest, double(world.jointPosition(slider)));
    }
    EXPECT_GT(lowest, -1.01);
    EXPECT_NEAR(world.jointPosition(slider), -1, 0.005);
}

// Motor without load (zero gravity): reaches its target speed (1 %), using at
// most maxForce: with max torque tau on inertia I it takes at least I w / tau.
TEST(Hinge, MotorReachesTargetSpeedWithinItsTorque) {
    World world(worldDef(4, {0, 0, 0}));
    const BodyId wheel = world.createBody(boxBody(1, {0, 0, 0}, {Real(0.5), Real(0.5), Real(0.5)}));
    JointDef j = jointDef(JointType::Hinge, kWorldBody, wheel, {0, 0, 0}, {0, 0, 1});
    j.motor = {true, 2, Real(0.5)};
    const JointId hinge = world.createJoint(j);
    const double inertia = 1.0 / 6.0;  // cube of side 1, mass 1
    const double spinUp = inertia * 2 / 0.5;  // 0.667 s at full torque
    int steps = 0;
    while (world.angularVelocity(wheel).z < 2 * 0.99 && steps < 600) {
        world.step(kDt);
        ++steps;
    }
    EXPECT_GE(steps * double(kDt), spinUp * 0.99);
    EXPECT_NEAR(steps * double(kDt), spinUp, 2 * double(kDt));
    for (int i = 0; i < 60; ++i) world.step(kDt);
    EXPECT_NEAR(world.angularVelocity(wheel).z, 2, 0.02);
    // At constant speed the motor does no work: reaction torque ~ 0.
    EXPECT_LT(length(world.jointReactionTorque(hinge)), 1e-2);
}

// A horizontal arm (mass 1, length 1, hinged at one end) needs m g L / 2 = 4.9 N m
// to lift. A motor limited to half of that can't: the arm falls; one with twice
// that lifts it at the target speed.
TEST(Hinge, WeakMotorCannotLiftALoad) {
    for (const double factor : {0.5, 2.0}) {
        World world(worldDef());
        const BodyId arm = world.createBody(boxBody(1, {Real(0.5), 0, 0}, {Real(0.5), Real(0.05), Real(0.05)}));
        JointDef j = jointDef(JointType::Hinge, kWorldBody, arm, {0, 0, 0}, {0, 0, 1});
        j.motor = {true, Real(0.5), Real(factor * 0.5 * kG)};
        const JointId hinge = world.createJoint(j);
        for (int i = 0; i < 60; ++i) world.step(kDt);
        if (factor < 1) {
            EXPECT_LT(world.jointPosition(hinge), -0.3) << "the weak motor held the arm";
        } else {
            EXPECT_NEAR(world.angularVelocity(arm).z, 0.5, 0.01);
            EXPECT_GT(world.jointPosition(hinge), 0.4);
        }
    }
}

// A motor driving into a limit doesn't push through it (within 0.02 rad).
TEST(Hinge, MotorDoesNotOvershootLimit) {
    World world(worldDef(4, {0, 0, 0}));
    const BodyId wheel = world.createBody(boxBody(1, {0, 0, 0}, {Real(0.5), Real(0.5), Real(0.5)}));
    JointDef j = jointDef(JointType::Hinge, kWorldBody, wheel, {0, 0, 0}, {0, 0, 1});
    j.motor = {true, 5, 100};
    j.hasLimits = true;
    j.lowerLimit = -1;
    j.upperLimit = 1;
    const JointId hinge = world.createJoint(j);
    double highest = 0;
    for (int i = 0; i < 120; ++i) {
        world.step(kDt);
        highest = std::max(highest, double(world.jointPosition(hinge)));
    }
    EXPECT_LT(highest, 1.02);
    EXPECT_NEAR(world.jointPosition(hinge), 1, 0.01);
}

// A slider spring (k, no gravity) oscillates with period 2 pi sqrt(m / k): within 1 %.
TEST(Slider, SpringPeriod) {
    World world(worldDef(4, {0, 0, 0}));
    BodyDef d = boxBody(2, {0, 0, 0}, {Real(0.1), Real(0.1), Real(0.1)});
    const BodyId block = world.createBody(d);
    JointDef j = jointDef(JointType::Slider, kWorldBody, block, {0, 0, 0}, {1, 0, 0});
    j.spring = {true, Real(0.3), 50, 0};  // target 0.3 m: starts 0.3 m from rest
    world.createJoint(j);
    const double T = measurePeriod(world, [&] { return double(world.position(block).x) - 0.3; }, 5, 2000);
    EXPECT_NEAR(T / (2 * kPi * std::sqrt(2.0 / 50.0)), 1, 0.01) << T;
}

// A hinge spring to a target angle (torsional k on inertia I): period 2 pi sqrt(I / k) within 1 %.
TEST(Hinge, SpringPeriod) {
    World world(worldDef(4, {0, 0, 0}));
    const BodyId wheel = world.createBody(boxBody(1, {0, 0, 0}, {Real(0.5), Real(0.5), Real(0.5)}));
    JointDef j = jointDef(JointType::Hinge, kWorldBody, wheel, {0, 0, 0}, {0, 0, 1});
    j.spring = {true, Real(0.4), 2, 0};
    world.createJoint(j);
    const double T = measurePeriod(world, [&] { return 2 * std::asin(double(world.orientation(wheel).z)) - 0.4; }, 5, 2000);
    EXPECT_NEAR(T / (2 * kPi * std::sqrt((1.0 / 6.0) / 2.0)), 1, 0.01) << T;
}
