// Handles and the slot pool behind them: each kind of handle is its own type,
// a handle to a destroyed object stays invalid after its slot is reused (also
// when the slot's generation wraps), and the World's messages name the kind.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <type_traits>
#include <unordered_set>

#include "dynamics/slot_pool.hpp"
#include "fulcrum/world.hpp"
#include "support/error_of.hpp"

using namespace fulcrum;
using fulcrum::test::errorOf;

// A JointId is not a BodyId: passing one where the other is expected does not compile.
static_assert(!std::is_same_v<BodyId, JointId>);
static_assert(!std::is_same_v<BodyId, SpringId>);
static_assert(!std::is_same_v<JointId, SpringId>);
static_assert(!std::is_same_v<BodyId, ParticleSystemId>);
static_assert(!std::is_convertible_v<JointId, BodyId>);
static_assert(!std::is_convertible_v<BodyId, JointId>);
static_assert(!std::is_convertible_v<SpringId, BodyId>);
static_assert(!std::is_convertible_v<ParticleSystemId, BodyId>);
// Value handles: trivially copyable, two words, null by default.
static_assert(std::is_trivially_copyable_v<BodyId>);
static_assert(sizeof(JointId) == 2 * sizeof(std::uint32_t));
static_assert(BodyId{}.isNull() && kWorldBody.isNull() && SpringId{}.isNull());
static_assert(!BodyId{0, 0}.isNull());
static_assert(BodyId{3, 1} == BodyId{3, 1} && BodyId{3, 1} != BodyId{3, 2});

namespace {

struct Item : detail::PoolSlot {
    int value = 0;
};
using ItemId = Id<struct ItemTag>;
using ItemPool = detail::SlotPool<Item, ItemId>;

ItemId add(ItemPool& pool, int value) {
    const std::uint32_t slot = pool.nextSlot();
    pool.add().value = value;
    return pool.handleOf(slot);
}

}  // namespace

TEST(Handles, HashDistinguishesIndexAndGeneration) {
    const std::unordered_set<BodyId> ids{BodyId{1, 0}, BodyId{0, 1}, BodyId{1, 1}, BodyId{}};
    EXPECT_EQ(ids.size(), 4u);
    EXPECT_EQ(ids.count(BodyId{1, 1}), 1u);
}

TEST(SlotPool, ReusesTheLastFreedSlotWithANewGeneration) {
    ItemPool pool;
    const ItemId a = add(pool, 1), b = add(pool, 2), c = add(pool, 3);
    EXPECT_EQ(pool.liveCount(), 3u);
    pool.remove(a.index);
    pool.remove(c.index);
    EXPECT_EQ(pool.liveCount(), 1u);
    EXPECT_EQ(pool.nextSlot(), c.index) << "the slot freed last is filled first";
    const ItemId d = add(pool, 4);
    EXPECT_EQ(d.index, c.index);
    EXPECT_EQ(d.generation, c.generation + 1);
    EXPECT_EQ(pool.lookup(c), detail::HandleState::Stale) << "the old handle does not alias the new object";
    EXPECT_EQ(pool.lookup(d), detail::HandleState::Live);
    EXPECT_EQ(pool.lookup(a), detail::HandleState::Stale);
    EXPECT_EQ(pool.lookup(b), detail::HandleState::Live);
    EXPECT_EQ(pool.lookup(ItemId{}), detail::HandleState::Null);
    EXPECT_EQ(pool.lookup(ItemId{7, 0}), detail::HandleState::OutOfRange);
    EXPECT_EQ(pool[d.index].value, 4);
    EXPECT_EQ(pool.size(), 3u);
    EXPECT_TRUE(pool.consistent());
}

TEST(SlotPool, GenerationWrapsAndTheOldHandleStaysStale) {
    ItemPool pool;
    const ItemId first = add(pool, 1);
    pool.slots()[first.index].generation = UINT32_MAX;  // as if reused 2^32 - 1 times
    const ItemId old = pool.handleOf(first.index);
    EXPECT_TRUE(pool.isLive(old));
    pool.remove(old.index);
    const ItemId next = add(pool, 2);
    EXPECT_EQ(next.index, old.index);
    EXPECT_EQ(next.generation, 0u) << "the generation wraps to 0";
    EXPECT_FALSE(pool.isLive(old));
    EXPECT_TRUE(pool.isLive(next));
}

TEST(SlotPool, ConsistencyCatchesABrokenFreeList) {
    ItemPool pool;
    const ItemId a = add(pool, 1);
    add(pool, 2);
    pool.remove(a.index);
    EXPECT_TRUE(pool.consistent());
    pool.freeSlots().push_back(a.index);  // listed twice
    EXPECT_FALSE(pool.consistent());
    pool.freeSlots() = {1};  // a live slot listed, the dead one missing
    EXPECT_FALSE(pool.consistent());
    pool.freeSlots() = {9};  // out of range
    EXPECT_FALSE(pool.consistent());
}

TEST(SlotPool, WorldRejectsAStaleHandleAfterItsSlotIsReused) {
    World world;
    BodyDef def;
    const BodyId a = world.createBody(def);
    def.position = {0, 3, 0};
    const BodyId b = world.createBody(def);

    SpringDef s;
    s.bodyA = a;
    s.bodyB = b;
    s.stiffness = 10;
    const SpringId spring = world.createSpring(s);
    world.destroySpring(spring);
    const SpringId reused = world.createSpring(s);
    ASSERT_EQ(reused.index, spring.index);
    EXPECT_FALSE(world.isValid(spring));
    EXPECT_TRUE(world.isValid(reused));
    EXPECT_EQ(errorOf([&] { (void)world.springLength(spring); }),
              "World::springLength: stale SpringId (index 0): that spring was destroyed (or one of its bodies was)");
    EXPECT_EQ(world.springCount(), 1u);

    JointDef j;
    j.type = JointType::Ball;
    j.bodyA = a;
    j.bodyB = b;
    const JointId joint = world.createJoint(j);
    world.destroyJoint(joint);
    const JointId reusedJoint = world.createJoint(j);
    ASSERT_EQ(reusedJoint.index, joint.index);
    EXPECT_EQ(errorOf([&] { (void)world.jointDef(joint); }),
              "World::jointDef: stale JointId (index 0): that joint was destroyed (or one of its bodies was)");
    EXPECT_EQ(errorOf([&] { (void)world.jointDef(JointId{}); }), "World::jointDef: null JointId");
    EXPECT_EQ(errorOf([&] { (void)world.jointDef(JointId{5, 0}); }), "World::jointDef: JointId index 5 does not exist");

    RopeDef rope;
    rope.name = "r";
    const ParticleSystemId r = world.createRope(rope);
    world.destroyParticleSystem(r);
    const ParticleSystemId reusedRope = world.createRope(rope);
    ASSERT_EQ(reusedRope.index, r.index);
    EXPECT_FALSE(world.isValid(r));
    EXPECT_EQ(errorOf([&] { (void)world.particleCount(r); }),
              "particle system handle {0, 0}: is stale or was never created");
    EXPECT_EQ(errorOf([&] { (void)world.particleCount(ParticleSystemId{}); }), "particle system handle: is null");
}
