// Queries between steps (bodies created, moved or destroyed since the last
// step are seen as they are now) and bad input at the query boundary.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <fulcrum/fulcrum.hpp>

namespace {

using namespace fulcrum;

constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
constexpr Real kInf = std::numeric_limits<Real>::infinity();

// Runs `f`, expects a fulcrum::Error whose message contains every fragment.
template <class F>
void expectError(F&& f, std::initializer_list<const char*> fragments) {
    try {
        f();
        ADD_FAILURE() << "no fulcrum::Error thrown (expected one mentioning '" << *fragments.begin() << "')";
    } catch (const Error& e) {
        const std::string msg = e.what();
        for (const char* frag : fragments) EXPECT_NE(msg.find(frag), std::string::npos) << "message: " << msg;
    }
}

BodyId addSphere(World& world, const Vec3& at, BodyType type = BodyType::Dynamic) {
    BodyDef def;
    def.type = type;
    def.shape = Shape::sphere(Real(0.5));
    def.position = at;
    return world.createBody(def);
}

TEST(QueriesBetweenSteps, BodyCreatedBeforeAnyStepIsFound) {
    World world;
    const BodyId a = addSphere(world, {0, 0, 0});
    const BodyId s = addSphere(world, {3, 0, 0}, BodyType::Static);
    const auto hit = world.castRay({{-5, 0, 0}, {10, 0, 0}});
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->body, a);
    EXPECT_NEAR(hit->fraction, Real(0.45), Real(1e-6));  // x = -0.5 of a 10 m ray from -5
    EXPECT_EQ(world.overlapSphere({0, Real(0.9), 0}, Real(0.5)), std::vector<BodyId>{a});
    EXPECT_EQ(world.overlapAABB({{-1, -1, -1}, {4, 1, 1}}), (std::vector<BodyId>{a, s}));
    const auto swept = world.castShape(Shape::box(Vec3::splat(Real(0.25))), {{3, 5, 0}, {}}, {0, -10, 0});
    ASSERT_TRUE(swept.has_value());
    EXPECT_EQ(swept->body, s);
    // A body created after some steps, between two steps, too.
    for (int i = 0; i < 5; ++i) world.step(Real(1) / 60);
    const BodyId late = addSphere(world, {0, 20, 0});
    EXPECT_EQ(world.overlapSphere({0, 20, 0}, Real(0.1)), std::vector<BodyId>{late});
}

TEST(QueriesBetweenSteps, TeleportAndDestroy) {
    World world{WorldDef{.gravity = {0, 0, 0}}};
    const BodyId a = addSphere(world, {0, 0, 0});
    const BodyId wall = addSphere(world, {0, 0, 5}, BodyType::Static);
    world.step(Real(1) / 60);
    world.setTransform(a, {10, 0, 0}, {});
    EXPECT_TRUE(world.overlapSphere({0, 0, 0}, Real(0.2)).empty());
    EXPECT_EQ(world.overlapSphere({10, 0, 0}, Real(0.2)), std::vector<BodyId>{a});
    world.setTransform(wall, {0, 0, -5}, {});  // a static body moved by hand
    EXPECT_EQ(world.overlapSphere({0, 0, -5}, Real(0.2)), std::vector<BodyId>{wall});
    EXPECT_TRUE(world.overlapSphere({0, 0, 5}, Real(0.2)).empty());
    world.destroyBody(a);
    EXPECT_TRUE(world.overlapSphere({10, 0, 0}, Real(0.2)).empty());
    EXPECT_FALSE(world.castRay({{10, 5, 0}, {0, -10, 0}}).has_value());
    // The freed slot reused by a new body elsewhere.
    const BodyId b = addSphere(world, {-7, 0, 0});
    EXPECT_EQ(b.index, a.index);
    EXPECT_EQ(world.overlapSphere({-7, 0, 0}, Real(0.2)), std::vector<BodyId>{b});
}

TEST(QueriesBetweenSteps, SleepingBodiesAreFound) {
    // A box settles on the ground and falls asleep; it is still found where it rests.
    World world;
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({10, Real(0.5), 10});
    ground.position = {0, Real(-0.5), 0};
    world.createBody(ground);
    BodyDef crate;
    crate.shape = Shape::box(Vec3::splat(Real(0.5)));
    crate.position = {0, 2, 0};
    const BodyId id = world.createBody(crate);
    for (int i = 0; i < 300 && world.isAwake(id); ++i) world.step(Real(1) / 60);
    ASSERT_FALSE(world.isAwake(id));
    const auto hit = world.castRay({{0, 5, 0}, {0, -10, 0}});
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->body, id);
    EXPECT_NEAR(hit->point.y, 1, Real(2e-3));  // resting on y = 0 (the soft contact sits within ~1 mm)
}

// ---- bad input -------------------------------------------------------------------------

class BadInput : public ::testing::Test {
protected:
    World world;
    BodyId ball = addSphere(world, {});
};

