// Body lifetime, handles, getters/setters and mass rules of World.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "fulcrum/fulcrum.hpp"

using namespace fulcrum;
using ::testing::HasSubstr;

namespace {

BodyDef sphereBody(const char* name, Vec3 position = {}) {
    BodyDef d;
    d.name = name;
    d.shape = Shape::sphere(Real(0.5));
    d.position = position;
    return d;
}

}  // namespace

TEST(BodyLifecycle, CreateQueryDestroyAndStaleHandles) {
    World world;
    const BodyId a = world.createBody(sphereBody("a", {1, 2, 3}));
    const BodyId b = world.createBody(sphereBody("b"));
    EXPECT_EQ(world.bodyCount(), 2u);
    EXPECT_EQ(world.name(a), "a");
    EXPECT_EQ(world.findBody("b"), b);
    EXPECT_TRUE(world.findBody("nobody").isNull());
    EXPECT_EQ(world.position(a), Vec3(1, 2, 3));

    world.destroyBody(a);
    EXPECT_FALSE(world.isValid(a));
    EXPECT_EQ(world.bodyCount(), 1u);
    // b was swap-moved in the dense arrays; its handle must still work.
    EXPECT_EQ(world.name(b), "b");
    try {
        (void)world.position(a);
        FAIL() << "stale handle accepted";
    } catch (const Error& e) {
        EXPECT_THAT(e.what(), HasSubstr("stale BodyId"));
        EXPECT_THAT(e.what(), HasSubstr("World::position"));
    }
    // The slot is reused with a new generation: the old handle stays stale.
    const BodyId c = world.createBody(sphereBody("c"));
    EXPECT_EQ(c.index, a.index);
    EXPECT_NE(c.generation, a.generation);
    EXPECT_FALSE(world.isValid(a));
    EXPECT_THROW((void)world.linearVelocity(a), Error);
    EXPECT_THROW((void)world.mass(BodyId{}), Error);
    EXPECT_THROW((void)world.mass(BodyId{99, 0}), Error);
    // Creation order, not slot order.
    const std::vector<BodyId> all = world.bodies();
    ASSERT_EQ(all.size(), 2u);
    EXPECT_EQ(all[0], b);
    EXPECT_EQ(all[1], c);
}
