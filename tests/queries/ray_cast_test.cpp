// World ray casts against analytic answers: one body of every shape type, hit
// where geometry says (fraction, point, outward normal), all-hits ordering,
// and the query filter.
//
// Tolerances: rays are 10 m long, so a fraction error of 1e-5 is 0.1 mm; points
// are checked to 1e-4 m and unit normals to 1e-4 per component (float
// arithmetic in the shape ray casts, relative error ~1e-6 of the 10-20 m
// coordinates involved).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <fulcrum/fulcrum.hpp>

namespace {

using namespace fulcrum;

constexpr Real kFractionTol = Real(1e-5);
constexpr Real kPointTol = Real(1e-4);
constexpr Real kNormalTol = Real(1e-4);

void expectVecNear(const Vec3& a, const Vec3& b, Real tol, const char* what) {
    EXPECT_NEAR(a.x, b.x, tol) << what;
    EXPECT_NEAR(a.y, b.y, tol) << what;
    EXPECT_NEAR(a.z, b.z, tol) << what;
}

BodyId addBody(World& world, const Shape& shape, const Vec3& position, const Quat& orientation = {},
               BodyType type = BodyType::Static) {
    BodyDef def;
    def.type = type;
    def.shape = shape;
    def.position = position;
    def.orientation = orientation;
    return world.createBody(def);
}

// A downward ray from y = 10 to y = 0 through (x, ., z), 10 m long.
Ray downAt(Real x, Real z, Real top = 10) { return {{x, top, z}, {0, -10, 0}}; }

// Checks a hit against the analytic hit point and normal of a ray.
void expectHit(const std::optional<RayCastHit>& hit, BodyId body, const Ray& ray, const Vec3& point,
               const Vec3& normal) {
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->body, body);
    // fraction = |point - origin| / |translation| along the ray.
    const Real expected = dot(point - ray.origin, ray.translation) / lengthSquared(ray.translation);
    EXPECT_NEAR(hit->fraction, expected, kFractionTol);
    expectVecNear(hit->point, point, kPointTol, "point");
    expectVecNear(hit->normal, normal, kNormalTol, "normal");
    EXPECT_NEAR(length(hit->normal), 1, Real(1e-5));
}

class EveryShape : public ::testing::Test {
protected:
    World world{WorldDef{.gravity = {0, 0, 0}}};
};

TEST_F(EveryShape, SphereOffCentre) {
    // Sphere r = 0.5 at (0, 1, 0); a ray 0.3 off the axis meets it at height
    // sqrt(0.25 - 0.09) = 0.4 above the centre, normal (0.3, 0.4, 0) / 0.5.
    const BodyId id = addBody(world, Shape::sphere(Real(0.5)), {0, 1, 0}, {}, BodyType::Dynamic);
    const Ray ray = downAt(Real(0.3), 0);
    expectHit(world.castRay(ray), id, ray, {Real(0.3), Real(1.4), 0}, {Real(0.6), Real(0.8), 0});
}

TEST_F(EveryShape, RotatedBoxFace) {
    // Box half extents (1, 0.5, 2) tilted 30 degrees about z: its top face has
    // normal n = (-sin 30, cos 30, 0) and plane n . (p - c) = 0.5.
    const Real a = std::numbers::pi_v<Real> / 6;
    const Vec3 c{5, 1, 0};
    const BodyId id = addBody(world, Shape::box({1, Real(0.5), 2}), c, Quat::fromAxisAngle({0, 0, 1}, a));
    const Vec3 n{-std::sin(a), std::cos(a), 0};
    const Ray ray = downAt(Real(5.2), Real(0.5));
    // Solve n . (o + t d - c) = 0.5 for t.
    const Real t = (Real(0.5) - dot(n, ray.origin - c)) / dot(n, ray.translation);
    expectHit(world.castRay(ray), id, ray, ray.origin + ray.translation * t, n);
}

