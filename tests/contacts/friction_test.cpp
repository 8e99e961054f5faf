// Friction and rolling against analytic results on an incline.
#include <gtest/gtest.h>

#include <numbers>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

constexpr Real kG = Real(9.81);

// A static slab tilted by theta about z (the slope goes down towards +x... or -x),
// with its top surface through the origin. Returns the unit down-slope direction.
Vec3 addIncline(World& world, Real theta, Real friction) {
    const Quat q = Quat::fromAxisAngle({0, 0, 1}, theta);
    BodyDef g;
    g.type = BodyType::Static;
    g.shape = Shape::box({40, Real(0.5), 10});
    g.orientation = q;
    g.position = rotate(q, {0, Real(-0.5), 0});
    g.friction = friction;
    world.createBody(g);
    return rotate(q, {-1, 0, 0});  // rotating +y towards -x: the surface descends along -x
}

Real slideDistance(Real thetaDeg, Real mu, Real seconds, int settleSteps = 0) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    const Real theta = thetaDeg * std::numbers::pi_v<Real> / 180;
    const Vec3 down = addIncline(world, theta, mu);
    return test::slideDistance(world, Quat::fromAxisAngle({0, 0, 1}, theta), down, mu, seconds, settleSteps);
}

}  // namespace

// Below tan(theta) = mu the box holds: mu = 0.5, theta = 20 deg (tan = 0.36):
// creep under 1 mm in 10 s (after a 0.5 s settle).
TEST(Friction, BoxHoldsBelowFrictionAngle) {
    EXPECT_LT(std::fabs(slideDistance(20, Real(0.5), 10, 30)), Real(0.001));
}

// Above it the box slides at a = g (sin theta - mu cos theta): theta = 30 deg,
// mu = 0.5 gives 0.657 m/s^2, so d = a t^2 / 2 = 1.314 m after 2 s (within 3 %).
TEST(Friction, BoxSlidesAtCoulombAcceleration) {
    const Real theta = std::numbers::pi_v<Real> / 6;
    const Real a = kG * (std::sin(theta) - Real(0.5) * std::cos(theta));
    const Real expected = Real(0.5) * a * 4;
    EXPECT_NEAR(slideDistance(30, Real(0.5), 2), expected, Real(0.03) * expected);
}

// A solid sphere rolling without slipping accelerates at 5/7 g sin theta
// (rolling resistance 0): speed after 2 s within 2 %, and the contact point
// doesn't slip (v = w r within 2 %).
TEST(Friction, SphereRollsAtFiveSeventhsGSinTheta) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    const Real theta = Real(20) * std::numbers::pi_v<Real> / 180;
    const Vec3 down = addIncline(world, theta, Real(0.6));
    const Quat q = Quat::fromAxisAngle({0, 0, 1}, theta);
    const Real r = Real(0.3);
    const BodyId ball = addSphere(world, rotate(q, {0, r, 0}), r);
    run(world, 120);
    const Real v = dot(world.linearVelocity(ball), down);
    const Real expected = Real(5) / 7 * kG * std::sin(theta) * 2;
    EXPECT_NEAR(v, expected, Real(0.02) * expected);
    EXPECT_NEAR(length(world.angularVelocity(ball)) * r, v, Real(0.02) * expected);
}

// Rolling resistance brings a rolling ball to rest on a level floor; without
// it the ball keeps rolling (energy is not lost by the friction row alone).
TEST(Friction, RollingResistanceStopsABall) {
    for (Real rr : {Real(0), Real(0.2)}) {
        WorldDef def;
        def.sleeping = false;
        World world(def);
        addGround(world);
        BodyDef d;
        d.shape = Shape::sphere(Real(0.25));
        d.mass = 1;
        d.position = {0, Real(0.25), 0};
        d.linearVelocity = {2, 0, 0};
        d.angularVelocity = {0, 0, -8};  // rolling: w = v / r
        d.rollingResistance = rr;
        const BodyId ball = world.createBody(d);
        run(world, 240);
        if (rr == 0) {
            EXPECT_GT(world.linearVelocity(ball).x, Real(1.95));
        } else {
            // Decelerates at about 5/7 rr g: stops within 2 s; 4 s later it is at rest.
            EXPECT_LT(length(world.linearVelocity(ball)), Real(1e-2));
        }
    }
}
