// A world saved and loaded before every step continues bit for bit, through
// a run in which contacts begin and end, a pile falls asleep and is woken,
// and joints are added. Resuming once at a few chosen steps (snapshot_test)
// missed that a contact's mixed material (friction, restitution, rolling
// resistance) was not saved: the step reads it before the narrow phase mixes
// it again, so a world loaded just before a box landed on a row of boxes
// solved that step frictionless and went its own way (format version 9 saves
// it; older files get it mixed from the bodies on load).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "contacts/helpers.hpp"
#include "fulcrum/snapshot.hpp"
#include "world/snapshot_versions.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

bool sameBits(Real a, Real b) { return std::memcmp(&a, &b, sizeof(Real)) == 0; }

void expectSameState(const World& kept, const World& resumed, const std::vector<BodyId>& bodies, int step) {
    for (const BodyId id : bodies) {
        const Vec3 p = kept.position(id), q = resumed.position(id);
        const Quat r = kept.orientation(id), s = resumed.orientation(id);
        ASSERT_TRUE(sameBits(p.x, q.x) && sameBits(p.y, q.y) && sameBits(p.z, q.z) && sameBits(r.w, s.w) &&
                    sameBits(r.x, s.x) && sameBits(r.y, s.y) && sameBits(r.z, s.z))
            << "body " << id.index << " differs at step " << step;
        ASSERT_EQ(kept.isAwake(id), resumed.isAwake(id)) << "body " << id.index << " at step " << step;
    }
}

// Six boxes in a row on the ground, five dropped across neighbours (new
// contacts, constraints sharing bodies), a sphere rolling into the row, and a
// pendulum; the materials differ per body so the mixed values matter.
World buildRowAndDrops(std::vector<BodyId>& bodies) {
    World world;
    addGround(world);
    for (int i = 0; i < 6; ++i) bodies.push_back(addBox(world, {Real(1.2) * Real(i) - 3, Real(0.5), 0}));
    for (int i = 0; i < 5; ++i) {
        bodies.push_back(addBox(world, {Real(1.2) * Real(i) - Real(2.4), Real(1.6) + Real(0.9) * Real(i), Real(0.05)}));
    }
    bodies.push_back(addSphere(world, {-6, Real(0.3), 0}, Real(0.3)));
    world.setLinearVelocity(bodies.back(), {2, 0, 0});
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        world.setFriction(bodies[k], Real(0.3) + Real(0.05) * static_cast<Real>(k));
        world.setRestitution(bodies[k], Real(0.02) * static_cast<Real>(k % 3));
    }
    BodyDef bob;
    bob.shape = Shape::sphere(Real(0.2));
    bob.position = {8, 3, 0};
    const BodyId pendulum = world.createBody(bob);
    bodies.push_back(pendulum);
    JointDef pivot;
    pivot.type = JointType::Ball;
    pivot.bodyB = pendulum;
    pivot.anchor = {7, 3, 0};
    world.createJoint(pivot);
    return world;
}

TEST(SnapshotResume, LoadedBeforeEveryStepContinuesBitForBit) {
    std::vector<BodyId> bodies;
    World kept = buildRowAndDrops(bodies);
    World resumed = loadSnapshotFromMemory(saveSnapshotToMemory(kept));
    bool pileSlept = false;
    for (int step = 0; step < 400; ++step) {
        if (step == 300) {
            pileSlept = !kept.isAwake(bodies[0]) && !kept.isAwake(bodies[6]);
            for (World* w : {&kept, &resumed}) {  // wake a box of the pile, hang the sphere on a rope
                w->setLinearVelocity(bodies[2], {0, 2, 0});
                JointDef rope;
                rope.type = JointType::Ball;
                rope.bodyB = bodies[11];
                rope.anchor = w->position(bodies[11]) + Vec3{0, 1, 0};
                w->createJoint(rope);
            }
        }
        kept.step(kDt);
        World reloaded = loadSnapshotFromMemory(saveSnapshotToMemory(resumed));
        reloaded.step(kDt);
        resumed = std::move(reloaded);
        expectSameState(kept, resumed, bodies, step);
    }
    EXPECT_TRUE(pileSlept);  // the run went through what it meant to
}

// A version-8 file has no contact materials: they are mixed from the bodies
// on load, which is what the saved world held as long as no material changed
// since its last narrow phase. Loaded just before the third box lands.
TEST(SnapshotResume, VersionEightFileGetsItsContactMaterialsMixedOnLoad) {
    std::vector<BodyId> bodies;
    World kept = buildRowAndDrops(bodies);
    for (int step = 0; step < 37; ++step) kept.step(kDt);
    World resumed = loadSnapshotFromMemory(detail::saveSnapshotAsVersion(kept, 8));
    for (int step = 37; step < 120; ++step) {
        kept.step(kDt);
        resumed.step(kDt);
        expectSameState(kept, resumed, bodies, step);
    }
}

}  // namespace