TEST_F(BadInput, Rays) {
    expectError([&] { (void)world.castRay({{kNaN, 0, 0}, {1, 0, 0}}); }, {"World::castRay", "ray.origin", "finite"});
    expectError([&] { (void)world.castRay({{0, 0, 0}, {kInf, 0, 0}}); }, {"World::castRay", "ray.translation", "finite"});
    expectError([&] { (void)world.castRayAll({{0, 0, 0}, {0, 0, 0}}); }, {"World::castRayAll", "ray.translation", "zero"});
    expectError([&] { (void)world.castRay({{0, 0, 0}, {1, 0, 0}, Real(1.5)}); }, {"ray.maxFraction", "[0, 1]", "1.5"});
    expectError([&] { (void)world.castRay({{0, 0, 0}, {1, 0, 0}, Real(-0.1)}); }, {"ray.maxFraction", "[0, 1]"});
    expectError([&] { (void)world.castRay({{0, 0, 0}, {1, 0, 0}, kNaN}); }, {"ray.maxFraction", "finite"});
    // An end point past Real's range: 3e38 + 3e38 in float, 1.5e308 + 1.5e308 in double.
    const Real huge = sizeof(Real) == sizeof(float) ? Real(3e38f) : Real(1.5e308);
    expectError([&] { (void)world.castRay({{huge, 0, 0}, {huge, 0, 0}}); }, {"ray.translation", "float range"});
}

TEST_F(BadInput, Filters) {
    const BodyId gone = addSphere(world, {5, 0, 0});
    world.destroyBody(gone);
    QueryFilter f;
    f.excludeBody = gone;
    expectError([&] { (void)world.castRay({{0, 5, 0}, {0, -10, 0}}, f); }, {"World::castRay", "filter.excludeBody", "stale"});
    expectError([&] { (void)world.overlapSphere({}, 1, f); }, {"World::overlapSphere", "filter.excludeBody"});
}

TEST_F(BadInput, Overlaps) {
    expectError([&] { (void)world.overlapSphere({0, kNaN, 0}, 1); }, {"World::overlapSphere", "center", "finite"});
    expectError([&] { (void)world.overlapSphere({}, 0); }, {"World::overlapSphere", "radius", "positive"});
    expectError([&] { (void)world.overlapSphere({}, -1); }, {"radius", "positive", "-1"});
    expectError([&] { (void)world.overlapBox({}, {1, 0, 1}, {}); }, {"World::overlapBox", "halfExtents", "positive"});
    expectError([&] { (void)world.overlapBox({}, {1, 1, 1}, {0, 0, 0, 0}); }, {"World::overlapBox", "orientation"});
    expectError([&] { (void)world.overlapBox({}, {1, kInf, 1}, {}); }, {"halfExtents", "finite"});
    expectError([&] { (void)world.overlapAABB({{1, 0, 0}, {0, 1, 1}}); }, {"World::overlapAABB", "box", "min <= max"});
    expectError([&] { (void)world.overlapAABB({{kNaN, 0, 0}, {1, 1, 1}}); }, {"World::overlapAABB", "box.min"});
    expectError([&] { (void)world.overlapShape(Shape::plane({0, 1, 0}, 0), {}); },
                {"World::overlapShape", "shape", "plane"});
    expectError([&] { (void)world.overlapShape(Shape::sphere(1), {{kNaN, 0, 0}, {}}); },
                {"World::overlapShape", "transform.p"});
}

TEST_F(BadInput, ShapeCasts) {
    const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    const std::vector<std::array<std::uint32_t, 3>> t{{0, 2, 1}};
    expectError([&] { (void)world.castShape(Shape::mesh(v, t), {}, {1, 0, 0}); }, {"World::castShape", "shape", "mesh"});
    expectError([&] { (void)world.castShape(Shape::plane({0, 1, 0}, 0), {}, {1, 0, 0}); },
                {"World::castShape", "shape", "plane"});
    const std::array<CompoundChild, 1> children{CompoundChild{Shape::mesh(v, t), {}}};
    expectError([&] { (void)world.castShape(Shape::compound(children), {}, {1, 0, 0}); },
                {"World::castShape", "compound holding a plane or mesh"});
    expectError([&] { (void)world.castShape(Shape::sphere(1), {}, {0, 0, 0}); }, {"World::castShape", "translation", "zero"});
    expectError([&] { (void)world.castShape(Shape::sphere(1), {}, {kNaN, 0, 0}); }, {"translation", "finite"});
    expectError([&] { (void)world.castShape(Shape::sphere(1), {{}, {kNaN, 0, 0, 0}}, {1, 0, 0}); }, {"transform.q"});
}

TEST(QueryDeterminism, SameQuerySameAnswerBitForBit) {
    // Two worlds built and stepped identically answer a query identically.
    auto build = [] {
        World world;
        BodyDef ground;
        ground.type = BodyType::Static;
        ground.shape = Shape::plane({0, 1, 0}, 0);
        world.createBody(ground);
        for (int i = 0; i < 20; ++i) {
            BodyDef def;
            def.shape = i % 2 ? Shape::box(Vec3::splat(Real(0.3))) : Shape::sphere(Real(0.3));
            def.position = {static_cast<Real>(i % 5) * Real(0.5), 1 + static_cast<Real>(i) * Real(0.7), 0};
            world.createBody(def);
        }
        for (int i = 0; i < 90; ++i) world.step(Real(1) / 60);
        return world;
    };
    const World a = build(), b = build();
    const Ray ray{{-1, Real(0.4), 0}, {5, 0, 0}};
    const auto ha = a.castRayAll(ray), hb = b.castRayAll(ray);
    ASSERT_EQ(ha.size(), hb.size());
    for (std::size_t i = 0; i < ha.size(); ++i) {
        EXPECT_EQ(ha[i].body, hb[i].body);
        EXPECT_EQ(ha[i].fraction, hb[i].fraction);
        EXPECT_EQ(ha[i].point, hb[i].point);
    }
    EXPECT_EQ(a.overlapSphere({1, Real(0.5), 0}, 1), b.overlapSphere({1, Real(0.5), 0}, 1));
}

}  // namespace