TEST_F(EveryShape, CapsuleCap) {
    // Capsule r = 0.3, half height 0.5, laid along x (90 degrees about z): its
    // cap centres are at x = +-0.5. A ray 0.1 beyond the end meets the cap
    // sphere at height sqrt(0.09 - 0.01).
    const Vec3 c{10, 1, 0};
    const BodyId id = addBody(world, Shape::capsule(Real(0.3), Real(0.5)), c,
                              Quat::fromAxisAngle({0, 0, 1}, std::numbers::pi_v<Real> / 2));
    const Real h = std::sqrt(Real(0.08));
    const Ray ray = downAt(Real(10.6), 0);
    expectHit(world.castRay(ray), id, ray, {Real(10.6), 1 + h, 0}, Vec3{Real(0.1), h, 0} / Real(0.3));
}

TEST_F(EveryShape, CylinderCapAndSide) {
    const Vec3 c{15, 1, 0};
    const BodyId id = addBody(world, Shape::cylinder(Real(0.4), Real(0.6)), c);
    // Down onto the cap: y = 1.6, normal up.
    const Ray down = downAt(Real(15.1), Real(0.2));
    expectHit(world.castRay(down), id, down, {Real(15.1), Real(1.6), Real(0.2)}, {0, 1, 0});
    // Sideways at z offset 0.2: meets the side at x = 15 + sqrt(0.16 - 0.04).
    const Real x = std::sqrt(Real(0.12));
    const Ray side{{25, Real(1.1), Real(0.2)}, {-10, 0, 0}};
    expectHit(world.castRay(side), id, side, {15 + x, Real(1.1), Real(0.2)}, Vec3{x, 0, Real(0.2)} / Real(0.4));
}

