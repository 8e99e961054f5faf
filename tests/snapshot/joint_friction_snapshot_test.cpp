// Snapshot format version 3: joint friction (JointDef::frictionTorque and the
// solver's warm-started friction impulse) and the WorldDef joint solver
// settings survive a snapshot, so save-at-step-N then load-and-continue is bit
// for bit the run that never stopped; a version-2 file still loads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"
#include "world/snapshot_versions.hpp"
#include "world/world_access.hpp"

namespace fulcrum {
namespace {

using test::stateHash;

constexpr Real kDt = Real(1) / Real(60);

BodyDef limb(Real mass, Vec3 p, Shape shape) {
    BodyDef d;
    d.shape = std::move(shape);
    d.mass = mass;
    d.position = p;
    d.angularDamping = Real(0.5);
    return d;
}

JointDef joint(JointType type, BodyId a, BodyId b, Vec3 anchor, Vec3 axis, Real friction) {
    JointDef j;
    j.type = type;
    j.bodyA = a;
    j.bodyB = b;
    j.anchor = anchor;
    j.axis = axis;
    j.frictionTorque = friction;
    return j;
}

// A ragdoll-like figure tipped over onto a floor: cone-twist spine and neck,
// ball shoulders and hips, hinge elbows and knees, every joint with dry
// friction. The joint settings differ from the defaults, so a snapshot that
// lost them would resume a different simulation.
World ragdollWorld(bool directSolve) {
    WorldDef def;
    def.jointHertz = 45;
    def.jointDampingRatio = Real(1.5);
    def.jointProjectionSlop = Real(0.01);
    def.jointDirectSolve = directSolve;
    World w(def);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({5, Real(0.5), 5});
    ground.position = {0, Real(-0.5), 0};
    w.createBody(ground);

    const Quat tilt = Quat::fromAxisAngle({0, 0, 1}, Real(0.3));
    const auto at = [&](Vec3 p) { return rotate(tilt, p) + Vec3{0, Real(0.3), 0}; };
    const Real friction = Real(0.8);
    const BodyId pelvis = w.createBody(limb(8, at({0, 1, 0}), Shape::box({Real(0.15), Real(0.1), Real(0.1)})));
    const BodyId torso = w.createBody(limb(15, at({0, Real(1.35), 0}), Shape::box({Real(0.18), Real(0.22), Real(0.1)})));
    const BodyId head = w.createBody(limb(4, at({0, Real(1.72), 0}), Shape::sphere(Real(0.11))));
    w.createJoint(joint(JointType::ConeTwist, pelvis, torso, at({0, Real(1.1), 0}), rotate(tilt, {0, 1, 0}), friction));
    w.createJoint(joint(JointType::ConeTwist, torso, head, at({0, Real(1.59), 0}), rotate(tilt, {0, 1, 0}), friction));
    for (const Real s : {Real(-1), Real(1)}) {
        const BodyId upperArm = w.createBody(limb(2, at({s * Real(0.38), Real(1.5), 0}), Shape::sphere(Real(0.08))));
        const BodyId lowerArm = w.createBody(limb(Real(1.5), at({s * Real(0.62), Real(1.5), 0}), Shape::sphere(Real(0.07))));
        w.createJoint(joint(JointType::Ball, torso, upperArm, at({s * Real(0.24), Real(1.5), 0}), {1, 0, 0}, friction));
        w.createJoint(joint(JointType::Hinge, upperArm, lowerArm, at({s * Real(0.5), Real(1.5), 0}), rotate(tilt, {0, 1, 0}), friction));
        const BodyId thigh = w.createBody(limb(7, at({s * Real(0.1), Real(0.7), 0}), Shape::capsule(Real(0.07), Real(0.13))));
        const BodyId shin = w.createBody(limb(4, at({s * Real(0.1), Real(0.27), 0}), Shape::capsule(Real(0.06), Real(0.15))));
        w.createJoint(joint(JointType::Ball, pelvis, thigh, at({s * Real(0.1), Real(0.9), 0}), {1, 0, 0}, friction));
        w.createJoint(joint(JointType::Hinge, thigh, shin, at({s * Real(0.1), Real(0.49), 0}), rotate(tilt, {1, 0, 0}), friction));
    }
    return w;
}

// Runs `total` steps straight through, and from a snapshot taken at `at`;
// every step after it must hash equal (bit-identical state).
void expectResumeMatches(bool directSolve, int at, int total) {
    World straight = ragdollWorld(directSolve);
    for (int i = 0; i < at; ++i) straight.step(kDt);
    World resumed = loadSnapshotFromMemory(saveSnapshotToMemory(straight));
    for (int i = at; i < total; ++i) {
        straight.step(kDt);
        resumed.step(kDt);
        ASSERT_EQ(stateHash(straight), stateHash(resumed)) << "direct solve " << directSolve << ", snapshot at step " << at
                                                           << ", diverged at step " << i + 1;
    }
    // Still in motion at the end (a world at rest would match trivially).
    Real fastest = 0;
    for (const BodyId id : straight.bodies()) fastest = std::max(fastest, length(straight.linearVelocity(id)));
    EXPECT_GT(fastest, Real(0.05)) << "the ragdoll must still move at step " << total;
}

TEST(JointFrictionSnapshot, SettingsAndFrictionTorqueSurvive) {
    World w = ragdollWorld(false);
    w.step(kDt);
    const World loaded = loadSnapshotFromMemory(saveSnapshotToMemory(w));
    EXPECT_EQ(loaded.settings().jointHertz, Real(45));
    EXPECT_EQ(loaded.settings().jointDampingRatio, Real(1.5));
    EXPECT_EQ(loaded.settings().jointProjectionSlop, Real(0.01));
    EXPECT_FALSE(loaded.settings().jointDirectSolve);
    ASSERT_EQ(loaded.joints().size(), 10u);
    for (const JointId id : loaded.joints()) EXPECT_EQ(loaded.jointDef(id).frictionTorque, Real(0.8));
}

TEST(JointFrictionSnapshot, ResumeIsBitIdenticalWithJointFriction) {
    // Step 20: falling, joints swinging against their friction; 45: hitting
    // the floor; 80: settling, friction impulses warm-started (the ragdoll is
    // still moving at step 120, so the comparison covers real motion).
    for (const bool direct : {true, false}) {
        for (const int at : {20, 45, 80}) expectResumeMatches(direct, at, 120);
    }
}

TEST(JointFrictionSnapshot, FrictionImpulseMatters) {
    // The proof that the test above sees the friction impulse: a resumed world
    // whose warm-start friction impulses are zeroed departs from the
    // uninterrupted run (tolerance 0: any changed bit counts).
    World straight = ragdollWorld(true);
    for (int i = 0; i < 45; ++i) straight.step(kDt);
    World resumed = loadSnapshotFromMemory(saveSnapshotToMemory(straight));
    bool anyFriction = false;
    for (detail::JointData& j : detail::implOf(resumed).joints) {
        anyFriction = anyFriction || j.impulses.friction != Vec3{};
        j.impulses.friction = {};
    }
    ASSERT_TRUE(anyFriction) << "the scene must have warm-started friction impulses at step 45";
    bool diverged = false;
    for (int i = 0; i < 30 && !diverged; ++i) {
        straight.step(kDt);
        resumed.step(kDt);
        diverged = stateHash(straight) != stateHash(resumed);
    }
    EXPECT_TRUE(diverged);
}

TEST(JointFrictionSnapshot, VersionTwoStillLoads) {
    // A version-2 file has no joint settings or friction: they load as the
    // defaults. A default-settings world with frictionless joints written as
    // version 2 resumes bit-identically.
    WorldDef def;
    World straight(def);
    BodyDef anchor;
    anchor.type = BodyType::Static;
    anchor.shape = Shape::sphere(Real(0.1));
    anchor.position = {0, 3, 0};
    BodyId previous = straight.createBody(anchor);
    for (int i = 1; i <= 4; ++i) {
        const BodyId link = straight.createBody(limb(1, {Real(0.4) * static_cast<Real>(i), 3, 0}, Shape::sphere(Real(0.1))));
        straight.createJoint(joint(JointType::Ball, previous, link, {Real(0.4) * static_cast<Real>(i - 1), 3, 0}, {1, 0, 0}, 0));
        previous = link;
    }
    for (int i = 0; i < 30; ++i) straight.step(kDt);
    const std::vector<std::uint8_t> v2 = detail::saveSnapshotAsVersion(straight, 2);
    const std::vector<std::uint8_t> v3 = detail::saveSnapshotAsVersion(straight, 3);
    EXPECT_EQ(v2[8], 2);
    EXPECT_EQ(v3[8], 3);
    // Version 3 adds 3 reals and a bool to the settings, and per joint one real and a Vec3.
    EXPECT_EQ(v3.size() - v2.size(), 3 * sizeof(Real) + 1 + 4 * (4 * sizeof(Real)));
    World resumed = loadSnapshotFromMemory(v2);
    EXPECT_EQ(resumed.settings().jointHertz, WorldDef{}.jointHertz);
    EXPECT_EQ(resumed.settings().jointDirectSolve, WorldDef{}.jointDirectSolve);
    for (int i = 0; i < 60; ++i) {
        straight.step(kDt);
        resumed.step(kDt);
        ASSERT_EQ(stateHash(straight), stateHash(resumed)) << "diverged at step " << i + 1;
    }
}

TEST(JointFrictionSnapshot, OtherVersionsAreRefused) {
    const World w;
    std::vector<std::uint8_t> bytes = saveSnapshotToMemory(w);
    bytes[8] = 1;
    try {
        (void)loadSnapshotFromMemory(bytes, nullptr, "old.snap");
        FAIL() << "version 1 must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "old.snap: unsupported snapshot version 1 (this build reads versions 2 to " + std::to_string(kSnapshotVersion) + ")");
    }
    EXPECT_THROW((void)detail::saveSnapshotAsVersion(w, kSnapshotVersion + 1), Error);
}

}  // namespace
}  // namespace fulcrum
