// The joint-tree solver on trees with every kind of node it has: bodies with
// at most one child joint (eliminated first, their joints coupled as 3x3
// blocks) and bodies where the tree branches (kept as 6x6 blocks), including
// a free tree's root.
#include <vector>

#include "joint_test_util.hpp"

namespace fulcrum::jointtest {
namespace {

struct SpinningStar {
    World world;
    std::vector<JointId> joints;
    SpinningStar() : world(worldDef(4, {0, 0, 0})) {
        BodyDef hubDef = boxBody(4, {0, 0, 0}, {Real(0.2), Real(0.2), Real(0.2)}, "hub");
        hubDef.filter.group = -1;  // no contacts: only the joints act
        const BodyId hub = world.createBody(hubDef);
        world.setLinearVelocity(hub, {Real(0.5), 0, Real(-0.3)});
        world.setAngularVelocity(hub, {Real(0.3), Real(2.0), Real(-0.4)});
        const Vec3 dirs[3] = {{1, 0, 0}, {Real(-0.5), Real(0.866), 0}, {Real(-0.5), Real(-0.866), 0}};
        for (int arm = 0; arm < 3; ++arm) {
            BodyId prev = hub;
            const Vec3 d = dirs[arm];
            for (int k = 0; k < 3; ++k) {
                BodyDef b;
                b.shape = Shape::capsule(Real(0.05), Real(0.2));
                b.mass = Real(0.5) + Real(0.25) * static_cast<Real>(k);
                b.position = d * (Real(0.2) + Real(0.25) + Real(0.5) * static_cast<Real>(k));
                b.orientation = Quat::fromTo({0, 1, 0}, d);
                b.filter.group = -1;
                const BodyId link = world.createBody(b);
                // Each link moves off on its own: the joints must pull them in.
                world.setLinearVelocity(link, Vec3{0, 0, 1} * Real(arm + 1) + d * Real(0.5 * k));
                world.setAngularVelocity(link, {Real(k), Real(-arm), Real(1)});
                const Vec3 anchor = d * (Real(0.2) + Real(0.5) * static_cast<Real>(k));
                joints.push_back(world.createJoint(jointDef(JointType::Ball, prev, link, anchor)));
                prev = link;
            }
        }
    }
    double worstError() const {
        double e = 0;
        for (const JointId j : joints) e = std::max(e, static_cast<double>(world.jointError(j)));
        return e;
    }
};

// A free star in zero gravity: a hub with three joints (kept, and the root:
// no world anchor) and three arms of three links, every body thrown off on
// its own. Joint impulses are internal, equal and opposite: the total linear
// momentum keeps its value to rounding. (Angular momentum only nearly: the
// solver turns each body's impulses with its inverse inertia from the step's
// start; measured within 1.5 %.) The joints stay closed below the projection
// slop (5 mm), so the velocity solve, not the position pass, holds them.
TEST(JointTree, FreeBranchedTreeConservesMomentumAndStaysClosed) {
    SpinningStar s;
    s.world.step(kDt);  // the first step absorbs the links' incompatible velocities
    const Vec3 p0 = s.world.linearMomentum();  // 12 kg m/s
    double worst = 0, worstP = 0;
    for (int i = 0; i < 180; ++i) {
        s.world.step(kDt);
        worst = std::max(worst, s.worstError());
        worstP = std::max(worstP, static_cast<double>(length(s.world.linearMomentum() - p0)));
    }
    EXPECT_LT(worstP, 1e-4 * length(p0));  // measured 1.2e-6
    EXPECT_LT(worst, 0.003);                // measured 1.6 mm
}

// A Y hung from the world: three light links, a hub where it branches (a
// body with three joints: a 6x6 block), and two arms of three light links,
// each ending in a 10 kg weight (100:1 against a link). Solved as one tree,
// the joints see the whole tree's inertia, and the soft rows' deflection under
// the load is g / omega^2 (a fraction of a millimetre) instead of (M/m) g /
// omega^2 per joint (centimetres; Gauss-Seidel, checked below). The top joint
// carries the whole weight.
struct HangingY {
    World world;
    std::vector<JointId> joints;
    std::vector<BodyId> weights;
    explicit HangingY(bool direct) : world(def(direct)) {
        BodyId prev = kWorldBody;
        Vec3 top{0, 0, 0};
        const auto link = [&](BodyId parent, Vec3 anchor, Real mass, Real length) {
            BodyDef b = sphereBody(mass, anchor - Vec3{0, length, 0}, Real(0.05));
            b.filter.group = -1;  // only the joints act
            const BodyId id = world.createBody(b);
            joints.push_back(world.createJoint(jointDef(JointType::Ball, parent, id, anchor)));
            return id;
        };
        for (int k = 0; k < 3; ++k) {
            prev = link(prev, top, Real(0.1), Real(0.25));
            top.y -= Real(0.25);
        }
        BodyDef hubDef = boxBody(Real(0.1), top - Vec3{0, Real(0.1), 0}, {Real(0.25), Real(0.1), Real(0.05)}, "hub");
        hubDef.filter.group = -1;
        const BodyId hub = world.createBody(hubDef);
        joints.push_back(world.createJoint(jointDef(JointType::Ball, prev, hub, top)));
        for (const Real x : {Real(-0.25), Real(0.25)}) {
            BodyId p = hub;
            Vec3 anchor{x, top.y - Real(0.2), 0};
            for (int k = 0; k < 3; ++k) {
                p = link(p, anchor, Real(0.1), Real(0.25));
                anchor.y -= Real(0.25);
            }
            weights.push_back(link(p, anchor, 10, Real(0.15)));
        }
    }
    static WorldDef def(bool direct) {
        WorldDef d = worldDef();
        d.jointDirectSolve = direct;
        return d;
    }
    double run(int steps) {
        double worst = 0;
        for (int i = 0; i < steps; ++i) {
            world.step(kDt);
            for (const JointId j : joints) worst = std::max(worst, static_cast<double>(world.jointError(j)));
        }
        return worst;
    }
};

TEST(JointTree, BranchedTreeCarriesAHeavyLoad) {
    HangingY y(true);
    const double restY = y.world.position(y.weights[0]).y;
    const double worst = y.run(180);
    EXPECT_LT(worst, 0.001);  // measured 0.07 mm (Gauss-Seidel: 6.4 cm)
    EXPECT_NEAR(y.world.position(y.weights[0]).y, restY, 0.001);
    EXPECT_NEAR(y.world.position(y.weights[1]).y, restY, 0.001);
    // 10 light bodies of 0.1 kg, the hub 0.1 kg, two 10 kg weights.
    EXPECT_NEAR(y.world.jointReactionForce(y.joints.front()).y / (21.1 * kG), 1, 0.01);

    HangingY gs(false);
    const double gsWorst = gs.run(180);
    EXPECT_GT(gsWorst, 0.01);
}

}  // namespace
}  // namespace fulcrum::jointtest