TEST_F(EveryShape, ConvexHullOctahedron) {
    // The octahedron |x| + |y| + |z| <= 1: above (0.2, 0.1) its face x + y + z = 1
    // is at y = 0.7, normal (1, 1, 1) / sqrt 3.
    const std::vector<Vec3> points{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const BodyId id = addBody(world, Shape::convexHull(points), {20, 0, 0});
    const Ray ray = downAt(Real(20.2), Real(0.1));
    expectHit(world.castRay(ray), id, ray, {Real(20.2), Real(0.7), Real(0.1)}, Vec3{1, 1, 1} / std::sqrt(Real(3)));
}

TEST_F(EveryShape, Plane) {
    // A wall z <= -10 (normal +z); a ray along -z from z = 0 meets it at z = -10.
    const BodyId id = addBody(world, Shape::plane({0, 0, 1}, -10), {});
    const Ray ray{{1, 2, 0}, {0, 0, -20}};
    expectHit(world.castRay(ray), id, ray, {1, 2, -10}, {0, 0, 1});
}

TEST_F(EveryShape, MeshTriangle) {
    // A quad of two triangles in the plane y = 0.5 (body at y = 0.5), x in
    // [30, 32], z in [-1, 1]. Hit from above: normal up, and the triangle
    // that contains the point.
    const std::vector<Vec3> v{{30, 0, -1}, {32, 0, -1}, {32, 0, 1}, {30, 0, 1}};
    const std::vector<std::array<std::uint32_t, 3>> t{{0, 2, 1}, {0, 3, 2}};
    const BodyId id = addBody(world, Shape::mesh(v, t), {0, Real(0.5), 0});
    // (31.5, -0.5) is in triangle 0 (x - 30 > z + 1); (30.5, 0.5) in triangle 1.
    const Ray a = downAt(Real(31.5), Real(-0.5));
    const auto ha = world.castRay(a);
    expectHit(ha, id, a, {Real(31.5), Real(0.5), Real(-0.5)}, {0, 1, 0});
    EXPECT_EQ(ha->triangle, 0u);
    const Ray b = downAt(Real(30.5), Real(0.5));
    const auto hb = world.castRay(b);
    expectHit(hb, id, b, {Real(30.5), Real(0.5), Real(0.5)}, {0, 1, 0});
    EXPECT_EQ(hb->triangle, 1u);
    // From below, the two-sided surface faces the ray.
    const Ray up{{31, -5, 0}, {0, 10, 0}};
    expectHit(world.castRay(up), id, up, {31, Real(0.5), 0}, {0, -1, 0});
}

TEST_F(EveryShape, CompoundChild) {
    // Two unit-half-extent boxes at x = -1.5 and x = +1.5 in the compound's
    // frame; the body at (40, 1, 0). A ray over x = 41.5 hits child 1's top (y = 2).
    const std::array<CompoundChild, 2> children{CompoundChild{Shape::box({Real(0.5), 1, Real(0.5)}), {{Real(-1.5), 0, 0}, {}}},
                                                CompoundChild{Shape::box({Real(0.5), 1, Real(0.5)}), {{Real(1.5), 0, 0}, {}}}};
    const BodyId id = addBody(world, Shape::compound(children), {40, 1, 0}, {}, BodyType::Dynamic);
    const Ray ray = downAt(Real(41.5), Real(0.2));
    const auto hit = world.castRay(ray);
    expectHit(hit, id, ray, {Real(41.5), 2, Real(0.2)}, {0, 1, 0});
    EXPECT_EQ(hit->child, 1u);
    // Between the children the ray passes through.
    EXPECT_FALSE(world.castRay(downAt(40, 0)).has_value());
}

TEST_F(EveryShape, StartsInsideHitsAtZero) {
    const BodyId id = addBody(world, Shape::box({1, 1, 1}), {0, 0, 0});
    const Ray ray{{Real(0.2), Real(0.1), 0}, {3, 0, 4}};
    const auto hit = world.castRay(ray);
    expectHit(hit, id, ray, ray.origin, Vec3{-3, 0, -4} / Real(5));
    EXPECT_EQ(hit->fraction, 0);
}

TEST_F(EveryShape, MaxFractionStopsShort) {
    // Sphere top at y = 1.5: a 10 m ray from y = 10 reaches it at fraction 0.85.
    addBody(world, Shape::sphere(Real(0.5)), {0, 1, 0});
    Ray ray = downAt(0, 0);
    ray.maxFraction = Real(0.84);
    EXPECT_FALSE(world.castRay(ray).has_value());
    EXPECT_TRUE(world.castRayAll(ray).empty());
    ray.maxFraction = Real(0.86);
    ASSERT_TRUE(world.castRay(ray).has_value());
    EXPECT_NEAR(world.castRay(ray)->fraction, Real(0.85), kFractionTol);
}

TEST_F(EveryShape, ZeroLengthRayIsAPointTest) {
    // maxFraction 0: the ray is its origin; it "hits" the solid bodies containing it,
    // static and moving alike.
    const BodyId ground = addBody(world, Shape::box({5, 1, 5}), {0, 0, 0});
    const BodyId ball = addBody(world, Shape::sphere(1), {0, Real(0.5), 0}, {}, BodyType::Dynamic);
    Ray ray{{0, Real(0.5), 0}, {1, 0, 0}, 0};
    const std::vector<RayCastHit> hits = world.castRayAll(ray);
    ASSERT_EQ(hits.size(), 2u);
    EXPECT_EQ(hits[0].body, ground);  // tie at 0: creation order
    EXPECT_EQ(hits[1].body, ball);
    ray.origin = {0, 3, 0};
    EXPECT_FALSE(world.castRay(ray).has_value());
}

// ---- all hits and filters -------------------------------------------------------------

class RowOfSpheres : public ::testing::Test {
protected:
    // Five spheres r = 0.5 at x = 0, 2, 4, 6, 8 (created in reverse, so creation
    // order differs from the order along the ray), a sensor at x = 3, and a ray
    // along +x from x = -5, 20 m long: sphere k is entered at x = 2k - 0.5,
    // fraction (2k + 4.5) / 20.
    void SetUp() override {
        for (int k = 4; k >= 0; --k) {
            BodyDef def;
            def.shape = Shape::sphere(Real(0.5));
            def.position = {static_cast<Real>(2 * k), 0, 0};
            def.filter.category = k % 2 == 0 ? 1u : 2u;
            spheres[static_cast<std::size_t>(k)] = world.createBody(def);
        }
        BodyDef sensor;
        sensor.shape = Shape::box({Real(0.2), 1, 1});
        sensor.position = {3, 0, 0};
        sensor.isSensor = true;
        sensorId = world.createBody(sensor);
    }
    static Real fractionOf(int k) { return (static_cast<Real>(2 * k) + Real(4.5)) / 20; }

    World world{WorldDef{.gravity = {0, 0, 0}}};
    std::array<BodyId, 5> spheres;
    BodyId sensorId;
    const Ray ray{{-5, 0, 0}, {20, 0, 0}};
};

TEST_F(RowOfSpheres, AllHitsSortedByFraction) {
    const std::vector<RayCastHit> hits = world.castRayAll(ray);
    ASSERT_EQ(hits.size(), 5u);  // the sensor is excluded by default
    for (std::size_t k = 0; k < 5; ++k) {
        EXPECT_EQ(hits[k].body, spheres[k]);
        EXPECT_NEAR(hits[k].fraction, fractionOf(static_cast<int>(k)), kFractionTol);
        expectVecNear(hits[k].normal, {-1, 0, 0}, kNormalTol, "normal");
    }
    const auto closest = world.castRay(ray);
    ASSERT_TRUE(closest.has_value());
    EXPECT_EQ(closest->body, spheres[0]);
}

TEST_F(RowOfSpheres, SensorsOnRequest) {
    QueryFilter f;
    f.includeSensors = true;
    const std::vector<RayCastHit> hits = world.castRayAll(ray, f);
    ASSERT_EQ(hits.size(), 6u);
    // The sensor's face at x = 2.8 comes between spheres 1 (x = 1.5) and 2 (x = 3.5).
    EXPECT_EQ(hits[2].body, sensorId);
    EXPECT_NEAR(hits[2].fraction, Real(7.8) / 20, kFractionTol);
}

TEST_F(RowOfSpheres, MaskAndCategory) {
    // Query mask 2 sees only the odd spheres (category 2).
    QueryFilter odd;
    odd.mask = 2;
    std::vector<RayCastHit> hits = world.castRayAll(ray, odd);
    ASSERT_EQ(hits.size(), 2u);
    EXPECT_EQ(hits[0].body, spheres[1]);
    EXPECT_EQ(hits[1].body, spheres[3]);
    EXPECT_EQ(world.castRay(ray, odd)->body, spheres[1]);
    // A body whose own mask excludes the query's category is not seen either.
    BodyDef blind;
    blind.shape = Shape::sphere(Real(0.5));
    blind.position = {-2, 0, 0};
    blind.filter.mask = ~4u;
    const BodyId blindId = world.createBody(blind);
    EXPECT_EQ(world.castRay(ray)->body, blindId);  // default category: all bits
    QueryFilter cat4;
    cat4.category = 4;
    EXPECT_EQ(world.castRay(ray, cat4)->body, spheres[0]);
}

TEST_F(RowOfSpheres, ExcludedBody) {
    QueryFilter f;
    f.excludeBody = spheres[0];
    EXPECT_EQ(world.castRay(ray, f)->body, spheres[1]);
    EXPECT_EQ(world.castRayAll(ray, f).size(), 4u);
}

TEST_F(RowOfSpheres, OutputVectorIsReused) {
    std::vector<RayCastHit> out(17);  // stale content is cleared
    world.castRayAll(ray, out);
    EXPECT_EQ(out.size(), 5u);
    const auto capacity = out.capacity();
    world.castRayAll(ray, out);
    EXPECT_EQ(out.capacity(), capacity);
}

TEST(RayCastTies, EqualFractionsGoToTheFirstCreated) {
    // Two identical spheres at the same place: the tie is broken by creation order,
    // whatever order the trees visit them in.
    World world{WorldDef{.gravity = {0, 0, 0}}};
    // The first is static and the second dynamic, so the moving tree (searched
    // first) finds the second one first.
    BodyDef def;
    def.shape = Shape::sphere(1);
    def.type = BodyType::Static;
    const BodyId first = world.createBody(def);
    def.type = BodyType::Dynamic;
    const BodyId second = world.createBody(def);
    const Ray ray{{0, 5, 0}, {0, -10, 0}};
    EXPECT_EQ(world.castRay(ray)->body, first);
    world.destroyBody(first);
    EXPECT_EQ(world.castRay(ray)->body, second);
}

}  // namespace
