// Snapshot format version 10: how each contact's pair first touched
// (Contact::firstTouch, the solver's push-out sharing: docs/solver.md, "Born
// deep, driven deep"). A world holding both kinds of deep pair resumes bit
// for bit; a version-9 file loads its touching pairs as born deep.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"
#include "world/snapshot_versions.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {
namespace {

constexpr Real kDt = Real(1) / 60;

BodyId addUnitBox(World& world, const Vec3& position, Real mass) {
    BodyDef d;
    d.shape = Shape::box(Vec3::splat(Real(0.5)));
    d.mass = mass;
    d.position = position;
    d.friction = Real(0.6);
    return world.createBody(d);
}

// A kinematic plate driving three boxes into a 150 kg box (their overlaps
// driven deep, tests/solver/pusher_jam_test.cpp) and, 10 m away, five boxes
// created at one spot (born deep).
World bothKinds() {
    World world(WorldDef{});
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({50, Real(0.5), 50});
    ground.position = {0, Real(-0.5), 0};
    ground.friction = Real(0.6);
    world.createBody(ground);
    BodyDef plate;
    plate.type = BodyType::Kinematic;
    plate.shape = Shape::box({Real(0.25), Real(0.5), Real(0.5)});
    plate.position = {Real(-0.75), Real(0.5), 0};
    plate.linearVelocity = {Real(3.5), 0, 0};
    world.createBody(plate);
    for (int i = 0; i < 3; ++i) addUnitBox(world, {Real(0.5) + static_cast<Real>(i), Real(0.5), 0}, 1);
    addUnitBox(world, {Real(3.5), Real(0.5), 0}, 150);
    for (int i = 0; i < 5; ++i) addUnitBox(world, {0, Real(0.5), 10}, 1);
    // And, 10 m away on the other side, a 10^6 kg box sinking into a 1 kg one
    // (a pair driven deep that the push-out by position of pairs grown within
    // a step leaves to the soft contact: ContactSolver::pushOutGrown; the
    // jam's boxes, pushed apart by it, no longer go deep).
    addUnitBox(world, {0, Real(0.5), -10}, 1);
    addUnitBox(world, {0, Real(1.5), -10}, Real(1e6));
    return world;
}

std::vector<detail::FirstTouch> firstTouches(const World& world) {
    std::vector<detail::FirstTouch> out;
    for (const detail::Contact& c : detail::implOf(world).contactManager.contacts()) out.push_back(c.firstTouch);
    return out;
}

TEST(FirstTouchSnapshot, BornAndDrivenPairsResumeBitForBit) {
    World original = bothKinds();
    for (int i = 0; i < 30; ++i) original.step(kDt);
    const std::vector<detail::FirstTouch> kinds = firstTouches(original);
    ASSERT_NE(std::count(kinds.begin(), kinds.end(), detail::FirstTouch::Deep), 0);
    ASSERT_NE(std::count(kinds.begin(), kinds.end(), detail::FirstTouch::Shallow), 0);
    World resumed = loadSnapshotFromMemory(saveSnapshotToMemory(original));
    EXPECT_EQ(firstTouches(resumed), kinds);
    // A version-9 file has no flag: its touching pairs load as born deep, so
    // the driven boxes share their push-out again and the run goes its own way.
    World fromNine = loadSnapshotFromMemory(detail::saveSnapshotAsVersion(original, 9));
    bool nineDiverged = false;
    for (int i = 0; i < 90; ++i) {
        original.step(kDt);
        resumed.step(kDt);
        fromNine.step(kDt);
        ASSERT_EQ(test::stateHash(resumed), test::stateHash(original)) << "diverged at step " << i + 1;
        nineDiverged = nineDiverged || test::stateHash(fromNine) != test::stateHash(original);
    }
    EXPECT_TRUE(nineDiverged) << "the flag must matter in this scene";
}

TEST(FirstTouchSnapshot, VersionNineLoadsTouchingPairsAsBornDeep) {
    World world = bothKinds();
    for (int i = 0; i < 30; ++i) world.step(kDt);
    const std::vector<std::uint8_t> v9 = detail::saveSnapshotAsVersion(world, 9);
    const std::vector<std::uint8_t> v10 = detail::saveSnapshotAsVersion(world, 10);
    EXPECT_EQ(v10[8], 10);
    const std::size_t contacts = detail::implOf(world).contactManager.contacts().size();
    EXPECT_EQ(v10.size() - v9.size(), contacts);  // one byte per contact slot
    const World loaded = loadSnapshotFromMemory(v9);
    for (const detail::Contact& c : detail::implOf(loaded).contactManager.contacts()) {
        if (!c.alive) continue;
        EXPECT_EQ(c.firstTouch, c.manifolds.empty() ? detail::FirstTouch::NotYet : detail::FirstTouch::Deep);
    }
}

}  // namespace
}  // namespace fulcrum
