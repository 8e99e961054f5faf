// Rounded shapes (docs/shapes.md, "Rounded shapes"): volume, mass and inertia
// against independent integrations of the Minkowski sum core + ball, bounds,
// ray casts and closest points against the analytic surface, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "collision/shape_cast.hpp"
#include "collision/shape_queries.hpp"
#include "collision/support.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {
namespace {

constexpr double kPi = std::numbers::pi;

// Moments of a solid symmetric about its centre: volume and the integrals of x^2, y^2, z^2.
struct Moments {
    double volume = 0, xx = 0, yy = 0, zz = 0;
};

// The rounded box (core half extents a, b, c; radius r) integrated over a
// grid in (y, z) with x done exactly: at (y, z) the solid spans |x| <= a +
// sqrt(r^2 - d^2), d the distance from (y, z) to the core's rectangle. The
// grid's outer cells line up with the bounds, so only the four rounded
// corners of the (y, z) shadow cost accuracy (about 1e-5 at n = 1200).
Moments integrateRoundedBox(double a, double b, double c, double r, int n) {
    Moments m;
    const double yMax = b + r, zMax = c + r, hy = 2 * yMax / n, hz = 2 * zMax / n;
    for (int i = 0; i < n; ++i) {
        const double y = -yMax + (i + 0.5) * hy;
        for (int k = 0; k < n; ++k) {
            const double z = -zMax + (k + 0.5) * hz;
            const double dy = std::max(0.0, std::fabs(y) - b), dz = std::max(0.0, std::fabs(z) - c);
            const double d2 = dy * dy + dz * dz;
            if (d2 > r * r) continue;
            const double x = a + std::sqrt(r * r - d2);
            const double cell = hy * hz;
            m.volume += 2 * x * cell;
            m.xx += 2 * x * x * x / 3 * cell;
            m.yy += 2 * x * y * y * cell;
            m.zz += 2 * x * z * z * cell;
        }
    }
    return m;
}

// The rounded cylinder (core radius p, core half height h, radius r) along y:
// at distance s from the axis the solid spans |y| <= Y(s); integrated over s
// with the ring measure 2 pi s. xx = zz = half the integral of s^2.
Moments integrateRoundedCylinder(double p, double h, double r, int n) {
    Moments m;
    const double sMax = p + r, ds = sMax / n;
    for (int i = 0; i < n; ++i) {
        const double s = (i + 0.5) * ds;
        const double y = s <= p ? h + r : h + std::sqrt(std::max(0.0, r * r - (s - p) * (s - p)));
        const double ring = 2 * kPi * s * ds;
        m.volume += 2 * y * ring;
        m.xx += 2 * y * s * s / 2 * ring;
        m.zz += 2 * y * s * s / 2 * ring;
        m.yy += 2 * y * y * y / 3 * ring;
    }
    return m;
}

void expectMassMatches(const Shape& shape, const Moments& ref, double density, double rel) {
    const MassProperties mp = shape.massProperties(Real(density));
    const double mass = ref.volume * density;
    EXPECT_NEAR(shape.volume(), ref.volume, rel * ref.volume);
    EXPECT_NEAR(mp.mass, mass, rel * mass);
    const double ix = density * (ref.yy + ref.zz), iy = density * (ref.xx + ref.zz), iz = density * (ref.xx + ref.yy);
    EXPECT_NEAR(mp.inertia(0, 0), ix, rel * ix);
    EXPECT_NEAR(mp.inertia(1, 1), iy, rel * iy);
    EXPECT_NEAR(mp.inertia(2, 2), iz, rel * iz);
    EXPECT_NEAR(mp.inertia(0, 1), 0, rel * ix);
    EXPECT_NEAR(mp.inertia(0, 2), 0, rel * ix);
    EXPECT_NEAR(mp.inertia(1, 2), 0, rel * ix);
    EXPECT_NEAR(length(mp.centerOfMass), 0, 1e-6);
}

TEST(RoundedShapes, BoxMassMatchesTheIntegratedMinkowskiSum) {
    // Outer half extents (0.5, 0.3, 0.2), radius 0.08: core (0.42, 0.22, 0.12).
    const double r = 0.08;
    const Shape box = Shape::roundedBox({Real(0.5), Real(0.3), Real(0.2)}, Real(r));
    expectMassMatches(box, integrateRoundedBox(0.5 - r, 0.3 - r, 0.2 - r, r, 1200), 700, 2e-4);
    // Closed-form volume: core + face slabs + edge quarter cylinders + corner ball.
    const double a = 0.42, b = 0.22, c = 0.12;
    const double v = 8 * a * b * c + 8 * r * (a * b + b * c + c * a) + 2 * kPi * r * r * (a + b + c) + 4.0 / 3 * kPi * r * r * r;
    EXPECT_NEAR(box.volume(), v, 1e-5 * v);
}

TEST(RoundedShapes, BoxLimitsAreTheBoxAndTheSphere) {
    const MassProperties plain = Shape::box({1, 2, 3}).massProperties(5);
    const MassProperties zero = Shape::roundedBox({1, 2, 3}, 0).massProperties(5);
    EXPECT_EQ(plain.mass, zero.mass);
    EXPECT_EQ(plain.inertia(0, 0), zero.inertia(0, 0));
    EXPECT_EQ(Shape::roundedBox({1, 2, 3}, 0).convexRadius(), 0);
    // A cube rounded by its half extent is a ball.
    const double r = 0.5;
    const MassProperties ball = Shape::roundedBox(Vec3::splat(Real(r)), Real(r)).massProperties(1);
    const double m = 4.0 / 3 * kPi * r * r * r;
    EXPECT_NEAR(ball.mass, m, 1e-5 * m);
    EXPECT_NEAR(ball.inertia(1, 1), 0.4 * m * r * r, 1e-5 * m * r * r);
}

TEST(RoundedShapes, CylinderMassMatchesTheIntegratedMinkowskiSum) {
    const double r = 0.1;
    const Shape cyl = Shape::roundedCylinder(Real(0.4), Real(0.6), Real(r));
    expectMassMatches(cyl, integrateRoundedCylinder(0.4 - r, 0.6 - r, r, 200000), 900, 1e-4);
    // Fully rounded (radius = half height): the core is a disc, still exact.
    const Shape puck = Shape::roundedCylinder(Real(0.5), Real(0.15), Real(0.15));
    expectMassMatches(puck, integrateRoundedCylinder(0.35, 0, 0.15, 200000), 1, 1e-4);
}

// The rounded hull's mass comes from a polyhedral stand-in (docs/shapes.md):
// a rounded box made as a hull of the core's corners is held to the exact
// rounded box within the documented 0.5 %.
TEST(RoundedShapes, HullMassApproximationIsWithinItsStatedError) {
    const Real r = Real(0.1);
    const Vec3 core{Real(0.4), Real(0.3), Real(0.2)};
    std::vector<Vec3> corners;
    for (int i = 0; i < 8; ++i) {
        corners.push_back({(i & 1) ? core.x : -core.x, (i & 2) ? core.y : -core.y, (i & 4) ? core.z : -core.z});
    }
    const Shape hull = Shape::roundedConvexHull(corners, r);
    const Shape box = Shape::roundedBox(core + Vec3::splat(r), r);
    const MassProperties h = hull.massProperties(1), b = box.massProperties(1);
    EXPECT_NEAR(h.mass, b.mass, 0.005 * b.mass);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(h.inertia(i, i), b.inertia(i, i), 0.005 * b.inertia(i, i));
    EXPECT_NEAR(length(h.centerOfMass), 0, 1e-3);
    // A rounded regular tetrahedron (edge a = 2 sqrt 2): Steiner's formula gives the exact volume,
    // V + A r + M r^2 + 4/3 pi r^3 (A the area, M the sum over edges of length x exterior angle / 2).
    const std::vector<Vec3> tet{{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}};
    const double edge = 2 * std::sqrt(2.0), exterior = kPi - std::acos(1.0 / 3);
    const double v0 = edge * edge * edge / (6 * std::sqrt(2.0)), area = std::sqrt(3.0) * edge * edge, mean = 6 * edge * exterior / 2;
    for (const double rt : {0.1, 0.5, 2.0}) {
        const double steiner = v0 + area * rt + mean * rt * rt + 4.0 / 3 * kPi * rt * rt * rt;
        EXPECT_NEAR(Shape::roundedConvexHull(tet, Real(rt)).volume(), steiner, 0.005 * steiner);
    }
    // Bounds: the core's grown by the radius.
    const AABB lb = hull.localBounds();
    EXPECT_NEAR(lb.max.x, core.x + r, 1e-6);
    EXPECT_NEAR(lb.min.y, -core.y - r, 1e-6);
}

TEST(RoundedShapes, BoundsAndSupportReachTheRoundedSurface) {
    const Shape box = Shape::roundedBox({Real(0.5), Real(0.3), Real(0.2)}, Real(0.1));
    const AABB lb = box.localBounds();
    EXPECT_NEAR(lb.max.x, 0.5, 1e-6);
    EXPECT_NEAR(lb.max.z, 0.2, 1e-6);
    // Rotated 45 degrees about z: the rounded corner reaches (core diagonal) + r, not the sharp corner.
    const Transform xf{{0, 0, 0}, Quat::fromAxisAngle({0, 0, 1}, Real(kPi / 4))};
    const AABB wb = box.bounds(xf);
    const double reach = (0.4 + 0.2) / std::sqrt(2.0) + 0.1;
    EXPECT_NEAR(wb.max.x, reach, 1e-5);
    const detail::ConvexShape c = detail::makeConvex(box, xf);
    EXPECT_NEAR(dot(c.support({1, 0, 0}), Vec3{1, 0, 0}), reach, 1e-5);
    Real lo, hi;
    c.extent({0, 1, 0}, lo, hi);
    EXPECT_NEAR(hi, reach, 1e-5);
    EXPECT_NEAR(lo, -reach, 1e-5);
    EXPECT_NEAR(c.boundingRadius(), length(Vec3{Real(0.4), Real(0.2), Real(0.1)}) + 0.1, 1e-6);
}

// Rays against the rounded box's face, edge and corner, and a rounded
// cylinder's rim: the analytic distances to the core's feature minus r.
TEST(RoundedShapes, RayCastHitsTheRoundedSurfaceAtTheAnalyticDistance) {
    const double r = 0.1, c = 0.4;  // cube of outer half extent 0.5
    const Shape box = Shape::roundedBox(Vec3::splat(Real(c + r)), Real(r));
    const Transform id = Transform::identity();
    {  // face: the flat part is where it was
        const auto hit = rayCastShape(box, id, {2, Real(0.1), 0}, {-1, 0, 0}, 10);
        ASSERT_TRUE(hit);
        EXPECT_NEAR(hit->fraction, 1.5, 1e-5);
        EXPECT_NEAR(hit->normal.x, 1, 1e-5);
    }
    {  // edge along z, hit along the diagonal of x and y: sqrt(2) (2 - c) - r
        const Vec3 d = normalize(Vec3{-1, -1, 0});
        const auto hit = rayCastShape(box, id, {2, 2, Real(0.1)}, d, 10);
        ASSERT_TRUE(hit);
        EXPECT_NEAR(hit->fraction, std::sqrt(2.0) * (2 - c) - r, 2e-5);
        EXPECT_NEAR(hit->normal.x, 1 / std::sqrt(2.0), 1e-4);
        EXPECT_NEAR(hit->normal.z, 0, 1e-4);
    }
    {  // corner along the main diagonal: sqrt(3) (2 - c) - r
        const Vec3 d = normalize(Vec3{-1, -1, -1});
        const auto hit = rayCastShape(box, id, {2, 2, 2}, d, 10);
        ASSERT_TRUE(hit);
        EXPECT_NEAR(hit->fraction, std::sqrt(3.0) * (2 - c) - r, 2e-5);
    }
    {  // a ray past the rounded corner that would clip the sharp one misses
        const Vec3 o{Real(0.49), 2, Real(0.49)};
        EXPECT_FALSE(rayCastShape(box, id, o, {0, -1, 0}, 10));
        EXPECT_TRUE(rayCastShape(Shape::box(Vec3::splat(Real(0.5))), id, o, {0, -1, 0}, 10));
    }
    {  // inside: fraction 0
        const auto hit = rayCastShape(box, id, {Real(0.45), 0, 0}, {1, 0, 0}, 10);
        ASSERT_TRUE(hit);
        EXPECT_EQ(hit->fraction, 0);
    }
    {  // rounded cylinder (outer radius 0.5, half height 0.5, r 0.1): the rim at 45 degrees in (x, y)
        const Shape cyl = Shape::roundedCylinder(Real(0.5), Real(0.5), Real(r));
        const Vec3 d = normalize(Vec3{-1, -1, 0});
        const auto hit = rayCastShape(cyl, id, {2, 2, 0}, d, 10);
        ASSERT_TRUE(hit);
        EXPECT_NEAR(hit->fraction, std::sqrt(2.0) * (2 - c) - r, 2e-5);
    }
    {  // rounded hull: a tetrahedron's vertex (1, 1, 1) from along its diagonal
        const std::vector<Vec3> tet{{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}};
        const Shape hull = Shape::roundedConvexHull(tet, Real(0.2));
        const auto hit = rayCastShape(hull, id, {3, 3, 3}, normalize(Vec3{-1, -1, -1}), 10);
        ASSERT_TRUE(hit);
        EXPECT_NEAR(hit->fraction, std::sqrt(3.0) * 2 - 0.2, 2e-5);
    }
}

// Shape casts see core + radius: a sphere (radius 0.2) cast onto the rounded
// cube's face and, along the diagonal, onto its rounded edge; and a rounded
// box inside a compound cast onto a plane stops at its rounded corner.
TEST(RoundedShapes, ShapeCastStopsAtTheRoundedSurface) {
    const Shape box = Shape::roundedBox(Vec3::splat(Real(0.5)), Real(0.1));
    const Shape ball = Shape::sphere(Real(0.2));
    const Transform id = Transform::identity();
    const ShapeCastResult face = shapeCast(ball, Transform({0, 3, 0}, {}), {0, -5, 0}, box, id);
    ASSERT_TRUE(face.hit);
    EXPECT_NEAR(face.fraction * 5, 3 - 0.7, 2e-4);
    // Edge: the centre stops 0.3 from the core's edge line (0.4, 0.4, z).
    const ShapeCastResult edge = shapeCast(ball, Transform({2, 2, 0}, {}), {-4, -4, 0}, box, id);
    ASSERT_TRUE(edge.hit);
    EXPECT_NEAR(edge.fraction, (2 - 0.4 - 0.3 / std::sqrt(2.0)) / 4, 1e-4);
    // A compound holding the rounded cube turned 45 degrees about z, dropped on the plane y = 0:
    // its lowest point is 0.4 sqrt 2 + 0.1 below its centre.
    const CompoundChild child{box, Transform({0, 0, 0}, Quat::fromAxisAngle({0, 0, 1}, Real(kPi / 4)))};
    const Shape compound = Shape::compound({&child, 1});
    const ShapeCastResult drop = shapeCast(compound, Transform({0, 2, 0}, {}), {0, -2, 0}, Shape::plane({0, 1, 0}, 0), id);
    ASSERT_TRUE(drop.hit);
    EXPECT_NEAR(2 - drop.fraction * 2, 0.4 * std::sqrt(2.0) + 0.1, 2e-4);
}

TEST(RoundedShapes, ClosestPointIsTheCoresMovedOutByTheRadius) {
    const Shape box = Shape::roundedBox(Vec3::splat(Real(0.5)), Real(0.1));
    const PointQuery q = closestPoint(box, Transform::identity(), {1, 1, 0});
    EXPECT_NEAR(q.distance, std::sqrt(2.0) * 0.6 - 0.1, 1e-5);
    EXPECT_NEAR(q.point.x, 0.4 + 0.1 / std::sqrt(2.0), 1e-5);
    const PointQuery inside = closestPoint(box, Transform::identity(), {Real(0.3), 0, 0});
    EXPECT_NEAR(inside.distance, -0.2, 1e-6);
    EXPECT_NEAR(inside.point.x, 0.5, 1e-6);
}

void expectErrorNaming(auto&& make, const std::string& field) {
    try {
        (void)make();
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
}

TEST(RoundedShapes, BadRadiusIsAClearError) {
    const Real nan = std::numeric_limits<Real>::quiet_NaN();
    expectErrorNaming([] { return Shape::roundedBox({1, Real(0.3), 1}, Real(-0.1)); }, "convex_radius");
    expectErrorNaming([] { return Shape::roundedBox({1, Real(0.3), 1}, Real(0.31)); }, "smallest half extent");
    expectErrorNaming([&] { return Shape::roundedBox({1, 1, 1}, nan); }, "convex_radius");
    expectErrorNaming([] { return Shape::roundedCylinder(Real(0.2), 1, Real(0.25)); }, "convex_radius");
    expectErrorNaming([&] { return Shape::roundedCylinder(1, 1, nan); }, "convex_radius");
    const std::vector<Vec3> tet{{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}};
    expectErrorNaming([&] { return Shape::roundedConvexHull(tet, Real(-1)); }, "convex_radius");
    expectErrorNaming([&] { return Shape::roundedConvexHull(tet, std::numeric_limits<Real>::infinity()); }, "convex_radius");
    // At the limit: allowed (a flat core).
    EXPECT_NO_THROW((void)Shape::roundedBox({1, Real(0.3), 1}, Real(0.3)));
}

}  // namespace
}  // namespace fulcrum
