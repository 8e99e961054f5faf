// A pair driven deep into each other (it touched first at a resting depth)
// is solved with the stiff spring and a push limit that grows with the
// overlap (docs/solver.md, "Driven deep: a stiffer spring and a growing
// push"); pairs born inside each other keep the gentle, shared push-out
// (tests/solver/overlap_recovery_test.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

struct PushOut {
    Real afterOneStep = 0;    // m: the overlap after the first step
    Real afterTenSteps = 0;   // m: the overlap after ten (negative: a gap)
    Real speedAfterTen = 0;   // m/s: the pair's relative speed then
};

// Two 1 kg unit boxes side by side, no gravity: they touch for a few steps
// (the contact starts at a resting depth: driven), then one is moved `depth`
// into the other along x, as a hull struck within a step arrives at the next
// one.
PushOut pushOut(Real depth) {
    WorldDef def;
    def.gravity = {0, 0, 0};
    def.sleeping = false;
    World world(def);
    const BodyId a = addBox(world, {0, 0, 0});
    const BodyId b = addBox(world, {1, 0, 0});
    run(world, 3);
    world.setTransform(b, world.position(a) + Vec3{1 - depth, 0, 0}, Quat{});
    world.setTransform(a, world.position(a), Quat{});
    world.setLinearVelocity(a, {0, 0, 0});
    world.setLinearVelocity(b, {0, 0, 0});
    const auto overlap = [&] { return 1 - (world.position(b).x - world.position(a).x); };
    PushOut out;
    world.step(kDt);
    out.afterOneStep = overlap();
    run(world, 9);
    out.afterTenSteps = overlap();
    out.speedAfterTen = std::abs(world.linearVelocity(b).x - world.linearVelocity(a).x);
    return out;
}

}  // namespace

// A fixed push limit of 3 m/s (contactPushMaxVelocity) can take at most
// 3 m/s x 1/60 s = 5 cm out of a 10 cm overlap in one step, whatever the
// stiffness: 5 cm would be left. The growing limit lets the stiff spring
// (75 Hz at the default 5 sub-steps, damping ratio 1.5) work: measured
// 2.3 cm left; asked below 3.5 cm. The push-out must not turn into a bounce
// (the relax pass takes the push velocity back out): after ten steps the
// boxes touch, within 2 mm, at under 5 cm/s.
TEST(DrivenOverlap, DeepOverlapIsPushedOutFasterThanTheFixedLimit) {
    const PushOut deep = pushOut(Real(0.1));
    EXPECT_LT(deep.afterOneStep, Real(0.035));
    EXPECT_GT(deep.afterOneStep, Real(0));  // still a spring, not a jump
    EXPECT_LT(std::abs(deep.afterTenSteps), Real(0.002));
    EXPECT_LT(deep.speedAfterTen, Real(0.05));
}

// A shallow overlap (below the driven-deep depth of 2 cm) keeps the soft
// spring of the sixth of the sub-step rate: 1.5 cm is still pushed out at
// that spring's pace, a few millimetres in one step, and comes to rest as
// the deep one does.
TEST(DrivenOverlap, ShallowOverlapKeepsTheSoftSpring) {
    const PushOut shallow = pushOut(Real(0.015));
    EXPECT_GT(shallow.afterOneStep, Real(0.001));
    EXPECT_LT(shallow.afterOneStep, Real(0.015));
    EXPECT_LT(std::abs(shallow.afterTenSteps), Real(0.002));
    EXPECT_LT(shallow.speedAfterTen, Real(0.05));
}
