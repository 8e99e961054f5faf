// World shape casts against analytic times of impact.
//
// Tolerance: shapeCast stops conservative advancement within 1e-4 m of
// contact (its default tolerance), so along a 10 m translation the fraction
// is early by at most 1e-5 (plus float rounding); we allow 2e-5, i.e. 0.2 mm.
// Normals: 1e-3 per component (the normal comes from the closest features at
// the stopping distance, 0.1 mm short of contact).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include <fulcrum/fulcrum.hpp>

namespace {

using namespace fulcrum;

constexpr Real kFractionTol = Real(2e-5);
constexpr Real kNormalTol = Real(1e-3);
constexpr Real kPointTol = Real(1e-3);

BodyId addStatic(World& world, const Shape& shape, const Vec3& position, const Quat& q = {}) {
    BodyDef def;
    def.type = BodyType::Static;
    def.shape = shape;
    def.position = position;
    def.orientation = q;
    return world.createBody(def);
}

void expectVecNear(const Vec3& a, const Vec3& b, Real tol, const char* what) {
    EXPECT_NEAR(a.x, b.x, tol) << what;
    EXPECT_NEAR(a.y, b.y, tol) << what;
    EXPECT_NEAR(a.z, b.z, tol) << what;
}

TEST(ShapeCast, SphereOntoPlane) {
    // Sphere r = 0.5 from y = 5 down 10 m onto the plane y = 0: contact when its
    // centre is at y = 0.5, fraction 0.45, at the point (x, 0, z), normal +y.
    World world;
    const BodyId ground = addStatic(world, Shape::plane({0, 1, 0}, 0), {});
    const auto hit = world.castShape(Shape::sphere(Real(0.5)), {{1, 5, 2}, {}}, {0, -10, 0});
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->body, ground);
    EXPECT_NEAR(hit->fraction, Real(0.45), kFractionTol);
    expectVecNear(hit->normal, {0, 1, 0}, kNormalTol, "normal");
    expectVecNear(hit->point, {1, 0, 2}, kPointTol, "point");
}

TEST(ShapeCast, SphereOntoTiltedPlaneAlongASlant) {
    // Plane with normal n = (0.6, 0.8, 0) through the origin; sphere r = 1 from
    // c0 = (0, 10, 0) along d = (0, -20, 0). Contact when n . (c0 + t d) = r:
    // t = (8 - 1) / 16 = 0.4375.
    World world;
    const BodyId plane = addStatic(world, Shape::plane({Real(0.6), Real(0.8), 0}, 0), {});
    const auto hit = world.castShape(Shape::sphere(1), {{0, 10, 0}, {}}, {0, -20, 0});
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->body, plane);
    EXPECT_NEAR(hit->fraction, Real(0.4375), kFractionTol);
    expectVecNear(hit->normal, {Real(0.6), Real(0.8), 0}, kNormalTol, "normal");
}

TEST(ShapeCast, SphereOntoRotatedBoxFace) {
    // Box half extents (1, 2, 0.5) turned 90 degrees about y: its +x face is the
    // local -z face, at x = 3 + 0.5. A sphere r = 0.25 moving along -x from
    // x = 10 touches when its centre is at x = 3.75: fraction 6.25 / 10.
    World world;
    const BodyId box = addStatic(world, Shape::box({1, 2, Real(0.5)}), {3, 0, 0},
                                 Quat::fromAxisAngle({0, 1, 0}, std::numbers::pi_v<Real> / 2));
    const auto hit = world.castShape(Shape::sphere(Real(0.25)), {{10, Real(0.3), Real(0.4)}, {}}, {-10, 0, 0});
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->body, box);
    EXPECT_NEAR(hit->fraction, Real(0.625), kFractionTol);
    expectVecNear(hit->normal, {1, 0, 0}, kNormalTol, "normal");
    expectVecNear(hit->point, {Real(3.5), Real(0.3), Real(0.4)}, kPointTol, "point");
}

