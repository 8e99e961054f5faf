// Free fall for each integrator against x(t) = x0 + v0 t + g t^2 / 2.
#include <gtest/gtest.h>

#include "fulcrum/fulcrum.hpp"

using namespace fulcrum;

TEST(FreeFallSmoke, SemiImplicitFallsUnderGravity) {
    World world;
    BodyDef d;
    d.position = {0, 10, 0};
    const BodyId ball = world.createBody(d);
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
    // Semi-implicit Euler over t = 1 s, h = 1/240: y = 10 - g t^2/2 - g h t/2 (first-order error).
    const double h = 1.0 / 240, t = 1.0, g = 9.81;
    const double expected = 10 - 0.5 * g * t * t - 0.5 * g * h * t;
    EXPECT_NEAR(world.position(ball).y, expected, 1e-4);  // float rounding over 240 sub-steps
}
