// Ropes, soft distance joints, chains and mass ratios.
#include <algorithm>
#include <vector>

#include "joints/joint_test_util.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {
// Chains and mass ratios are solved exactly by the joint-tree solver
// (src/solver/joints/tree_solver.hpp). Measured worst errors at 4 sub-steps:
// 20-link chain 0.51 cm (was 1.00 cm with Gauss-Seidel point rows); 100:1 mass
// ratio 0.01 mm (was 2.8 cm); 100 links released horizontal 0.86 cm at the
// world's default 5 sub-steps (1.08 cm at 4, 0.62 cm at 8).

JointDef rope(BodyId a, BodyId b, Vec3 anchorA, Vec3 anchorB, Real maxLength) {
    JointDef j = jointDef(JointType::Distance, a, b, anchorA);
    j.anchorB = anchorB;
    j.minLength = 0;
    j.maxLength = maxLength;
    return j;
}

// `links` capsules (radius 0.05, half-height 0.2, 0.5 m between anchors, mass
// `linkMass`) hanging from the world at the origin, straight along +x (or down
// -y), ball-jointed; an optional end weight (a sphere) on the last link.
struct Chain {
    World world;
    std::vector<BodyId> bodies;
    std::vector<JointId> joints;
    Chain(int links, Real linkMass, bool horizontal, Real endMass = 0, int substeps = 4, bool direct = true)
        : world([&] {
              WorldDef d = worldDef(substeps);
              d.jointDirectSolve = direct;
              return d;
          }()) {
        BodyId prev = kWorldBody;
        const Vec3 dir = horizontal ? Vec3{1, 0, 0} : Vec3{0, -1, 0};
        const Quat q = Quat::fromAxisAngle({0, 0, 1}, horizontal ? Real(kPi / 2) : 0);
        for (int i = 0; i < links; ++i) {
            BodyDef d;
            d.shape = Shape::capsule(Real(0.05), Real(0.2));
            d.mass = linkMass;
            d.position = dir * (Real(0.5) * static_cast<Real>(i) + Real(0.25));
            d.orientation = q;
            const BodyId id = world.createBody(d);
            joints.push_back(world.createJoint(jointDef(JointType::Ball, prev, id, dir * (Real(0.5) * static_cast<Real>(i)))));
            bodies.push_back(id);
            prev = id;
        }
        if (endMass > 0) {
            const Vec3 p = dir * (Real(0.5) * static_cast<Real>(links) + Real(0.2));
            const BodyId w = world.createBody(sphereBody(endMass, p, Real(0.2)));
            joints.push_back(world.createJoint(jointDef(JointType::Ball, prev, w, dir * (Real(0.5) * static_cast<Real>(links)))));
            bodies.push_back(w);
        }
    }
    double worstError() const {
        double e = 0;
        for (JointId j : joints) e = std::max(e, double(world.jointError(j)));
        return e;
    }
};

}  // namespace

// A ball on a 2 m rope released from the horizontal swings through the bottom
// at sqrt(2 g L) = 6.3 m/s: the rope never stretches more than 5 mm (the
// position projection's slop).
TEST(Rope, NeverExceedsItsLength) {
    World world(worldDef());
    const BodyId ball = world.createBody(sphereBody(1, {2, 0, 0}));
    const JointId r = world.createJoint(rope(kWorldBody, ball, {0, 0, 0}, {2, 0, 0}, 2));
    double longest = 0;
    for (int i = 0; i < 300; ++i) {
        world.step(kDt);
        longest = std::max(longest, double(world.jointPosition(r)));
    }
    EXPECT_LT(longest, 2.005);
    EXPECT_GT(longest, 1.99);  // it was taut at the bottom
}

// A ball 1.9 m below the anchor of a 2 m rope, thrown up at 4 m/s: the slack
// rope does nothing. The ball moves exactly as a free twin thrown alongside
// (1e-5 m), and that twin follows y0 + v t - g t^2 / 2 to the integrator's
// known first-order error (g h t / 2 for sub-step h: 1.6 cm at 0.8 s; + 1 mm).
TEST(Rope, GoesSlack) {
    World world(worldDef());
    BodyDef d = sphereBody(1, {0, Real(-1.9), 0});
    d.linearVelocity = {0, 4, 0};
    const BodyId ball = world.createBody(d);
    d.position.z = 5;
    const BodyId twin = world.createBody(d);
    const JointId r = world.createJoint(rope(kWorldBody, ball, {0, 0, 0}, {0, Real(-1.9), 0}, 2));
    for (int i = 1; i <= 48; ++i) {  // 0.8 s: rises 0.8 m and comes back to -1.8 m
        world.step(kDt);
        const double t = i * double(kDt);
        EXPECT_NEAR(world.position(ball).y, world.position(twin).y, 1e-5) << "t = " << t;
        EXPECT_NEAR(world.position(ball).y, -1.9 + 4 * t - 0.5 * kG * t * t, kG * (kDt / 4) * t / 2 + 1e-3) << "t = " << t;
    }
    EXPECT_LT(world.jointPosition(r), 2);
    EXPECT_NEAR(length(world.jointReactionForce(r)), 0, 1e-6);
}

// A soft distance joint (stiffness k, rest length at creation) with a mass in
// zero gravity, pulled 0.2 m out: period 2 pi sqrt(m / k) within 1 %.
TEST(DistanceSpring, Period) {
    World world(worldDef(4, {0, 0, 0}));
    const BodyId ball = world.createBody(sphereBody(Real(0.5), {Real(1.2), 0, 0}));
    JointDef j = jointDef(JointType::Distance, kWorldBody, ball, {0, 0, 0});
    j.anchorB = {Real(1.2), 0, 0};
    j.stiffness = 20;
    const JointId spring = world.createJoint(j);
    // The rest length is the creation distance: move the ball 0.2 m further out.
    world.setTransform(ball, {Real(1.4), 0, 0}, {});
    const double T = measurePeriod(world, [&] { return double(world.jointPosition(spring)) - 1.2; }, 5, 2000);
    EXPECT_NEAR(T / (2 * kPi * std::sqrt(0.5 / 20.0)), 1, 0.01) << T;
}

