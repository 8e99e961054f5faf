// Pendulums against their analytic periods, and the double pendulum's energy.
#include <algorithm>

#include "joints/joint_test_util.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

// A sphere on a rigid rod (distance joint, anchors at the pivot and the
// sphere's centre) is a simple pendulum: the rod exerts no torque on the sphere.
struct RodPendulum {
    World world{worldDef()};
    BodyId bob;
    JointId rod;
    RodPendulum(double L, double theta0) {
        const Vec3 p{Real(L * std::sin(theta0)), Real(-L * std::cos(theta0)), 0};
        bob = world.createBody(sphereBody(1, p));
        JointDef j = jointDef(JointType::Distance, kWorldBody, bob, {0, 0, 0});
        j.anchorB = p;
        rod = world.createJoint(j);
    }
};

}  // namespace

// Small amplitude (5 degrees): period 2 pi sqrt(L/g) times the finite-amplitude
// factor (AGM), within 1 %.
TEST(Pendulum, SmallAmplitudePeriod) {
    const double L = 1, theta0 = 5 * kPi / 180;
    RodPendulum p(L, theta0);
    const double T = measurePeriod(p.world, [&] { return double(p.world.position(p.bob).x); }, 6, 2000);
    const double expected = pendulumPeriod(L, theta0);
    EXPECT_NEAR(expected / (2 * kPi * std::sqrt(L / kG)), 1.0005, 1e-4);  // the AGM is right
    EXPECT_NEAR(T / expected, 1, 0.01) << "T " << T << " expected " << expected;
}

// Released from 90 degrees: T = 4 sqrt(L/g) K(sin 45 deg) = 1.18 x the small-angle period; within 1 %.
TEST(Pendulum, NinetyDegreePeriod) {
    const double L = 2, theta0 = kPi / 2;
    RodPendulum p(L, theta0);
    const double T = measurePeriod(p.world, [&] { return double(p.world.position(p.bob).x); }, 5, 2000);
    const double expected = pendulumPeriod(L, theta0);
    EXPECT_NEAR(T / expected, 1, 0.01) << "T " << T << " expected " << expected;
    EXPECT_LT(p.world.jointError(p.rod), 1e-3);
}

// A ball joint makes a compound pendulum of the sphere (radius r, at distance L):
// equivalent length (L^2 + 2/5 r^2) / L. Small amplitude, within 1 %.
TEST(Pendulum, BallJointCompoundPendulum) {
    const double L = 1, r = 0.2, theta0 = 4 * kPi / 180;
    World world(worldDef());
    const Vec3 p{Real(L * std::sin(theta0)), Real(-L * std::cos(theta0)), 0};
    const BodyId bob = world.createBody(sphereBody(2, p, Real(r)));
    const JointId j = world.createJoint(jointDef(JointType::Ball, kWorldBody, bob, {0, 0, 0}));
    const double T = measurePeriod(world, [&] { return double(world.position(bob).x); }, 6, 2000);
    const double expected = pendulumPeriod((L * L + 0.4 * r * r) / L, theta0);
    EXPECT_NEAR(T / expected, 1, 0.01) << "T " << T << " expected " << expected;
    EXPECT_LT(world.jointError(j), 1e-3);
}

// Double pendulum (two rods, chaotic, released horizontal): the constraint
// solver must not add energy. Over 20 s the total energy never rises above its
// start by more than 1 % of the energy it swings through (3 m g L = 29 J: the
// symplectic integrator's bounded oscillation), the highest energy of the last
// 5 s is not above that of the first 5 s (no growth), and the rods hold (1 cm,
// at bob speeds up to 8 m/s).
TEST(Pendulum, DoublePendulumEnergyBounded) {
    World world(worldDef());
    const Vec3 p1{1, 0, 0}, p2{2, 0, 0};
    const BodyId b1 = world.createBody(sphereBody(1, p1));
    const BodyId b2 = world.createBody(sphereBody(1, p2));
    JointDef r1 = jointDef(JointType::Distance, kWorldBody, b1, {0, 0, 0});
    r1.anchorB = p1;
    JointDef r2 = jointDef(JointType::Distance, b1, b2, p1);
    r2.anchorB = p2;
    const JointId j1 = world.createJoint(r1), j2 = world.createJoint(r2);
    const double e0 = world.energy().total;
    const double scale = 3 * kG * 1;
    double maxRise = -1e9, worstError = 0, firstMax = -1e9, lastMax = -1e9;
    for (int i = 0; i < 1200; ++i) {
        world.step(kDt);
        const double e = world.energy().total - e0;
        maxRise = std::max(maxRise, e);
        if (i < 300) firstMax = std::max(firstMax, e);
        if (i >= 900) lastMax = std::max(lastMax, e);
        worstError = std::max({worstError, double(world.jointError(j1)), double(world.jointError(j2))});
    }
    EXPECT_LT(maxRise, 0.01 * scale) << "energy grew by " << maxRise << " J";
    EXPECT_LE(lastMax, firstMax);
    // ... and it doesn't just bleed away either (soft joints damp a little: 1.2 J measured).
    EXPECT_GT(world.energy().total - e0, -0.1 * scale);
    EXPECT_LT(worstError, 1e-2);
}
