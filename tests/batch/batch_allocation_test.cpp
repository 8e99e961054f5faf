// A batch adds no heap allocation to the worlds' steps in steady state
// (docs/architecture.md: no per-step allocation), nor to reading and writing
// the arrays: a learning loop calls these every step.
#include <gtest/gtest.h>

#include <vector>

#include "fulcrum/batch.hpp"
#include "support/counting_allocator.hpp"

namespace fulcrum {
namespace {

World stackWorld(int height) {
    WorldDef def;
    def.sleeping = false;  // keep the contacts working every step
    World world(def);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({5, Real(0.5), 5});
    ground.position = {0, Real(-0.5), 0};
    world.createBody(ground);
    for (int i = 0; i < height; ++i) {
        BodyDef box;
        box.shape = Shape::box({Real(0.5), Real(0.5), Real(0.5)});
        box.mass = 1;
        box.position = {Real(0.02) * Real(i), Real(0.5) + Real(i), 0};
        world.createBody(box);
    }
    return world;
}

TEST(BatchAllocation, SteppingAndArraysAllocateNothingInSteadyState) {
    for (int threads : {1, 2}) {
        std::vector<World> worlds;
        for (int w = 0; w < 5; ++w) worlds.push_back(stackWorld(3 + w));  // different costs
        // Arrays need one body count: pad the smaller worlds with free spheres far away.
        for (int w = 0; w < 5; ++w) {
            for (int k = 3 + w; k < 7; ++k) {
                BodyDef ball;
                ball.shape = Shape::sphere(Real(0.2));
                ball.mass = 1;
                ball.position = {Real(20 + 2 * k), 5, 0};
                ball.gravityScale = 0;
                worlds[static_cast<std::size_t>(w)].createBody(ball);
            }
        }
        Batch batch(std::move(worlds), BatchDef{threads});
        const Real dt = Real(1) / Real(60);
        batch.step(dt, 60);  // contact caches and scratch reach their size
        std::vector<Real> positions(batch.size() * batch.bodyCount() * 3);
        std::vector<Real> forces(positions.size(), 0);
        batch.positions(positions);

        test::CountAllocations count;
        for (int s = 0; s < 10; ++s) {
            batch.applyForces(forces);
            batch.step(dt, 1);
            batch.positions(positions);
        }
        EXPECT_EQ(count.stop(), 0) << "threads " << threads;
    }
}

}  // namespace
}  // namespace fulcrum