TEST(ShapeCast, SphereOntoBoxEdge) {
    // Unit-half-extent box turned 45 degrees about z: its top is an edge along z
    // at height sqrt(2). A sphere r = 0.5 falling from y = 5 over the edge
    // touches when its centre is at sqrt(2) + 0.5: fraction (5 - 1.914) / 10.
    World world;
    addStatic(world, Shape::box({1, 1, 1}), {}, Quat::fromAxisAngle({0, 0, 1}, std::numbers::pi_v<Real> / 4));
    const auto hit = world.castShape(Shape::sphere(Real(0.5)), {{0, 5, Real(0.3)}, {}}, {0, -10, 0});
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->fraction, (5 - std::sqrt(Real(2)) - Real(0.5)) / 10, kFractionTol);
    expectVecNear(hit->normal, {0, 1, 0}, kNormalTol, "normal");
}

TEST(ShapeCast, FirstOfSeveralBodiesAndFilter) {
    // Boxes with tops at y = 1 (x = 0) and y = 3 (x = 0, higher, created later):
    // a sphere r = 0.5 falling from y = 10 hits the higher one first (centre at
    // y = 3.5: fraction 0.65); excluding it, the lower one (y = 1.5: 0.85).
    World world;
    const BodyId low = addStatic(world, Shape::box({2, Real(0.5), 2}), {0, Real(0.5), 0});
    BodyDef high;
    high.shape = Shape::box({Real(0.5), Real(0.5), Real(0.5)});
    high.position = {0, Real(2.5), 0};
    const BodyId highId = world.createBody(high);  // dynamic, never stepped
    const Shape ball = Shape::sphere(Real(0.5));
    const auto first = world.castShape(ball, {{0, 10, 0}, {}}, {0, -10, 0});
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->body, highId);
    EXPECT_NEAR(first->fraction, Real(0.65), kFractionTol);
    QueryFilter f;
    f.excludeBody = highId;
    const auto second = world.castShape(ball, {{0, 10, 0}, {}}, {0, -10, 0}, f);
    ASSERT_TRUE(second.has_value());
    EXPECT_EQ(second->body, low);
    EXPECT_NEAR(second->fraction, Real(0.85), kFractionTol);
    // Too short a sweep hits nothing.
    EXPECT_FALSE(world.castShape(ball, {{0, 10, 0}, {}}, {0, -6, 0}).has_value());
}

TEST(ShapeCast, CompoundQueryShapeAndStartingInContact) {
    // A compound of two spheres (r = 0.5 at x = +-1) falling onto a plane: the
    // lower sphere's centre is at y = c - 0.3 (the compound turned so one child
    // sits lower), contact when it reaches 0.5.
    World world;
    addStatic(world, Shape::plane({0, 1, 0}, 0), {});
    const std::array<CompoundChild, 2> children{CompoundChild{Shape::sphere(Real(0.5)), {{-1, Real(-0.3), 0}, {}}},
                                                CompoundChild{Shape::sphere(Real(0.5)), {{1, 0, 0}, {}}}};
    const Shape dumbbell = Shape::compound(children);
    const auto hit = world.castShape(dumbbell, {{0, 4, 0}, {}}, {0, -8, 0});
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->fraction, (Real(3.7) - Real(0.5)) / 8, kFractionTol);
    // Already touching: fraction 0.
    const auto touching = world.castShape(Shape::sphere(Real(0.5)), {{0, Real(0.4), 0}, {}}, {1, 0, 0});
    ASSERT_TRUE(touching.has_value());
    EXPECT_EQ(touching->fraction, 0);
}

TEST(ShapeCast, AgainstMesh) {
    // Sphere r = 0.5 falling onto a flat quad mesh at y = 1: fraction (5 - 1.5) / 10.
    World world;
    const std::vector<Vec3> v{{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
    const std::vector<std::array<std::uint32_t, 3>> t{{0, 2, 1}, {0, 3, 2}};
    const BodyId mesh = addStatic(world, Shape::mesh(v, t), {0, 1, 0});
    const auto hit = world.castShape(Shape::sphere(Real(0.5)), {{1, 5, 1}, {}}, {0, -10, 0});
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->body, mesh);
    EXPECT_NEAR(hit->fraction, Real(0.35), kFractionTol);
    expectVecNear(hit->normal, {0, 1, 0}, kNormalTol, "normal");
}

}  // namespace
