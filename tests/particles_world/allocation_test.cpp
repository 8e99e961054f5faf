// No heap allocation inside World::step with ropes and cloths once the world
// has warmed up, and bit-identical results for the same input (global
// operator new is counted by support/counting_allocator.hpp).
#include <gtest/gtest.h>

#include "fulcrum/world.hpp"
#include "support/counting_allocator.hpp"

using namespace fulcrum;

namespace {

// A rope holding a box, a cloth falling on a sphere and a box, a ground.
World buildScene() {
    World world;
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::plane({0, 1, 0}, 0);
    world.createBody(ground);
    BodyDef ball;
    ball.type = BodyType::Static;
    ball.shape = Shape::sphere(Real(0.4));
    ball.position = {0, 0.8f, 0};
    world.createBody(ball);
    BodyDef box;
    box.shape = Shape::box(Vec3::splat(Real(0.1)));
    box.mass = Real(0.5);
    box.position = {0.6f, 0.1f, 0};
    world.createBody(box);
    BodyDef weight = box;
    weight.position = {2, 1.9f, 0};
    const BodyId hung = world.createBody(weight);
    RopeDef rope;
    rope.start = {2, 3, 0};
    rope.end = {2, 2, 0};
    rope.attachEnd = hung;
    rope.bendCompliance = 1;
    world.createRope(rope);
    ClothDef cloth;
    cloth.size = {12, 12};
    cloth.spacing = Real(0.1);
    cloth.radius = Real(0.04);
    cloth.origin = {-0.5f, 1.6f, -0.5f};
    cloth.bendCompliance = Real(0.1);
    world.createCloth(cloth);
    return world;
}

}  // namespace

TEST(ParticlesWorldAllocation, StepAllocatesNothingAfterWarmUp) {
    World world = buildScene();
    for (int i = 0; i < 30; ++i) world.step(Real(1) / 60);  // contacts, pairs and scratch reach their size
    fulcrum::test::CountAllocations count;
    for (int i = 0; i < 30; ++i) world.step(Real(1) / 60);
    EXPECT_EQ(count.stop(), 0);
}

TEST(ParticlesWorldAllocation, SameInputGivesBitIdenticalParticles) {
    World a = buildScene(), b = buildScene();
    for (int i = 0; i < 40; ++i) {
        a.step(Real(1) / 60);
        b.step(Real(1) / 60);
    }
    for (std::size_t k = 0; k < a.particleSystems().size(); ++k) {
        const auto xa = a.particlePositions(a.particleSystems()[k]), xb = b.particlePositions(b.particleSystems()[k]);
        ASSERT_EQ(xa.size(), xb.size());
        for (std::size_t i = 0; i < xa.size(); ++i) ASSERT_EQ(xa[i], xb[i]) << "system " << k << " particle " << i;
    }
    for (const BodyId id : a.bodies()) EXPECT_EQ(a.transform(id), b.transform(id));
}
