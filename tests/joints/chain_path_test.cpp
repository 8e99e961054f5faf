// The joint-tree solver's chain path (JointTreeSolver::solveChain: a tree
// whose every node is a joint below the next, solved in one fused sweep over
// packed links). Each test checks that the trees under test take that path
// (chainCount) and compares with an analytic result or with itself built
// the other way round, or on more threads.
#include <vector>

#include "joint_test_util.hpp"
#include "world/world_access.hpp"

namespace fulcrum::jointtest {
namespace {

const detail::JointTreeSolver& trees(const World& w) { return detail::implOf(w).jointSolver.trees(); }

// `links` capsules of mass 1 + 0.1 k, 1 m between anchors, hung from the
// world at `top` along `dir`. Joint k joins link k - 1 (the world for k = 0)
// and link k; `flipped(k)` says whether it names them the other way round
// (bodyA the lower link), so the chain's links meet their joints as either
// end: every sign the packed links keep (viaIsA, viaIsParentA, ownA/ownB).
struct Chain {
    std::vector<BodyId> bodies;
    std::vector<JointId> joints;
    std::vector<double> masses;
    Chain(World& world, int links, Vec3 top, Vec3 dir, const std::function<bool(int)>& flipped,
          const std::function<JointType(int)>& type = [](int) { return JointType::Ball; }) {
        BodyId prev = kWorldBody;
        for (int k = 0; k < links; ++k) {
            BodyDef b;
            b.shape = Shape::capsule(Real(0.1), Real(0.4));
            b.mass = Real(1) + Real(0.1) * static_cast<Real>(k);
            b.position = top + dir * (Real(0.5) + static_cast<Real>(k));
            b.orientation = Quat::fromTo({0, 1, 0}, dir);
            b.filter.group = -1;  // only the joints act
            const BodyId id = world.createBody(b);
            const Vec3 anchor = top + dir * static_cast<Real>(k);
            // A hinge's axis across the chain, so hanging it turns nothing.
            const Vec3 axis = std::fabs(dir.z) < Real(0.9) ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
            JointDef j = flipped(k) && !prev.isNull() && prev != kWorldBody ? jointDef(type(k), id, prev, anchor, axis)
                                                                            : jointDef(type(k), prev, id, anchor, axis);
            joints.push_back(world.createJoint(j));
            bodies.push_back(id);
            masses.push_back(static_cast<double>(b.mass));
            prev = id;
        }
    }
    double worstError(const World& world) const {
        double e = 0;
        for (const JointId j : joints) e = std::max(e, static_cast<double>(world.jointError(j)));
        return e;
    }
};

// A chain of 12 links of different masses hanging at rest, its joints named
// in every pattern of ends: joint k carries the weight of links k..11,
// g sum(m_k..m_11) (statics), to 0.1 %, and stays closed.
TEST(ChainPath, EveryJointCarriesTheWeightBelowIt) {
    const std::vector<std::function<bool(int)>> patterns = {
        [](int) { return false; }, [](int) { return true; }, [](int k) { return k % 2 == 1; },
        [](int k) { return k % 3 == 0; }};
    for (std::size_t p = 0; p < patterns.size(); ++p) {
        World world(worldDef(5));
        Chain c(world, 12, {0, 20, 0}, {0, -1, 0}, patterns[p]);
        for (int i = 0; i < 60; ++i) world.step(kDt);
        EXPECT_EQ(trees(world).treeCount(), 1u);
        EXPECT_EQ(trees(world).chainCount(), 1u) << "pattern " << p;
        double below = 0;
        for (int k = 11; k >= 0; --k) {
            below += c.masses[static_cast<std::size_t>(k)] * kG;
            const double force = length(world.jointReactionForce(c.joints[static_cast<std::size_t>(k)]));
            EXPECT_NEAR(force, below, below * 1e-3) << "pattern " << p << " joint " << k;
        }
        EXPECT_LT(c.worstError(world), 1e-4) << "pattern " << p;
    }
}

// The same with hinge, cone-twist and fixed joints in the chain (their point
// rows in the chain path, their angular rows Gauss-Seidel before it).
TEST(ChainPath, MixedJointTypesCarryTheWeightBelowThem) {
    const JointType types[4] = {JointType::Ball, JointType::Hinge, JointType::ConeTwist, JointType::Fixed};
    World world(worldDef(5));
    Chain c(world, 8, {0, 20, 0}, {0, -1, 0}, [](int k) { return k % 2 == 0; },
            [&](int k) { return types[k % 4]; });
    for (int i = 0; i < 60; ++i) world.step(kDt);
    EXPECT_EQ(trees(world).chainCount(), 1u);
    double below = 0;
    for (int k = 7; k >= 0; --k) {
        below += c.masses[static_cast<std::size_t>(k)] * kG;
        const double force = length(world.jointReactionForce(c.joints[static_cast<std::size_t>(k)]));
        EXPECT_NEAR(force, below, below * 1e-3) << "joint " << k;
    }
    EXPECT_LT(c.worstError(world), 1e-4);
}

// 20 links released horizontally, named the usual way (bodyA the upper link)
// and every joint the other way round: the same physics, so after 1 s of
// falling and whipping (the free end at ~20 m/s) the two chains are in the
// same place to within a millimetre (rounding differs, nothing else), and
// as closed.
TEST(ChainPath, ChainNamedEitherWayRoundMovesTheSame) {
    World usual(worldDef(5)), reversed(worldDef(5));
    Chain a(usual, 20, {0, 30, 0}, {1, 0, 0}, [](int) { return false; });
    Chain b(reversed, 20, {0, 30, 0}, {1, 0, 0}, [](int) { return true; });
    double worstA = 0, worstB = 0, apart = 0, fastest = 0;
    for (int i = 0; i < 60; ++i) {
        usual.step(kDt);
        reversed.step(kDt);
        worstA = std::max(worstA, a.worstError(usual));
        worstB = std::max(worstB, b.worstError(reversed));
    }
    for (std::size_t k = 0; k < a.bodies.size(); ++k) {
        apart = std::max(apart, static_cast<double>(length(usual.position(a.bodies[k]) - reversed.position(b.bodies[k]))));
        fastest = std::max(fastest, static_cast<double>(length(usual.linearVelocity(a.bodies[k]))));
    }
    EXPECT_EQ(trees(usual).chainCount(), 1u);
    EXPECT_EQ(trees(reversed).chainCount(), 1u);
    EXPECT_GT(fastest, 10.0);  // it did whip
    EXPECT_LT(apart, 1e-3);
    EXPECT_LT(worstA, 0.01);
    EXPECT_LT(worstB, 0.01);
    EXPECT_NEAR(worstA, worstB, 1e-3);
}

// Twelve whipping chains (trees solved in ranges across the task system):
// bit-identical on 1 and 3 threads.
TEST(ChainPath, SameBitsOnOneAndThreeThreads) {
    std::vector<Vec3> result[2];
    for (int run = 0; run < 2; ++run) {
        WorldDef d = worldDef(5);
        d.threads = run == 0 ? 1 : 3;
        d.parallelMinBodies = 0;
        World world(d);
        std::vector<Chain> chains;
        for (int c = 0; c < 12; ++c) {
            chains.emplace_back(world, 10, Vec3{0, 30, Real(3) * static_cast<Real>(c)}, Vec3{1, 0, 0},
                                [c](int k) { return (k + c) % 3 == 0; });
        }
        for (int i = 0; i < 40; ++i) world.step(kDt);
        EXPECT_EQ(trees(world).chainCount(), 12u);
        for (const Chain& c : chains) {
            for (const BodyId b : c.bodies) {
                result[run].push_back(world.position(b));
                result[run].push_back(world.linearVelocity(b));
            }
        }
    }
    ASSERT_EQ(result[0].size(), result[1].size());
    for (std::size_t i = 0; i < result[0].size(); ++i) {
        EXPECT_EQ(result[0][i].x, result[1][i].x) << i;
        EXPECT_EQ(result[0][i].y, result[1][i].y) << i;
        EXPECT_EQ(result[0][i].z, result[1][i].z) << i;
    }
}

}  // namespace
}  // namespace fulcrum::jointtest
