// Built against an installed Fulcrum: a ball dropped on a plane must come to
// rest touching it (centre at its radius, within 2 mm) and fall asleep.
#include <fulcrum/fulcrum.hpp>

#include <cmath>
#include <cstdio>

int main() {
    fulcrum::World world;
    fulcrum::BodyDef ground;
    ground.type = fulcrum::BodyType::Static;
    ground.shape = fulcrum::Shape::plane({0, 1, 0}, 0);
    world.createBody(ground);
    fulcrum::BodyDef ball;
    ball.shape = fulcrum::Shape::sphere(0.25f);
    ball.position = {0, 10, 0};
    ball.restitution = 0.5f;
    const fulcrum::BodyId id = world.createBody(ball);
    for (int i = 0; i < 600; ++i) world.step(1.0f / 60);
    const float y = world.position(id).y;
    std::printf("ball at y = %.4f m, %s\n", static_cast<double>(y), world.isAwake(id) ? "awake" : "asleep");
    return std::fabs(y - 0.25f) < 0.002f && !world.isAwake(id) ? 0 : 1;
}
