// The joint solver keeps its colouring and its joint trees from one step to
// the next while the joints and their bodies' sleeping are unchanged, and each
// joint's frame between passes while its bodies' deltas are (joint_solver.cpp:
// sameStructureAsLastStep, refreshFrames). A stale cache after a change would
// solve the wrong trees (joints the tree solver believes it has, or misses).
//
// Each test changes the joint set or the sleeping state of a world that has
// been stepping (its caches warm), then copies the world through a snapshot
// (a fresh World: fresh solver, no cache) and steps both on the same input:
// every following step must be bit-identical (stateHash: positions,
// orientations, velocities, awake flags). The original must also still hold
// its joints together (worst error near the 5 mm projection slop), so the
// comparison is not between two equally broken worlds.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "joints/joint_test_util.hpp"

namespace fulcrum::jointtest {
namespace {

struct ChainWorld {
    World world;
    std::vector<BodyId> links;
    std::vector<JointId> joints;
    explicit ChainWorld(const WorldDef& d) : world(d) {}
};

// A chain of `n` capsules hanging from the world at `origin`, released
// horizontal; joint types cycle ball, hinge, cone-twist so the trees hold
// every point-block kind.
void addChain(ChainWorld& c, Vec3 origin, int n) {
    BodyId prev = kWorldBody;
    for (int i = 0; i < n; ++i) {
        BodyDef b;
        b.shape = Shape::capsule(Real(0.05), Real(0.15));
        b.mass = Real(1 + i % 3);
        b.position = origin + Vec3{Real(0.25) + Real(0.5) * static_cast<Real>(i), 0, 0};
        b.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));
        const BodyId id = c.world.createBody(b);
        const JointType type = i % 3 == 0 ? JointType::Ball : (i % 3 == 1 ? JointType::Hinge : JointType::ConeTwist);
        JointDef j = jointDef(type, prev, id, origin + Vec3{Real(0.5) * static_cast<Real>(i), 0, 0}, {0, 0, 1});
        j.swingLimit = Real(1.2);
        j.twistLower = Real(-0.5);
        j.twistUpper = Real(0.5);
        c.links.push_back(id);
        c.joints.push_back(c.world.createJoint(j));
        prev = id;
    }
}

Real worstJointError(const World& w, const std::vector<JointId>& joints) {
    Real worst = 0;
    for (const JointId id : joints) {
        if (w.isJointEnabled(id)) worst = std::max(worst, w.jointError(id));
    }
    return worst;
}

// Steps the changed world and its fresh copy `steps` times; bit-identical
// every step. Returns the original's worst joint error over the steps.
Real expectSameAsFreshWorld(ChainWorld& c, int steps, const char* change) {
    World fresh = loadSnapshotFromMemory(saveSnapshotToMemory(c.world));
    EXPECT_EQ(test::stateHash(c.world), test::stateHash(fresh)) << change << ": the copy must start equal";
    Real worst = 0;
    for (int i = 0; i < steps; ++i) {
        c.world.step(kDt);
        fresh.step(kDt);
        EXPECT_EQ(test::stateHash(c.world), test::stateHash(fresh)) << change << ": diverged at step " << i + 1;
        if (test::stateHash(c.world) != test::stateHash(fresh)) break;
        worst = std::max(worst, worstJointError(c.world, c.joints));
    }
    return worst;
}

// Trees hold their joints within the 5 mm projection slop (docs/joints.md:
// 0.5 cm worst on the benchmark chain); 1 cm leaves room for the released
// chain's whip. A Gauss-Seidel loop opens by a few cm (docs: 2.2 cm).
constexpr Real kTreeError = Real(0.01), kLoopError = Real(0.04);

TEST(JointStructureCache, DestroyAndCreateJointsMatchAFreshWorld) {
    ChainWorld c(worldDef(5));
    addChain(c, {0, 10, 0}, 12);
    for (int i = 0; i < 30; ++i) c.world.step(kDt);
    // Cut the chain in the middle and, in the same step, tie its free end to
    // the world: as many joints as before, two trees instead of one.
    c.world.destroyJoint(c.joints[6]);
    c.joints.erase(c.joints.begin() + 6);
    const Vec3 end = c.world.position(c.links.back());
    c.joints.push_back(c.world.createJoint(jointDef(JointType::Ball, kWorldBody, c.links.back(), end)));
    EXPECT_LT(expectSameAsFreshWorld(c, 20, "joint moved"), kTreeError);
    // Cut again: one joint fewer, a free-falling tree with no world anchor.
    c.world.destroyJoint(c.joints[2]);
    c.joints.erase(c.joints.begin() + 2);
    EXPECT_LT(expectSameAsFreshWorld(c, 20, "joint destroyed"), kTreeError);
    // A loop: the last link tied to the first (no longer a tree: Gauss-Seidel).
    const Vec3 mid = (c.world.position(c.links.front()) + c.world.position(c.links.back())) * Real(0.5);
    c.joints.push_back(c.world.createJoint(jointDef(JointType::Ball, c.links.front(), c.links.back(), mid)));
    EXPECT_LT(expectSameAsFreshWorld(c, 20, "loop closed"), kLoopError);
}

