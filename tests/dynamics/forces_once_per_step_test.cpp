// The sub-steps after the first keep the step's forces when nothing makes
// them vary within the step (no drag, ForceCallback or spring: step.cpp,
// WorldImpl::buildSubSteps). A body's force is then gravity plus the user's
// forces, both fixed for the step, so evaluating it again at every sub-step
// gave the same values: the results must be the bits of that path
// (detail::setForcesOncePerStepEnabled(false)), at one thread and three, and
// the path must follow the world as what it depends on changes between
// steps (a body added, woken, moved or pushed by the user, drag set and
// cleared, a callback and a spring added and removed).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/world.hpp"
#include "threads/staged_parallel.hpp"

using namespace fulcrum;

namespace {

std::vector<std::uint64_t> scriptedHashes(int threads, bool forcesOnce) {
    detail::setForcesOncePerStepEnabled(forcesOnce);
    WorldDef def;
    def.threads = threads;
    def.parallelMinBodies = 0;  // the parallel stages even for a few bodies
    World world(def);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({40, 1, 40});
    ground.position = {0, -1, 0};
    world.createBody(ground);
    std::vector<BodyId> boxes;
    for (int i = 0; i < 12; ++i) {
        BodyDef d;
        d.shape = Shape::box({Real(0.5), Real(0.4), Real(0.3)});
        d.mass = 1 + Real(0.25) * static_cast<Real>(i % 3);
        // Half rest on the ground, half fall from a little height, turned.
        d.position = {Real(2) * static_cast<Real>(i) - 11, i % 2 == 0 ? Real(0.4) : Real(1.5), 0};
        const Real angle = Real(0.2) * static_cast<Real>(i % 4);
        d.orientation = normalize(Quat{std::cos(angle / 2), std::sin(angle / 2), 0, 0});
        boxes.push_back(world.createBody(d));
    }
    SpringId spring;
    std::vector<std::uint64_t> hashes;
    for (int s = 0; s < 160; ++s) {
        switch (s) {
            case 20: {  // a body added
                BodyDef d;
                d.shape = Shape::sphere(Real(0.3));
                d.position = {0, 3, 2};
                boxes.push_back(world.createBody(d));
                break;
            }
            case 30:  // the user's forces for one step, a user move, a velocity
                world.applyForceAtCenter(boxes[2], {3, 20, 0});
                world.applyTorque(boxes[4], {0, 1, 0});
                world.setTransform(boxes[6], {1, 2, 3}, Quat{});
                world.setLinearVelocity(boxes[8], {0, 0, 2});
                break;
            case 40: world.setDrag(boxes[3], Real(0.8), Real(0.3)); break;  // a velocity-dependent force
            case 60: world.setDrag(boxes[3], 0, 0); break;
            case 70:  // a callback (velocity- and time-dependent)
                world.setForceCallback(boxes[5], [](const BodyKinematics& k) {
                    return Wrench{Vec3{0, 5, 0} - k.linearVelocity * Real(2), {}};
                });
                break;
            case 90: world.setForceCallback(boxes[5], {}); break;
            case 100: {
                SpringDef sd;
                sd.bodyB = boxes[7];
                sd.anchorA = world.position(boxes[7]) + Vec3{0, 2, 0};
                sd.anchorB = world.position(boxes[7]);
                sd.restLength = 1;
                sd.stiffness = 30;
                sd.damping = 1;
                spring = world.createSpring(sd);
                break;
            }
            case 120: world.destroySpring(spring); break;
            case 130: world.setGravityScale(boxes[9], Real(0.5)); break;
            default: break;
        }
        // A force held over many steps (the user's, applied before each step).
        if (s >= 140) world.applyForceAtCenter(boxes[10], {0, 4, 1});
        world.step(Real(1) / 60);
        hashes.push_back(test::stateHash(world));
    }
    detail::setForcesOncePerStepEnabled(true);
    return hashes;
}

}  // namespace

TEST(ForcesOncePerStep, SameBitsAsEvaluatingEverySubStep) {
    for (const int threads : {1, 3}) {
        const std::vector<std::uint64_t> kept = scriptedHashes(threads, true);
        const std::vector<std::uint64_t> again = scriptedHashes(threads, false);
        ASSERT_EQ(kept.size(), again.size());
        for (std::size_t s = 0; s < kept.size(); ++s) {
            ASSERT_EQ(kept[s], again[s]) << "threads " << threads << ", step " << s;
        }
        // Same bits whatever the thread count, too.
        if (threads == 3) {
            EXPECT_EQ(kept, scriptedHashes(1, true));
        }
    }
}

// Free fall under gravity alone, kept forces: after n steps of the 5 sub-steps,
// v = g t exactly up to float rounding (each sub-step adds g h), and the
// position is the semi-implicit Euler sum y0 + g h^2 (1 + 2 + ... + 5n).
TEST(ForcesOncePerStep, FreeFallMatchesTheSubStepSum) {
    WorldDef def;
    def.gravity = {0, Real(-9.81), 0};
    World world(def);
    BodyDef d;
    d.shape = Shape::sphere(Real(0.5));
    d.position = {0, 100, 0};
    const BodyId ball = world.createBody(d);
    const int steps = 60;
    const Real dt = Real(1) / 60;
    for (int s = 0; s < steps; ++s) world.step(dt);
    const double h = 1.0 / 60.0 / def.substeps;
    const double n = static_cast<double>(steps * def.substeps);
    const double v = -9.81 * h * n;
    const double y = 100.0 - 9.81 * h * h * n * (n + 1) / 2;
    EXPECT_NEAR(world.linearVelocity(ball).y, v, 1e-4);
    EXPECT_NEAR(world.position(ball).y, y, 1e-3);
}