// ... and its max length is still enforced: a 1 kg ball hanging on a weak
// spring (k = 10 N/m would stretch 0.98 m) stops at maxLength (5 mm).
TEST(DistanceSpring, LimitsStillHold) {
    World world(worldDef());
    const BodyId ball = world.createBody(sphereBody(1, {0, -1, 0}));
    JointDef j = jointDef(JointType::Distance, kWorldBody, ball, {0, 0, 0});
    j.anchorB = {0, -1, 0};
    j.stiffness = 10;
    j.damping = 2;
    j.maxLength = Real(1.5);
    const JointId spring = world.createJoint(j);
    double longest = 0;
    for (int i = 0; i < 300; ++i) {
        world.step(kDt);
        longest = std::max(longest, double(world.jointPosition(spring)));
    }
    EXPECT_LT(longest, 1.505);
    EXPECT_NEAR(world.jointPosition(spring), 1.5, 0.005);
}

// A 20-link chain released horizontal whips down (free end > 10 m/s): every
// joint stays within 1 cm for 3 s.
TEST(Chain, DoesNotStretch) {
    Chain c(20, 1, true);
    double worst = 0, fastest = 0;
    for (int i = 0; i < 180; ++i) {
        c.world.step(kDt);
        worst = std::max(worst, c.worstError());
        fastest = std::max(fastest, double(length(c.world.linearVelocity(c.bodies.back()))));
    }
    EXPECT_GT(fastest, 10);
    EXPECT_LT(worst, 0.01);
}

// 100 links (50 m) released horizontal at the world's default 5 sub-steps: the
// free end whips past 50 m/s, and no joint opens by 1 cm over 5 s.
TEST(Chain, HundredLinksDoNotStretch) {
    Chain c(100, 1, true, 0, WorldDef{}.substeps);
    double worst = 0, fastest = 0;
    for (int i = 0; i < 300; ++i) {
        c.world.step(kDt);
        worst = std::max(worst, c.worstError());
        fastest = std::max(fastest, double(length(c.world.linearVelocity(c.bodies.back()))));
    }
    EXPECT_GT(fastest, 50);
    EXPECT_LT(worst, 0.01);
}

// Mass ratio 100:1: a 10 kg weight on 10 links of 0.1 kg hanging down. Every
// joint stays within 1 mm (measured 0.01 mm), the weight within 1 mm of its
// rest height, and the top joint carries the whole weight: (10 + 1) kg x g
// within 1 %. With Gauss-Seidel point rows (jointDirectSolve off) the same
// chain stretches by centimetres (soft rows see a light link's effective mass).
TEST(Chain, MassRatioHolds) {
    Chain c(10, Real(0.1), false, 10);
    const double restY = c.world.position(c.bodies.back()).y;
    double worst = 0;
    for (int i = 0; i < 180; ++i) {
        c.world.step(kDt);
        worst = std::max(worst, c.worstError());
    }
    EXPECT_LT(worst, 0.001);
    EXPECT_NEAR(c.world.position(c.bodies.back()).y, restY, 0.001);
    EXPECT_NEAR(c.world.jointReactionForce(c.joints.front()).y / (11 * kG), 1, 0.01);

    Chain gs(10, Real(0.1), false, 10, 4, false);
    double gsWorst = 0;
    for (int i = 0; i < 180; ++i) {
        gs.world.step(kDt);
        gsWorst = std::max(gsWorst, gs.worstError());
    }
    EXPECT_GT(gsWorst, 0.01);
}

// A closed loop (a square of four balls, ball-jointed round the ring, the top
// two also hung from the world) is not a tree: it stays on Gauss-Seidel rows
// and still holds, every joint within 3 cm while it swings after a 3 m/s kick
// (measured 2.2 cm: Gauss-Seidel's convergence on the loop).
TEST(Chain, LoopsAreSolvedToo) {
    World world(worldDef());
    std::vector<BodyId> b;
    for (const Vec3 p : {Vec3{0, -1, 0}, Vec3{1, -1, 0}, Vec3{1, -2, 0}, Vec3{0, -2, 0}}) b.push_back(world.createBody(sphereBody(1, p)));
    std::vector<JointId> joints;
    joints.push_back(world.createJoint(jointDef(JointType::Ball, kWorldBody, b[0], {0, 0, 0})));
    joints.push_back(world.createJoint(jointDef(JointType::Ball, kWorldBody, b[1], {1, 0, 0})));
    for (int i = 0; i < 4; ++i) {
        const BodyId p = b[static_cast<std::size_t>(i)], q = b[static_cast<std::size_t>((i + 1) % 4)];
        joints.push_back(world.createJoint(jointDef(JointType::Ball, p, q, (world.position(p) + world.position(q)) * Real(0.5))));
    }
    world.setLinearVelocity(b[2], {0, 0, 3});
    double worst = 0;
    for (int i = 0; i < 180; ++i) {
        world.step(kDt);
        for (JointId j : joints) worst = std::max(worst, double(world.jointError(j)));
    }
    EXPECT_LT(worst, 0.03);
    EXPECT_GT(length(world.linearVelocity(b[2])) + length(world.position(b[2]) - Vec3{1, -2, 0}), 0.01);  // it moved
}