TEST(JointStructureCache, DisableEnableAndParametersMatchAFreshWorld) {
    ChainWorld c(worldDef(5));
    addChain(c, {0, 10, 0}, 9);
    for (int i = 0; i < 30; ++i) c.world.step(kDt);
    c.world.setJointEnabled(c.joints[4], false);
    EXPECT_LT(expectSameAsFreshWorld(c, 15, "joint disabled"), kTreeError);
    // Re-enabled, the joint starts open (the halves fell apart meanwhile) and
    // is pulled shut: measured at the end, not over the run.
    const Real opened = c.world.jointError(c.joints[4]);
    EXPECT_GT(opened, Real(0.05)) << "the disabled joint must have opened";
    // Re-enable it and disable another in the same step: as many joints as
    // before. (Only for a few steps: re-enabled after 25 steps, 8.5 m open,
    // the chain blew up, before the caches too.)
    c.world.setJointEnabled(c.joints[4], true);
    c.world.setJointEnabled(c.joints[7], false);
    expectSameAsFreshWorld(c, 5, "one joint enabled, another disabled");
    c.world.setJointEnabled(c.joints[7], true);
    expectSameAsFreshWorld(c, 30, "all enabled");
    EXPECT_LT(worstJointError(c.world, c.joints), kTreeError) << "the re-enabled joints closed again";
    // Joint parameters (not the structure; the rows are rebuilt every step).
    c.world.setJointLimits(c.joints[1], true, Real(-0.2), Real(0.2));
    c.world.setJointMotor(c.joints[4], JointMotor{true, Real(2), Real(5)});
    EXPECT_LT(expectSameAsFreshWorld(c, 15, "limits and motor changed"), kTreeError);
}

TEST(JointStructureCache, BodiesCreatedAndDestroyedMatchAFreshWorld) {
    ChainWorld c(worldDef(5));
    // A loose body created first: destroying it moves the chain's bodies to
    // other dense and solver indices, with the same joints.
    const BodyId loose = c.world.createBody(sphereBody(1, {-20, 5, 0}));
    addChain(c, {0, 10, 0}, 8);
    for (int i = 0; i < 30; ++i) c.world.step(kDt);
    c.world.destroyBody(loose);
    EXPECT_LT(expectSameAsFreshWorld(c, 20, "bodies renumbered"), kTreeError);
    // A heavy load hung on the chain's end: a new body and joint.
    BodyDef load = sphereBody(20, c.world.position(c.links.back()) + Vec3{0, Real(-0.3), 0}, Real(0.1));
    const BodyId heavy = c.world.createBody(load);
    c.joints.push_back(c.world.createJoint(jointDef(JointType::Ball, c.links.back(), heavy, c.world.position(heavy))));
    EXPECT_LT(expectSameAsFreshWorld(c, 20, "load added"), kTreeError);
    c.world.destroyBody(c.links[2]);  // takes its two joints with it
    std::erase_if(c.joints, [&](JointId id) { return !c.world.isValid(id); });
    EXPECT_LT(expectSameAsFreshWorld(c, 20, "link destroyed"), kTreeError);
}

TEST(JointStructureCache, SleepAndWakeMatchAFreshWorld) {
    WorldDef d = worldDef(5);
    d.sleeping = true;
    ChainWorld c(d);
    // Two chains hanging straight down, at rest: both fall asleep.
    for (const Real x : {Real(0), Real(5)}) {
        BodyId prev = kWorldBody;
        for (int i = 0; i < 6; ++i) {
            const Vec3 p{x, Real(10) - Real(0.25) - Real(0.5) * static_cast<Real>(i), 0};
            const BodyId id = c.world.createBody(sphereBody(1, p));
            c.links.push_back(id);
            c.joints.push_back(c.world.createJoint(jointDef(JointType::Ball, prev, id, p + Vec3{0, Real(0.25), 0})));
            prev = id;
        }
    }
    for (int i = 0; i < 120; ++i) c.world.step(kDt);
    for (const BodyId id : c.links) ASSERT_FALSE(c.world.isAwake(id)) << "the resting chains must be asleep";
    // Wake one chain (a push on its last link): its joints come back, the other's stay out.
    c.world.setLinearVelocity(c.links[5], {2, 0, 0});
    ASSERT_TRUE(c.world.isAwake(c.links[0]));
    ASSERT_FALSE(c.world.isAwake(c.links[6]));
    EXPECT_LT(expectSameAsFreshWorld(c, 30, "one chain woken"), kTreeError);
    // And the other one: both trees solved again.
    c.world.setLinearVelocity(c.links[11], {0, 0, 2});
    EXPECT_LT(expectSameAsFreshWorld(c, 30, "both chains awake"), kTreeError);
}

}  // namespace
}  // namespace fulcrum::jointtest
