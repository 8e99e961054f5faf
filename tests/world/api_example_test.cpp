// The minimal example of docs/api.md, compiled and run as a test (keep them in sync).
// Physics check: the ball, dropped from 10 m, has fallen g t^2 / 2 = 4.905 m after
// 1 s (semi-implicit Euler at h = 1/300, 5 sub-steps, adds g h t / 2 = 0.016 m; 1e-3 tolerance).
#include <gtest/gtest.h>

#include <cstdio>

// ---- example begins
#include <fulcrum/fulcrum.hpp>

double dropBall() {
    using namespace fulcrum;
    World world;                                   // gravity (0, -9.81, 0), semi-implicit Euler, 5 sub-steps

    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::plane({0, 1, 0}, 0);
    world.createBody(ground);

    BodyDef ball;
    ball.name = "ball";
    ball.shape = Shape::sphere(0.25f);
    ball.mass = 2;                                 // or leave 0 and set density
    ball.position = {0, 10, 0};
    const BodyId id = world.createBody(ball);

    world.setDrag(id, 0, 0);                       // no air resistance
    for (int i = 0; i < 60; ++i) world.step(1.0f / 60);

    const Vec3 p = world.position(id);
    const EnergyReport e = world.energy();
    std::printf("%s at y = %.3f m, E = %.2f J\n", world.name(id).c_str(), p.y, e.total);
    return p.y;
}
// ---- example ends

TEST(ApiExample, DropBall) { EXPECT_NEAR(dropBall(), 10 - 0.5 * 9.81 - 0.5 * 9.81 / 300, 1e-3); }
