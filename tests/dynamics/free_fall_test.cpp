// Free fall and projectile motion for each integrator against the exact
// x(t) = x0 + v0 t + g t^2 / 2, and the order of each method's error.
//
// With constant acceleration a the errors are known in closed form
// (x_n = x0 + v0 t + a h^2 n(n -/+ 1) / 2):
//   explicit Euler       x_n = exact - a h t / 2   (lags behind: first order)
//   semi-implicit Euler  x_n = exact + a h t / 2   (runs ahead: first order)
//   Verlet               x_n = exact               (second order, exact for constant a)
// Here a = -g along y, so explicit Euler ends g h t / 2 too high and
// semi-implicit Euler g h t / 2 too low.
#include "dynamics/test_scenes.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

struct Projectile {
    Vec3 position, velocity;
};

Projectile runProjectile(Integrator integrator, int stepsPerSecond, double seconds) {
    World world(worldDef(integrator));
    const BodyId ball = world.createBody(pointMass(1, {0, 2, 0}, {5, 10, -3}));
    const int steps = static_cast<int>(std::lround(seconds * stepsPerSecond));
    for (int i = 0; i < steps; ++i) world.step(Real(1) / static_cast<Real>(stepsPerSecond));
    return {world.position(ball), world.linearVelocity(ball)};
}

constexpr double g = 9.81, t = 1.0;
const double exactY = 2 + 10 * t - 0.5 * g * t * t;
const double exactX = 5 * t, exactZ = -3 * t;
const double exactVy = 10 - g * t;

}  // namespace

TEST(FreeFall, ErrorMatchesEachIntegratorsOrder) {
    for (Integrator integrator : kAllIntegrators) {
        SCOPED_TRACE(toString(integrator));
        const Projectile coarse = runProjectile(integrator, 60, t);
        const Projectile fine = runProjectile(integrator, 120, t);
        // Horizontal motion has no acceleration: every method is exact (float rounding, 1e-5 m).
        EXPECT_NEAR(coarse.position.x, exactX, 1e-5);
        EXPECT_NEAR(coarse.position.z, exactZ, 1e-5);
        // The velocity of a constant acceleration is exact for all three (1e-4 m/s rounding).
        EXPECT_NEAR(coarse.velocity.y, exactVy, 1e-4);

        const double errCoarse = coarse.position.y - exactY;
        const double errFine = fine.position.y - exactY;
        switch (integrator) {
            case Integrator::ExplicitEuler:
            case Integrator::SemiImplicitEuler: {
                const double sign = integrator == Integrator::ExplicitEuler ? 1 : -1;
                // The closed-form error -/+ g h t / 2 (0.5 % tolerance for float rounding).
                EXPECT_NEAR(errCoarse, sign * g * (1.0 / 60) * t / 2, 0.005 * g / 120);
                EXPECT_NEAR(errFine, sign * g * (1.0 / 120) * t / 2, 0.005 * g / 240);
                // First order: halving h halves the error (ratio 2 within 1 %).
                EXPECT_NEAR(errCoarse / errFine, 2.0, 0.02);
                break;
            }
            case Integrator::Verlet:
                // Exact up to float rounding (positions ~5 m, 60 steps: 5e-5 m).
                EXPECT_NEAR(errCoarse, 0.0, 5e-5);
                EXPECT_NEAR(errFine, 0.0, 5e-5);
                break;
        }
    }
}

TEST(FreeFall, SubstepsAreEquivalentToSmallerSteps) {
    // 60 Hz with 4 sub-steps must land where 240 Hz with 1 sub-step does
    // (same h): semi-implicit error -g h t / 2 with h = 1/240 (1e-4 m rounding).
    World world(worldDef(Integrator::SemiImplicitEuler, 4));
    const BodyId ball = world.createBody(pointMass(1, {0, 2, 0}, {5, 10, -3}));
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
    EXPECT_NEAR(world.position(ball).y, exactY - g * (1.0 / 240) * t / 2, 1e-4);
    EXPECT_NEAR(world.time(), 1.0, 1e-6);
    EXPECT_EQ(world.stepCount(), 60u);
}

TEST(FreeFall, GravityScaleScalesTheAcceleration) {
    // Verlet is exact for constant acceleration, so y = y0 - s g t^2 / 2 (1e-4 m).
    for (Real scale : {Real(0), Real(0.5), Real(-1)}) {
        World world(worldDef(Integrator::Verlet));
        BodyDef d = pointMass(2, {0, 10, 0});
        d.gravityScale = scale;
        const BodyId ball = world.createBody(d);
        for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
        EXPECT_NEAR(world.position(ball).y, 10 - 0.5 * scale * g, 1e-4) << "scale " << scale;
    }
    // setGravityScale after creation.
    World world(worldDef(Integrator::Verlet));
    const BodyId ball = world.createBody(pointMass(2, {0, 10, 0}));
    world.setGravityScale(ball, Real(0.25));
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
    EXPECT_NEAR(world.position(ball).y, 10 - 0.125 * g, 1e-4);
}
