// FixedStepper: the number of steps and the interpolation factor for a sequence
// of frame times, and interpolation that lands on the analytic trajectory.
#include "dynamics/test_scenes.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

TEST(FixedStepper, StepsAndAlphaForFrameTimes) {
    World world(worldDef(Integrator::SemiImplicitEuler, 1, {0, 0, 0}));
    const Real dt = Real(0.01);
    FixedStepper stepper(world, dt, 4);
    // accumulator: 0.004 -> 0 steps, alpha 0.4
    EXPECT_EQ(stepper.advance(Real(0.004)), 0);
    EXPECT_NEAR(stepper.alpha(), 0.4, 1e-4);
    // 0.004 + 0.011 = 0.015 -> 1 step, alpha 0.5
    EXPECT_EQ(stepper.advance(Real(0.011)), 1);
    EXPECT_NEAR(stepper.alpha(), 0.5, 1e-4);
    // 0.005 + 0.0251 = 0.0301 -> 3 steps, alpha 0.01
    EXPECT_EQ(stepper.advance(Real(0.0251)), 3);
    EXPECT_NEAR(stepper.alpha(), 0.01, 1e-3);
    // A 1 s hitch: at most 4 steps, the backlog is dropped, alpha stays in [0, 1).
    EXPECT_EQ(stepper.advance(1), 4);
    EXPECT_GE(stepper.alpha(), 0);
    EXPECT_LT(stepper.alpha(), 1);
    EXPECT_EQ(world.stepCount(), 8u);
    EXPECT_NEAR(world.time(), 0.08, 1e-6);
    EXPECT_EQ(stepper.advance(0), 0);
}

TEST(FixedStepper, InterpolationFollowsTheTrajectory) {
    // A body moving at 2 m/s and turning at pi rad/s with no forces: the interpolated
    // transform at alpha sits at the analytic pose of time (steps - 1 + alpha) dt.
    World world(worldDef(Integrator::SemiImplicitEuler, 1, {0, 0, 0}));
    BodyDef d = pointMass(1, {}, {2, 0, 0});
    d.angularVelocity = {0, 0, Real(kPi)};
    const BodyId b = world.createBody(d);
    const Real dt = Real(1) / 60;
    FixedStepper stepper(world, dt);
    double frameTime = 0;
    for (int frame = 0; frame < 7; ++frame) {
        stepper.advance(Real(0.0123));
        frameTime += 0.0123;
        if (world.stepCount() == 0) continue;
        // Rendering lags one step: the interpolated pose is that of time
        // t_render = frameTime - dt (steps - 1 + alpha = (frameTime - dt) / dt).
        const double tRender = (static_cast<double>(world.stepCount()) - 1 + stepper.alpha()) * dt;
        EXPECT_NEAR(tRender, frameTime - dt, 1e-5);
        const Transform t = stepper.interpolatedTransform(b);
        EXPECT_NEAR(t.p.x, 2 * tRender, 1e-5);  // 1e-5 m float rounding
        const double angle = 2 * std::atan2(t.q.z, t.q.w);
        EXPECT_NEAR(angle, kPi * tRender, 1e-4);
    }
}

TEST(FixedStepper, RejectsBadInput) {
    World world;
    EXPECT_THROW(FixedStepper(world, 0), Error);
    EXPECT_THROW(FixedStepper(world, Real(0.01), 0), Error);
    FixedStepper stepper(world, Real(0.01));
    EXPECT_THROW(stepper.advance(-1), Error);
    EXPECT_THROW(stepper.advance(std::numeric_limits<Real>::quiet_NaN()), Error);
}
