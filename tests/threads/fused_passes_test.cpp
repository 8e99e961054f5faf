// The step's fused per-body passes (step.cpp: velocity integration + gather,
// scatter + position integration + rotation deltas + gather, scatter + next
// sub-step's forces and velocities + gather) run only without joints; with a
// joint anywhere in the world the step takes the stage-by-stage passes. Both
// must give the same bits to bodies the joint does not touch: the same pile
// is stepped next to a far-away pendulum on a ball joint (stage by stage) and
// next to the same body with no joint (fused), and every pile body's state is
// compared bit for bit after every step. Physics check: the pile stays on the
// ground (no body below -5 cm, ten times the resting overlap). Mutation
// check: leaving the relax scatter out of the last fused pass fails at step 1.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "fulcrum/world.hpp"
#include "ground.hpp"

using namespace fulcrum;

namespace {

struct PileWorld {
    World world;
    std::vector<BodyId> pile;
};

PileWorld makePile(bool pendulumOnJoint) {
    WorldDef def;
    def.threads = 1;
    PileWorld p{World(def), {}};
    test::addGroundSlab(p.world);
    for (int y = 0; y < 6; ++y) {
        for (int x = 0; x < 6; ++x) {
            for (int z = 0; z < 6; ++z) {
                BodyDef d;
                d.shape = Shape::box({Real(0.25), Real(0.25), Real(0.25)});
                d.mass = 1;
                // Dropped tilted and spinning, rows offset: they land on each other and tumble.
                d.position = {Real(0.55) * static_cast<Real>(x) + Real(0.2) * static_cast<Real>(y % 2),
                              Real(0.5) + Real(0.8) * static_cast<Real>(y), Real(0.55) * static_cast<Real>(z)};
                d.orientation = normalize(Quat{1, Real(0.1) * static_cast<Real>(x % 3), 0, Real(0.1) * static_cast<Real>(z % 2)});
                d.angularVelocity = {Real(0.5), Real(0.3) * static_cast<Real>((x + z) % 3), 0};
                p.pile.push_back(p.world.createBody(d));
            }
        }
    }
    BodyDef bob;
    bob.shape = Shape::sphere(Real(0.2));
    bob.mass = 1;
    bob.position = {100, 10, 0};
    bob.linearVelocity = {1, 0, 0};
    const BodyId bobId = p.world.createBody(bob);
    if (pendulumOnJoint) {
        JointDef j;
        j.type = JointType::Ball;
        j.bodyA = kWorldBody;
        j.bodyB = bobId;
        j.anchor = {100, 11, 0};
        p.world.createJoint(j);
    }
    return p;
}

bool sameBits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(const Quat& a, const Quat& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST(FusedPasses, SameBitsAsTheStageByStagePasses) {
    PileWorld fused = makePile(false);
    PileWorld staged = makePile(true);
    int moving = 0;
    for (int step = 1; step <= 150; ++step) {
        fused.world.step(Real(1) / 60);
        staged.world.step(Real(1) / 60);
        for (std::size_t k = 0; k < fused.pile.size(); ++k) {
            const BodyId a = fused.pile[k], b = staged.pile[k];
            ASSERT_TRUE(sameBits(fused.world.position(a), staged.world.position(b))) << "body " << k << ", step " << step;
            ASSERT_TRUE(sameBits(fused.world.orientation(a), staged.world.orientation(b))) << "body " << k << ", step " << step;
            ASSERT_TRUE(sameBits(fused.world.linearVelocity(a), staged.world.linearVelocity(b))) << "body " << k << ", step " << step;
            ASSERT_TRUE(sameBits(fused.world.angularVelocity(a), staged.world.angularVelocity(b))) << "body " << k << ", step " << step;
            ASSERT_GT(fused.world.position(a).y, Real(-0.05)) << "body " << k << " sank through the ground, step " << step;
            if (step == 40 && lengthSquared(fused.world.linearVelocity(a)) > Real(1e-4)) ++moving;
        }
    }
    // The comparison means something only if the pile was really moving (contacts, solver, friction).
    EXPECT_GT(moving, 20);
}
