// World::createBody's cheaper path for many static bodies (branch `bigworld`,
// large_world: a million static boxes): the values are tested at once and
// field by field only when that fails, so the first bad field in the
// documented order still names the error; the contact buffers are reserved
// again only when their count, the pair limit or the step changed, so a
// world whose static bodies came first still steps without allocating.
#include <gmock/gmock.h>

#include <limits>

#include "dynamics/test_scenes.hpp"
#include "support/counting_allocator.hpp"

using namespace fulcrum;
using namespace fulcrum::test;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

namespace {

constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
constexpr Real kInf = std::numeric_limits<Real>::infinity();

BodyDef tile() {
    BodyDef d;
    d.name = "tile";
    d.type = BodyType::Static;
    d.shape = Shape::box({Real(0.5), Real(0.25), Real(0.5)});
    return d;
}

template <class Edit>
std::string createError(Edit edit) {
    World world;
    BodyDef d = tile();
    edit(d);
    return errorOf([&] { world.createBody(d); });
}

}  // namespace

TEST(StaticCreation, TheFirstBadFieldInOrderNamesTheError) {
    // Order: position, orientation, linearVelocity, angularVelocity, friction,
    // restitution, rollingResistance, linearDamping, angularDamping,
    // linearDrag, quadraticDrag, gravityScale.
    EXPECT_THAT(createError([](BodyDef& d) {
                    d.friction = -1;
                    d.gravityScale = kInf;
                }),
                AllOf(HasSubstr("body 'tile'"), HasSubstr("friction"), Not(HasSubstr("gravityScale"))));
    EXPECT_THAT(createError([](BodyDef& d) {
                    d.position.y = kNaN;
                    d.orientation = {0, 0, 0, 0};
                }),
                AllOf(HasSubstr("position"), Not(HasSubstr("orientation"))));
    EXPECT_THAT(createError([](BodyDef& d) {
                    d.orientation = {0, 0, 0, 0};
                    d.restitution = -1;
                }),
                AllOf(HasSubstr("orientation"), HasSubstr("non-zero")));
    EXPECT_THAT(createError([](BodyDef& d) { d.orientation = {0, 0, 0, 0}; }), AllOf(HasSubstr("orientation"), HasSubstr("non-zero")));
    EXPECT_THAT(createError([](BodyDef& d) { d.rollingResistance = -Real(0.5); }),
                AllOf(HasSubstr("rollingResistance"), HasSubstr("negative")));
    EXPECT_THAT(createError([](BodyDef& d) { d.quadraticDrag = kInf; }), AllOf(HasSubstr("quadraticDrag"), HasSubstr("finite")));
    EXPECT_THAT(createError([](BodyDef& d) {
                    d.angularVelocity.x = kInf;
                    d.linearDamping = kNaN;
                }),
                HasSubstr("angularVelocity"));
    // -0 is not negative, as before; the largest finite value is finite.
    World world;
    BodyDef d = tile();
    d.friction = -Real(0);
    d.linearDrag = std::numeric_limits<Real>::max();
    EXPECT_NO_THROW(world.createBody(d));
    EXPECT_EQ(world.bodyCount(), 1u);
}

TEST(StaticCreation, AStaticBoxSitsWhereItWasPut) {
    // No mass properties are worked out for a plain static primitive: its
    // centre of mass is its origin, so its pose reads back exactly.
    World world;
    BodyDef d = tile();
    d.position = {Real(1.25), Real(-3.5), Real(7)};
    d.orientation = normalize(Quat{Real(0.8), Real(0.1), Real(-0.5), Real(0.3)});
    const BodyId b = world.createBody(d);
    EXPECT_EQ(world.position(b), d.position);
    EXPECT_EQ(world.orientation(b), d.orientation);
}

TEST(StaticCreation, StaticBodiesFirstThenMovingOnesStepWithoutAllocating) {
    // large_world's order: the ground's tiles (more than the bulk build's
    // 1,024) before any moving body, so every tile's creation keeps the
    // contact buffers' count; the spheres after them raise it. Once warm,
    // the steps allocate nothing while the spheres land on the tiles.
    World world;
    for (int i = 0; i < 40; ++i) {
        for (int j = 0; j < 40; ++j) {
            BodyDef d = tile();
            d.name.clear();
            d.position = {Real(i) - 20, 0, Real(j) - 20};
            world.createBody(d);
        }
    }
    for (int k = 0; k < 30; ++k) {
        BodyDef s;
        s.shape = Shape::sphere(Real(0.3));
        s.density = 1000;
        s.position = {Real(k % 6) * Real(1.3) - 4, Real(0.6) + Real(k / 6) * Real(0.7), Real(k % 5) - 2};
        world.createBody(s);
    }
    world.step(Real(1) / 60);  // warm-up: the static tree's bulk build, the first pairs
    CountAllocations count;
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
    EXPECT_EQ(count.stop(), 0);
    EXPECT_GT(world.contacts().size(), 0u);  // they rest on the tiles
}
