// Characters in snapshots (format version 6): a run saved mid-walk and
// restored continues bit for bit; an older format refuses them.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include <fulcrum/fulcrum.hpp>
#include <fulcrum/snapshot.hpp>

#include "world/snapshot_versions.hpp"

namespace {

using namespace fulcrum;

constexpr Real kDt = Real(1) / Real(60);

World walkWorld() {
    World world;
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::plane({0, 1, 0}, 0);
    world.createBody(ground);
    BodyDef platform;
    platform.type = BodyType::Kinematic;
    platform.shape = Shape::box({2, Real(0.2), 2});
    platform.position = {4, Real(0.2), 0};
    platform.angularVelocity = {0, Real(0.5), 0};
    world.createBody(platform);
    for (int i = 0; i < 3; ++i) {
        BodyDef box;
        box.shape = Shape::box({Real(0.25), Real(0.25), Real(0.25)});
        box.mass = 8;
        box.position = {Real(1 + 0.6 * i), Real(0.25), Real(-1.5)};
        world.createBody(box);
    }
    CharacterDef a;
    a.name = "a";
    a.position = {0, Real(0.91), 0};
    a.inputs = {{0, {Real(1.5), 0, 0}, false}, {Real(1.5), {0, 0, 0}, true}, {Real(1.6), {0, 0, 0}, false}};
    world.createCharacter(a);
    CharacterDef b;
    b.name = "b";
    b.position = {0, Real(0.91), Real(-1.5)};
    b.inputs = {{0, {1, 0, 0}, false}};
    world.createCharacter(b);
    return world;
}

TEST(CharacterSnapshot, MidWalkContinuesBitForBit) {
    World original = walkWorld();
    for (int i = 0; i < 80; ++i) original.step(kDt);
    const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(original);
    World restored = loadSnapshotFromMemory(bytes);
    ASSERT_EQ(restored.characters().size(), 2u);
    for (int i = 0; i < 120; ++i) {
        original.step(kDt);
        restored.step(kDt);
    }
    for (std::size_t k = 0; k < 2; ++k) {
        const CharacterState a = original.characterState(original.characters()[k]);
        const CharacterState b = restored.characterState(restored.characters()[k]);
        EXPECT_EQ(a.position, b.position);
        EXPECT_EQ(a.velocity, b.velocity);
        EXPECT_EQ(a.ground, b.ground);
        EXPECT_EQ(a.groundBody, b.groundBody);
    }
    const std::vector<BodyId> ba = original.bodies(), bb = restored.bodies();
    ASSERT_EQ(ba.size(), bb.size());
    for (std::size_t i = 0; i < ba.size(); ++i) EXPECT_EQ(original.transform(ba[i]), restored.transform(bb[i]));
}

TEST(CharacterSnapshot, OlderFormatRefusesCharacters) {
    World world = walkWorld();
    world.step(kDt);
    EXPECT_THROW((void)detail::saveSnapshotAsVersion(world, 5), Error);
}

}  // namespace
