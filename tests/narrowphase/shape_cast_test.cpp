// Shape casts and time of impact against analytic hit times. Tolerance: the
// cast stops within 1e-4 m of contact, so the fraction is within 1e-4 / |d|.
#include <gtest/gtest.h>

#include "collision/gjk.hpp"
#include "collision/shape_cast.hpp"
#include "collision/support.hpp"
#include "helpers.hpp"

using namespace fulcrum;
using fulcrum::test::expectVecNear;

TEST(ShapeCast, SphereAtBoxHitsAtTheAnalyticFraction) {
    // Centre from x = -5 along +10: touches the face x = -1 when the centre is at -1.5.
    const ShapeCastResult r = shapeCast(Shape::sphere(0.5f), {{-5, 0.3f, 0.2f}, {}}, {10, 0, 0}, Shape::box({1, 1, 1}), {});
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.fraction, 0.35f, 2e-5f);
    expectVecNear(r.normal, {1, 0, 0}, 1e-4f);
    expectVecNear(r.point, {-1, 0.3f, 0.2f}, 2e-4f);
    // Towards the corner along the diagonal: first touch when |c - corner| = r.
    const Vec3 dir = normalize(Vec3{1, 1, 1});
    const Vec3 start = Vec3{1, 1, 1} + dir * 4;
    const ShapeCastResult c = shapeCast(Shape::sphere(0.5f), {start, {}}, -dir * 8, Shape::box({1, 1, 1}), {});
    ASSERT_TRUE(c.hit);
    EXPECT_NEAR(c.fraction, 3.5f / 8, 2e-5f);
    expectVecNear(c.normal, -dir, 1e-3f);
}

TEST(ShapeCast, SphereAtPlaneAndMissesAndStartsInContact) {
    const Shape ground = Shape::plane({0, 1, 0}, 0);
    const ShapeCastResult r = shapeCast(Shape::sphere(0.5f), {{1, 5, 2}, {}}, {0, -10, 0}, ground, {});
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.fraction, 0.45f, 1e-6f);
    expectVecNear(r.normal, {0, -1, 0}, 1e-6f);
    expectVecNear(r.point, {1, 0, 2}, 1e-5f);
    // Moving away or falling short: no hit.
    EXPECT_FALSE(shapeCast(Shape::sphere(0.5f), {{1, 5, 2}, {}}, {0, 10, 0}, ground, {}).hit);
    EXPECT_FALSE(shapeCast(Shape::sphere(0.5f), {{1, 5, 2}, {}}, {0, -4, 0}, ground, {}).hit);
    EXPECT_FALSE(shapeCast(Shape::sphere(0.5f), {{-5, 3, 0}, {}}, {10, 0, 0}, Shape::box({1, 1, 1}), {}).hit);
    // Already touching: fraction 0.
    const ShapeCastResult z = shapeCast(Shape::box({1, 1, 1}), {{0, 0.99f, 0}, {}}, {1, 0, 0}, ground, {});
    ASSERT_TRUE(z.hit);
    EXPECT_EQ(z.fraction, 0);
}

TEST(ShapeCast, BoxAndCapsuleAgainstMeshAndCompound) {
    const TriangleMesh m = test::flatGrid(4, 1);
    const Shape grid = Shape::mesh(m.vertices, m.triangles);
    // Capsule lying, falling 3 m onto the grid from bottom at y = 2.
    const ShapeCastResult r = shapeCast(Shape::capsule(0.2f, 0.5f), {{0.1f, 2.2f, 0.3f}, Quat::fromAxisAngle({0, 0, 1}, 1.5707963f)},
                                        {0, -3, 0}, grid, {});
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.fraction, 2.0f / 3, 5e-5f);
    // A compound dumbbell against a box: the lower child hits first.
    const CompoundChild kids[2] = {{Shape::sphere(0.25f), {{0, -1, 0}, {}}}, {Shape::sphere(0.25f), {{0, 1, 0}, {}}}};
    const ShapeCastResult c = shapeCast(Shape::compound(kids), {{0, 5, 0}, {}}, {0, -5, 0}, Shape::box({1, 1, 1}), {});
    ASSERT_TRUE(c.hit);
    EXPECT_NEAR(c.fraction, (5 - 1 - 0.25f - 1) / 5, 3e-5f);
}

TEST(Toi, ApproachingSpheresMeetAtTheAnalyticTime) {
    Sweep a, b;
    a.start = {{-3, 0, 0}, {}};
    a.linearVelocity = {2, 0, 0};
    b.start = {{3, 0.5f, 0}, {}};
    b.linearVelocity = {-1, 0, 0};
    // Gap |(6 - 3t, 0.5)| = 1.5 -> 6 - 3t = sqrt(2.25 - 0.25) -> t = (6 - sqrt 2) / 3.
    const ToiResult r = timeOfImpact(Shape::sphere(1), a, Shape::sphere(0.5f), b, 5);
    ASSERT_EQ(r.state, ToiResult::State::Hit);
    EXPECT_NEAR(r.time, (6 - std::sqrt(2.0f)) / 3, 1e-4f);
}

TEST(Toi, SpinningBoxNeverPassesTheContactAndStopsAtIt) {
    // A long thin box spinning fast and drifting towards another box: the
    // reported time must have the shapes touching (gap within tolerance), and
    // densely sampled earlier times must all be separated (conservative).
    Sweep a, b;
    a.start = {{-2, 0, 0}, {}};
    a.linearVelocity = {1, 0, 0};
    a.angularVelocity = {0, 0, 10};
    b.start = {{1.5f, 0, 0}, {}};
    const Shape bar = Shape::box({1, 0.1f, 0.1f}), block = Shape::box({0.5f, 0.5f, 0.5f});
    const ToiResult r = timeOfImpact(bar, a, block, b, 3);
    ASSERT_EQ(r.state, ToiResult::State::Hit);
    auto gap = [&](Real t) {
        const detail::GjkResult g = detail::gjkDistance(detail::makeConvex(bar, a.at(t)), detail::makeConvex(block, b.at(t)), false);
        return g.overlap ? Real(0) : g.distance;
    };
    EXPECT_LT(gap(r.time), 2e-4f);
    for (int i = 0; i < 400; ++i) {
        const Real t = r.time * static_cast<Real>(i) / 400;
        EXPECT_GT(gap(t), 0) << "t " << t;
    }
}
