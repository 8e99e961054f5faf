// Contact force per body (World::contactForce, contactForces): the sum of the
// contact report's forces on a body over the last step, against statics.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <vector>

#include "fulcrum/fulcrum.hpp"

using namespace fulcrum;

namespace {

World groundWorld() {
    WorldDef d;
    d.sleeping = false;
    World world(d);
    BodyDef g;
    g.type = BodyType::Static;
    g.shape = Shape::plane({0, 1, 0}, 0);
    world.createBody(g);
    return world;
}

BodyId box(World& world, Real mass, Vec3 position, Real half) {
    BodyDef b;
    b.shape = Shape::box({half, half, half});
    b.mass = mass;
    b.position = position;
    return world.createBody(b);
}

}  // namespace

// A resting box: its contact force is m g up within 0.5 %, and nothing sideways.
TEST(BodyContactForce, RestingBoxCarriesItsWeight) {
    World world = groundWorld();
    const Real m = 3;
    const BodyId b = box(world, m, {0, Real(0.25), 0}, Real(0.25));
    for (int i = 0; i < 120; ++i) world.step(Real(1) / 60);
    const Vec3 f = world.contactForce(b);
    EXPECT_NEAR(f.y, m * Real(9.81), Real(0.005) * m * Real(9.81));
    EXPECT_NEAR(f.x, 0, Real(1e-3));
    EXPECT_NEAR(f.z, 0, Real(1e-3));
}

// Two boxes stacked: the lower one is pushed up by the ground (both weights)
// and down by the upper one (its weight): net m_lower g; the upper one
// carries its own weight; the bulk call gives the same, in the order asked.
TEST(BodyContactForce, StackSumsBothSides) {
    World world = groundWorld();
    const BodyId lower = box(world, 2, {0, Real(0.25), 0}, Real(0.25));
    const BodyId upper = box(world, 1, {0, Real(0.75), 0}, Real(0.25));
    for (int i = 0; i < 180; ++i) world.step(Real(1) / 60);
    const std::vector<BodyId> asked{upper, lower, upper};
    const std::vector<Vec3> f = world.contactForces(asked);
    ASSERT_EQ(f.size(), 3u);
    EXPECT_NEAR(f[0].y, Real(1 * 9.81), Real(0.005 * 9.81));
    EXPECT_NEAR(f[1].y, Real(2 * 9.81), Real(0.005 * 2 * 9.81));
    EXPECT_EQ(f[2].y, f[0].y);
    EXPECT_EQ(world.contactForce(lower).y, f[1].y);
}

// A body without contacts reads zero; a stale handle is an error naming the call.
TEST(BodyContactForce, NoContactsAndStaleHandles) {
    World world = groundWorld();
    const BodyId b = box(world, 1, {0, 5, 0}, Real(0.25));
    world.step(Real(1) / 60);
    EXPECT_EQ(world.contactForce(b).y, 0);
    world.destroyBody(b);
    try {
        (void)world.contactForce(b);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_THAT(e.what(), testing::HasSubstr("World::contactForces"));
    }
}
