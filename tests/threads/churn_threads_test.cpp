// The churn scenes of bench/churn_scenes.hpp, small: bodies and joints
// created and destroyed between steps (Box3D's rain: ragdolls, their
// capsules' frames moved onto the capsules), fast continuous bodies in a box
// (Jolt's HighSpeed: most moving proxies leave their fat boxes every step, so
// the moving tree is rebuilt in bulk rather than leaf by leaf) and many
// static bodies under a few dropped spheres (Box3D's large_world: the
// buffers sized for the moving bodies). Each runs on one thread and on two
// (the parallel paths forced on) and must give the same bits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "../../bench/churn_scenes.hpp"
#include "../../bench/fulcrum_world.hpp"

namespace {

using namespace fulcrum;

// Every live body's position and orientation after the scene's steps.
std::vector<Real> finalState(const bench::SceneSpec& scene, int threads) {
    bench::FulcrumWorld built = bench::buildFulcrumWorld(scene, threads);
    World& world = *built.world;
    world.setParallelMinBodies(0);
    bench::FulcrumScript script(scene, built);
    for (int i = 0; i < scene.steps; ++i) {
        script.beforeStep(i);
        world.step(static_cast<Real>(scene.dt));
    }
    std::vector<BodyId> ids = built.bodies;
    for (const BodyId id : script.liveBodies()) ids.push_back(id);
    std::vector<Real> state;
    for (const BodyId id : ids) {
        const Vec3 p = world.position(id);
        const Quat q = world.orientation(id);
        for (const Real v : {p.x, p.y, p.z, q.w, q.x, q.y, q.z}) {
            EXPECT_TRUE(std::isfinite(v));
            state.push_back(v);
        }
    }
    return state;
}

void expectSameBits(const bench::SceneSpec& scene) {
    const std::vector<Real> one = finalState(scene, 1);
    const std::vector<Real> two = finalState(scene, 2);
    ASSERT_EQ(one.size(), two.size()) << scene.name;
    EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(Real)), 0)
        << scene.name << ": the results differ between one and two threads";
}

TEST(ChurnThreads, RagdollsCreatedAndDestroyedGiveTheSameBitsOnOneAndTwoThreads) {
    // Two columns of one-ragdoll groups: created at steps 0 and 16, then
    // destroyed and re-created at 64, 80, 128 and 144.
    const bench::SceneSpec scene = bench::rain(2, 1, 150);
    ASSERT_EQ(scene.script.size(), 2u + 2u + 4u * 4u);
    expectSameBits(scene);
}

TEST(ChurnThreads, FastContinuousBodiesGiveTheSameBitsOnOneAndTwoThreads) {
    // 600 bodies at 250 m/s: more than the 256 movers that start a bulk rebuild.
    expectSameBits(bench::joltHighSpeed(600, 30));
}

TEST(ChurnThreads, SpheresDroppedOnManyStaticBodiesGiveTheSameBitsOnOneAndTwoThreads) {
    const bench::SceneSpec scene = bench::largeWorld(60, 150);  // 3,600 static boxes, 29 spheres
    expectSameBits(scene);
    // The spheres come to rest on the floor's top face (y = 0.25): centres at 0.75.
    bench::FulcrumWorld built = bench::buildFulcrumWorld(scene, 1);
    bench::FulcrumScript script(scene, built);
    for (int i = 0; i < scene.steps; ++i) {
        script.beforeStep(i);
        built.world->step(static_cast<Real>(scene.dt));
    }
    const std::vector<BodyId> spheres = script.liveBodies();
    ASSERT_EQ(spheres.size(), 29u);
    for (std::size_t k = 0; 5 * (k + 1) + 40 <= static_cast<std::size_t>(scene.steps); ++k) {  // dropped 40 steps ago or more
        EXPECT_NEAR(built.world->position(spheres[k]).y, 0.75, 0.01) << "sphere " << k;
    }
}

}  // namespace
