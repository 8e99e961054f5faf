// World::lastStepProfile: the phases partition the step's time, and the sizes
// are those of the scene (a box on the floor is one manifold; a pendulum is one
// joint; a resting box falls asleep and then costs no awake body).
#include <gtest/gtest.h>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

double phaseSum(const StepProfile& p) {
    return p.collide + p.prepare + p.solve + p.store + p.continuous + p.particles + p.sleep + p.finish;
}

TEST(StepProfile, ZeroBeforeTheFirstStep) {
    World world;
    const StepProfile p = world.lastStepProfile();
    EXPECT_EQ(p.total, 0.0);
    EXPECT_EQ(p.awakeBodies, 0u);
}

// The phases are laps of one clock from the step's entry, so their sum is
// the total up to double rounding (1e-9 relative), and none is negative.
TEST(StepProfile, PhasesAddUpToTheTotalAndSizesMatchTheScene) {
    World world;
    addGround(world);
    const BodyId box = addBox(world, {0, Real(0.5), 0});
    run(world, 10);
    const StepProfile p = world.lastStepProfile();
    EXPECT_GT(p.total, 0.0);
    for (const double phase : {p.collide, p.prepare, p.solve, p.store, p.continuous, p.particles, p.sleep, p.finish}) {
        EXPECT_GE(phase, 0.0);
    }
    EXPECT_NEAR(phaseSum(p), p.total, 1e-9 * p.total);
    EXPECT_EQ(p.awakeBodies, 1u);
    EXPECT_EQ(p.contactConstraints, 1u);  // box on the floor: one face-face manifold
    EXPECT_EQ(p.jointConstraints, 0u);
    EXPECT_EQ(p.workers, 1u);  // one body is below WorldDef::parallelMinBodies: the calling thread

    // At rest it falls asleep: the step then moves no body and solves nothing.
    run(world, 120);
    ASSERT_FALSE(world.isAwake(box));
    const StepProfile asleep = world.lastStepProfile();
    EXPECT_EQ(asleep.awakeBodies, 0u);
    EXPECT_EQ(asleep.contactConstraints, 0u);
}

TEST(StepProfile, CountsAPendulumsJoint) {
    World world;
    BodyDef bob;
    bob.shape = Shape::sphere(Real(0.1));
    bob.position = {1, 0, 0};
    const BodyId b = world.createBody(bob);
    JointDef pivot;
    pivot.type = JointType::Ball;
    pivot.bodyB = b;
    pivot.anchor = {0, 0, 0};
    world.createJoint(pivot);
    world.step(Real(1) / 60);
    const StepProfile p = world.lastStepProfile();
    EXPECT_EQ(p.awakeBodies, 1u);
    EXPECT_EQ(p.jointConstraints, 1u);
    EXPECT_EQ(p.contactConstraints, 0u);
}

}  // namespace
