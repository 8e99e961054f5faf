// The joint-tree solver's factorization reuse (tree_solver.hpp, solve()): a
// factorization serves the passes until its anchors are maxFactorAge position
// updates old (age 2: 3 factorizations per 5-sub-step step instead of 5; the
// default, kOncePerStep: once per step), and a reused one is dropped when an
// anchor has turned more than JointTreeSolver::kGuardTurn since (the guard). Each test compares the reuse with every pass factored
// exactly (setMaxFactorAge(1)) and with an analytic result.
#include <vector>

#include "joint_test_util.hpp"
#include "world/world_access.hpp"

namespace fulcrum::jointtest {
namespace {

detail::JointTreeSolver& trees(World& w) { return detail::implOf(w).jointSolver.trees(); }

// `links` capsules of 1 kg, 1 m between anchors, hung from the world at the
// origin along `dir` (straight down: at rest; sideways: it falls and whips).
struct Chain {
    World world;
    std::vector<BodyId> bodies;
    std::vector<JointId> joints;
    Chain(int links, Vec3 dir, int maxFactorAge, Vec3 gravity = {0, Real(-9.81), 0}) : world(def(gravity)) {
        trees(world).setMaxFactorAge(maxFactorAge);
        BodyId prev = kWorldBody;
        for (int i = 0; i < links; ++i) {
            BodyDef b;
            b.shape = Shape::capsule(Real(0.1), Real(0.4));
            b.mass = 1;
            b.position = dir * (Real(0.5) + static_cast<Real>(i));
            b.orientation = Quat::fromTo({0, 1, 0}, dir);
            b.filter.group = -1;  // only the joints act
            const BodyId id = world.createBody(b);
            joints.push_back(world.createJoint(jointDef(JointType::Ball, prev, id, dir * static_cast<Real>(i))));
            bodies.push_back(id);
            prev = id;
        }
    }
    static WorldDef def(Vec3 gravity) {
        WorldDef d = worldDef(5, gravity);  // the world default, 5 sub-steps
        return d;
    }
    double worstError() const {
        double e = 0;
        for (const JointId j : joints) e = std::max(e, static_cast<double>(world.jointError(j)));
        return e;
    }
};

// A chain of 10 links hanging at rest: the top joint carries the weight of
// all of them, 10 m g (the reaction on its body B, upwards), with the
// factorization reused and with every pass factored. Nothing turns, so the
// guard never trips and the schedule is exact: 3 factorizations per step
// with reuse (sub-step 0's biased pass, the relax passes of sub-steps 1 and
// 3), 6 with every pass after a position update factored.
TEST(FactorReuse, HangingChainCarriesItsWeightWithThreeFactorizationsPerStep) {
    for (const int age : {2, 1}) {
        Chain c(10, {0, -1, 0}, age);
        const int steps = 60;
        for (int i = 0; i < steps; ++i) c.world.step(kDt);
        const Vec3 top = c.world.jointReactionForce(c.joints[0]);
        EXPECT_NEAR(top.y, 10 * kG, 10 * kG * 1e-3) << "age " << age;
        EXPECT_NEAR(length(top), 10 * kG, 10 * kG * 1e-3) << "age " << age;
        EXPECT_LT(c.worstError(), 1e-4) << "age " << age;
        EXPECT_EQ(trees(c.world).guardTrips(), 0u) << "age " << age;
        EXPECT_EQ(trees(c.world).factorizations(), static_cast<std::uint64_t>(steps * (age == 2 ? 3 : 6))) << "age " << age;
    }
}

// Steps two chains side by side: each one's worst joint error over the run,
// and how far apart their bodies got at worst.
struct SideBySide {
    double worstReused = 0, worstExact = 0, apart = 0;
};
SideBySide stepSideBySide(Chain& reused, Chain& exact, int steps) {
    SideBySide r;
    for (int i = 0; i < steps; ++i) {
        reused.world.step(kDt);
        exact.world.step(kDt);
        r.worstReused = std::max(r.worstReused, reused.worstError());
        r.worstExact = std::max(r.worstExact, exact.worstError());
        for (std::size_t k = 0; k < reused.bodies.size(); ++k) {
            r.apart = std::max(r.apart, static_cast<double>(length(reused.world.position(reused.bodies[k]) -
                                                                   exact.world.position(exact.bodies[k]))));
        }
    }
    return r;
}

// 20 links released horizontally: after 1 s of falling and whipping the
// chain with the factorization reused is where the exactly factored one is,
// to well under a millimetre, and its joints are as closed.
TEST(FactorReuse, WhippingChainAgreesWithExactFactorization) {
    Chain reused(20, {1, 0, 0}, 2), exact(20, {1, 0, 0}, 1);
    const auto [worstReused, worstExact, apart] = stepSideBySide(reused, exact, 60);
    // The free end fell ~10 m and swung: both chains are at the same place.
    const Vec3 end = reused.world.position(reused.bodies.back());
    EXPECT_LT(end.y, -4);
    EXPECT_LT(worstReused, 1e-3);  // measured 0.13 mm
    EXPECT_LT(worstExact, 1e-3);   // 0.12 mm
    EXPECT_LT(apart, 1e-3);  // measured 6.4e-5 m
}

// The schedule kOncePerStep (no limit by age, the default) factors once
// per step and leaves the rest to the guard. A chain hanging at rest never trips
// it: one factorization per step, the top joint carries 10 m g as with every
// pass factored. A whipping chain does trip it, and lands where the exactly
// factored one does, its joints as closed.
TEST(FactorReuse, OncePerStepFactorsOnceAStepAndTheGuardKeepsAWhippingChainExact) {
    {
        Chain c(10, {0, -1, 0}, detail::JointTreeSolver::kOncePerStep);
        const int steps = 60;
        for (int i = 0; i < steps; ++i) c.world.step(kDt);
        const Vec3 top = c.world.jointReactionForce(c.joints[0]);
        EXPECT_NEAR(top.y, 10 * kG, 10 * kG * 1e-3);
        EXPECT_LT(c.worstError(), 1e-4);
        EXPECT_EQ(trees(c.world).guardTrips(), 0u);
        EXPECT_EQ(trees(c.world).factorizations(), static_cast<std::uint64_t>(steps));
    }
    Chain reused(20, {1, 0, 0}, detail::JointTreeSolver::kOncePerStep), exact(20, {1, 0, 0}, 1);
    const auto [worstReused, worstExact, apart] = stepSideBySide(reused, exact, 60);
    EXPECT_GT(trees(reused.world).guardTrips(), 0u);
    EXPECT_LT(reused.world.position(reused.bodies.back()).y, -4);
    EXPECT_LT(worstReused, 1e-3);
    EXPECT_LT(worstExact, 1e-3);
    EXPECT_LT(apart, 1e-3);
}

// A 1 kg rod pinned at one end to the world, no gravity, spinning at 60
// rad/s about the pin: its anchor turns 0.2 rad per sub-step, far beyond the
// guard's kGuardTurn. With reuse allowed for a whole step (maxFactorAge 100),
// every relax pass that would reuse the factorization trips the guard (5 a
// step) and factors again, and the biased pass after it reuses that one with
// the same anchors: every pass is exact, so the rod moves as with every pass
// factored (setMaxFactorAge(1)), to rounding. Physics: no pass may add
// energy (a stale factorization that amplified would), and the pin holds
// the rod within the projection slop. (The spin itself decays in both, 60 ->
// 51 rad/s in these 3 steps: the soft step's linearised anchors at 0.2 rad
// per sub-step, not the factorization.)
TEST(FactorReuse, GuardRefactorsAFastSpinningRod) {
    Chain guarded(1, {1, 0, 0}, 100, {0, 0, 0}), exact(1, {1, 0, 0}, 1, {0, 0, 0});
    const double w0 = 60;
    for (Chain* c : {&guarded, &exact}) {
        c->world.setAngularVelocity(c->bodies[0], {0, 0, static_cast<Real>(w0)});
        c->world.setLinearVelocity(c->bodies[0], {0, static_cast<Real>(w0 * 0.5), 0});
    }
    double energy = guarded.world.energy().total, worst = 0;
    const int steps = 3;
    for (int i = 0; i < steps; ++i) {
        guarded.world.step(kDt);
        exact.world.step(kDt);
        const double e = guarded.world.energy().total;
        EXPECT_LE(e, energy * (1 + 1e-6)) << "step " << i;
        energy = e;
        worst = std::max(worst, guarded.worstError());
        const double spin = length(guarded.world.angularVelocity(guarded.bodies[0]));
        const double spinExact = length(exact.world.angularVelocity(exact.bodies[0]));
        EXPECT_NEAR(spin, spinExact, 1e-5 * w0) << "step " << i;
        EXPECT_GT(spin, 0.1 / (static_cast<double>(kDt) / 5)) << "step " << i;  // still turning beyond the guard
    }
    EXPECT_EQ(trees(guarded.world).guardTrips(), static_cast<std::uint64_t>(5 * steps));
    EXPECT_LT(worst, 0.0051);
}

// The warm start folded into a tree's exact biased pass (markWarmStartFree,
// JointSolver::warmStart) gives what applying it first gives: a 20-link chain
// released horizontally, once as it is (the fold applies: 3 of 5 sub-steps)
// and once with a slack rope (a distance joint, 0-100 m) from the world to
// its third link, which never pulls but has Gauss-Seidel rows on that link,
// so the tree is not warm-start free and every sub-step applies the warm
// start first. Both follow the same path to float rounding and carry the
// same load: the top joint's reaction agrees too.
TEST(FactorReuse, FoldedWarmStartMatchesTheAppliedOne) {
    Chain folded(20, {1, 0, 0}, 2), applied(20, {1, 0, 0}, 2);
    JointDef rope = jointDef(JointType::Distance, kWorldBody, applied.bodies[2], {0, 0, 0});
    rope.anchorB = applied.world.position(applied.bodies[2]);
    rope.minLength = 0;
    rope.maxLength = 100;
    const JointId ropeId = applied.world.createJoint(rope);
    double apart = 0, force = 0;
    for (int i = 0; i < 60; ++i) {
        folded.world.step(kDt);
        applied.world.step(kDt);
        for (std::size_t k = 0; k < folded.bodies.size(); ++k) {
            apart = std::max(apart, static_cast<double>(length(folded.world.position(folded.bodies[k]) -
                                                               applied.world.position(applied.bodies[k]))));
        }
        force = std::max(force, static_cast<double>(length(folded.world.jointReactionForce(folded.joints[0]) -
                                                           applied.world.jointReactionForce(applied.joints[0]))));
        ASSERT_EQ(length(applied.world.jointReactionForce(ropeId)), 0) << "the rope must stay slack";
    }
    EXPECT_LT(apart, 2e-5);  // measured 2.0e-6 m
    EXPECT_LT(force, 0.03);  // N, against hundreds; measured 0.0033 N
    EXPECT_LT(folded.worstError(), 1e-3);
}

}  // namespace
}  // namespace fulcrum::jointtest
