// Heightfields: the shape's validation and layout, and ray casts, shape casts,
// overlaps and closest points against the analytic surface.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "collision/heightfield.hpp"
#include "collision/shape_queries.hpp"
#include "fulcrum/fulcrum.hpp"

using namespace fulcrum;
using ::testing::HasSubstr;

namespace {

// The smooth terrain sampled by the fields below (field-local x, z).
Real hills(Real x, Real z) { return Real(0.5) * std::sin(Real(0.9) * x) + Real(0.3) * std::cos(Real(0.6) * z + Real(0.2) * x); }

struct Field {
    std::uint32_t rows, columns;
    Real dx, dz;
    std::vector<Real> heights;
    Shape shape;
};

Field hillField(std::uint32_t rows, std::uint32_t columns, Real dx, Real dz, std::vector<std::uint32_t> holes = {}) {
    Field f{rows, columns, dx, dz, {}, {}};
    for (std::uint32_t r = 0; r < rows; ++r) {
        for (std::uint32_t c = 0; c < columns; ++c) f.heights.push_back(hills(static_cast<Real>(c) * dx, static_cast<Real>(r) * dz));
    }
    f.shape = Shape::heightField(rows, columns, dx, dz, f.heights, holes);
    return f;
}

// The surface the two documented triangles of each cell span, computed from
// the samples here independently of the engine: the cell's diagonal runs from
// sample (r, c) to (r + 1, c + 1).
Real piecewiseLinear(const Field& f, Real x, Real z, std::uint32_t* triangle = nullptr) {
    const Real u = x / f.dx, w = z / f.dz;
    const auto c = static_cast<std::uint32_t>(u), r = static_cast<std::uint32_t>(w);
    const Real fu = u - static_cast<Real>(c), fw = w - static_cast<Real>(r);
    const auto h = [&](std::uint32_t rr, std::uint32_t cc) { return f.heights[rr * f.columns + cc]; };
    const Vec3 p00{0, h(r, c), 0}, p10{0, h(r + 1, c), 1}, p11{1, h(r + 1, c + 1), 1}, p01{1, h(r, c + 1), 0};
    const std::uint32_t cell = r * (f.columns - 1) + c;
    if (fw >= fu) {  // triangle (r, c), (r + 1, c), (r + 1, c + 1): barycentric in the unit cell
        if (triangle) *triangle = 2 * cell;
        return p00.y + fw * (p10.y - p00.y) + fu * (p11.y - p10.y);
    }
    if (triangle) *triangle = 2 * cell + 1;
    return p00.y + fu * (p01.y - p00.y) + fw * (p11.y - p01.y);
}

}  // namespace

TEST(HeightFieldShape, LayoutBoundsAndStaticOnly) {
    const std::vector<Real> h = {0, 1, 2, 3, 4, 5};  // 2 rows x 3 columns
    const Shape s = Shape::heightField(2, 3, Real(0.5), 2, h);
    EXPECT_EQ(s.type(), ShapeType::HeightField);
    EXPECT_STREQ(toString(s.type()), "heightfield");
    EXPECT_TRUE(s.staticOnly());
    const HeightField& f = s.heightField();
    EXPECT_EQ(f.cellRows(), 1u);
    EXPECT_EQ(f.cellColumns(), 2u);
    EXPECT_EQ(f.sample(1, 2), Vec3(1, 5, 2));  // (c dx, heights[r C + c], r dz)
    Vec3 v[3];
    f.triangle(2, v);  // cell 1's first triangle: (0, 1), (1, 1), (1, 2)
    EXPECT_EQ(v[0], Vec3(Real(0.5), 1, 0));
    EXPECT_EQ(v[1], Vec3(Real(0.5), 4, 2));
    EXPECT_EQ(v[2], Vec3(1, 5, 2));
    EXPECT_GT(cross(v[1] - v[0], v[2] - v[0]).y, 0);  // front faces point up
    f.triangle(3, v);
    EXPECT_GT(cross(v[1] - v[0], v[2] - v[0]).y, 0);
    const AABB b = s.localBounds();
    EXPECT_EQ(b.min, Vec3(0, 0, 0));
    EXPECT_EQ(b.max, Vec3(1, 5, 2));
    EXPECT_THROW((void)s.massProperties(1), Error);
    EXPECT_EQ(s.volume(), 0);
    BodyDef d;
    d.shape = s;
    World world;
    EXPECT_THROW(world.createBody(d), Error);  // dynamic
    d.type = BodyType::Static;
    EXPECT_NO_THROW(world.createBody(d));
}

TEST(HeightFieldShape, BadInputNamesTheField) {
    const std::vector<Real> four = {0, 0, 0, 0};
    const auto message = [](auto&& make) {
        try {
            make();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    std::vector<Real> nan = four;
    nan[2] = std::numeric_limits<Real>::quiet_NaN();
    EXPECT_THAT(message([&] { Shape::heightField(2, 2, 1, 1, nan); }), HasSubstr("heightfield: heights[2] (row 1, column 0) is not finite"));
    std::vector<Real> inf = four;
    inf[3] = std::numeric_limits<Real>::infinity();
    EXPECT_THAT(message([&] { Shape::heightField(2, 2, 1, 1, inf); }), HasSubstr("heights[3]"));
    EXPECT_THAT(message([&] { Shape::heightField(2, 3, 1, 1, four); }),
                HasSubstr("heightfield: heights has 4 values, rows * columns = 2 * 3 = 6"));
    EXPECT_THAT(message([&] { Shape::heightField(2, 2, 0, 1, four); }), HasSubstr("heightfield: spacing x must be a positive"));
    EXPECT_THAT(message([&] { Shape::heightField(2, 2, 1, -1, four); }), HasSubstr("heightfield: spacing z must be a positive"));
    EXPECT_THAT(message([&] { Shape::heightField(2, 2, std::numeric_limits<Real>::quiet_NaN(), 1, four); }), HasSubstr("spacing x"));
    EXPECT_THAT(message([&] { Shape::heightField(1, 4, 1, 1, four); }), HasSubstr("heightfield: rows must be between 2 and 4097, got 1"));
    EXPECT_THAT(message([&] { Shape::heightField(4, 1, 1, 1, four); }), HasSubstr("heightfield: columns must be between 2"));
    EXPECT_THAT(message([&] { Shape::heightField(100000, 100000, 1, 1, four); }), HasSubstr("rows must be between 2 and 4097"));
    // The size limit (kMaxShapeCoordinate, 1e12 m): at it, fine; a finite extent beyond it is refused.
    EXPECT_THAT(message([&] { Shape::heightField(2, 2, Real(1e12), 1, std::vector<Real>(4, 0)); }), HasSubstr("no error"));
    EXPECT_THAT(message([&] { Shape::heightField(2, 2, Real(1e38), 1, std::vector<Real>(4, 0)); }),
                HasSubstr("heightfield: spacing times the number of cells is beyond the limit of 1e12 m"));
    // The extent (spacing x (columns - 1)) overflows Real: 3e38 x 2 in float, 1.5e308 x 2 in double.
    const Real hugeSpacing = sizeof(Real) == sizeof(float) ? Real(3e38) : Real(1.5e308);
    EXPECT_THAT(message([&] { Shape::heightField(2, 3, hugeSpacing, 1, std::vector<Real>(6, 0)); }), HasSubstr("overflows"));
    const std::uint32_t badHole[] = {1};
    EXPECT_THAT(message([&] { Shape::heightField(2, 2, 1, 1, four, badHole); }),
                HasSubstr("heightfield: holes[0] = 1 is not a cell index (the field has 1 cells)"));
    const std::uint32_t allHoles[] = {0};
    EXPECT_THAT(message([&] { Shape::heightField(2, 2, 1, 1, four, allHoles); }), HasSubstr("every cell is a hole"));
}

// Vertical rays at many points land on the piecewise-linear surface of the
// documented triangulation (within float rounding, 1e-5 m), report the
// triangle of that point, and come within the sampling error of the smooth
// terrain (its curvature |h''| <= 0.55 /m^2 gives |error| <= h'' s^2 / 4).
TEST(HeightFieldQueries, RayCastsLandOnTheDocumentedSurface) {
    const Field f = hillField(41, 33, Real(0.25), Real(0.3));
    const Transform xf({3, -1, 2}, Quat::fromAxisAngle({0, 1, 0}, Real(0.4)));
    World world;
    BodyDef d;
    d.type = BodyType::Static;
    d.shape = f.shape;
    d.position = xf.p;
    d.orientation = xf.q;
    const BodyId body = world.createBody(d);
    int hits = 0;
    for (int i = 0; i < 200; ++i) {
        // Deterministic points inside the field (golden-ratio sequence).
        const Real x = std::fmod(Real(0.618034) * static_cast<Real>(i) + Real(0.1), Real(1)) * Real(7.9) + Real(0.02);
        const Real z = std::fmod(Real(0.414214) * static_cast<Real>(i) + Real(0.3), Real(1)) * Real(11.9) + Real(0.02);
        std::uint32_t triangle = 0;
        const Real expected = piecewiseLinear(f, x, z, &triangle);
        const Vec3 top = transformPoint(xf, {x, 5, z});
        const auto hit = world.castRay({top, rotate(xf.q, {0, -10, 0}), 1});
        ASSERT_TRUE(hit.has_value()) << i;
        EXPECT_EQ(hit->body, body);
        const Vec3 local = inverseTransformPoint(xf, hit->point);
        EXPECT_NEAR(local.y, expected, Real(1e-5)) << x << " " << z;
        EXPECT_NEAR(local.y, hills(x, z), Real(0.55) * Real(0.3) * Real(0.3) / 4 + Real(1e-5));
        // Exactly on a diagonal either triangle is right.
        const Real u = x / f.dx - std::floor(x / f.dx), w = z / f.dz - std::floor(z / f.dz);
        if (std::fabs(u - w) > Real(1e-3)) {
            EXPECT_EQ(hit->triangle, triangle) << x << " " << z;
        }
        EXPECT_GT(dot(hit->normal, rotate(xf.q, {0, 1, 0})), 0);  // against the ray: up
        EXPECT_NEAR(length(hit->normal), 1, Real(1e-5));
        ++hits;
    }
    EXPECT_EQ(hits, 200);
}

// Oblique rays: the hit point lies on the surface and no earlier point of the
// segment is under it (the first crossing); rays from below hit the back side;
// a ray over a hole or beside the field misses.
TEST(HeightFieldQueries, ObliqueRaysBackSidesHolesAndMisses) {
    // Hole: cell (2, 3) of 12 columns -> 2 * 11 + 3 = 25.
    const Field f = hillField(10, 12, Real(0.5), Real(0.5));
    const Field holed = hillField(10, 12, Real(0.5), Real(0.5), {25});
    const Transform xf;
    for (int i = 0; i < 50; ++i) {
        const Real a = Real(0.13) * static_cast<Real>(i);
        const Vec3 origin{Real(2.5) + std::cos(a), 3, Real(2.2) + std::sin(a)};
        const Vec3 dir{std::sin(a) * Real(1.5), -4, std::cos(a) * Real(1.2)};
        const auto hit = rayCastShape(f.shape, xf, origin, dir, 1);
        ASSERT_TRUE(hit.has_value()) << i;
        Real surface = 0;
        ASSERT_TRUE(detail::heightFieldSurface(f.shape.heightField(), hit->point.x, hit->point.z, surface));
        EXPECT_NEAR(hit->point.y, surface, Real(1e-4));
        for (int k = 0; k < 100; ++k) {
            const Vec3 p = origin + dir * (hit->fraction * static_cast<Real>(k) / 100);
            Real below = 0;
            if (detail::heightFieldSurface(f.shape.heightField(), p.x, p.z, below)) {
                EXPECT_GE(p.y, below - Real(1e-4));
            }
        }
    }
    const auto fromBelow = rayCastShape(f.shape, xf, {1, -5, 1}, {0, 10, 0}, 1);
    ASSERT_TRUE(fromBelow.has_value());
    EXPECT_LT(fromBelow->normal.y, 0);
    // Through the middle of the hole (x in [1.5, 2], z in [1, 1.5]).
    EXPECT_FALSE(rayCastShape(holed.shape, xf, {Real(1.75), 5, Real(1.25)}, {0, -10, 0}, 1).has_value());
    EXPECT_TRUE(rayCastShape(f.shape, xf, {Real(1.75), 5, Real(1.25)}, {0, -10, 0}, 1).has_value());
    EXPECT_TRUE(rayCastShape(holed.shape, xf, {Real(2.25), 5, Real(1.25)}, {0, -10, 0}, 1).has_value());  // next cell
    EXPECT_FALSE(rayCastShape(f.shape, xf, {-1, 5, 1}, {0, -10, 0}, 1).has_value());
    EXPECT_FALSE(rayCastShape(f.shape, xf, {1, 5, 1}, {0, -1, 0}, Real(0.5)).has_value());  // stops short
    // A ray grazing along the whole field, just above its top, misses; just below its bottom too.
    const AABB b = f.shape.localBounds();
    EXPECT_FALSE(rayCastShape(f.shape, xf, {-1, b.max.y + Real(0.01), 2}, {20, 0, 0}, 1).has_value());
}

// A big field costs a ray no more than a path's cells: a 1025 x 1025 field
// answers rays with the same hits as the analytic surface.
TEST(HeightFieldQueries, LargeFieldRayCasts) {
    const Field f = hillField(1025, 1025, Real(0.1), Real(0.1));
    for (int i = 0; i < 20; ++i) {
        const Real x = Real(3.7) * static_cast<Real>(i) + Real(0.33), z = Real(101.9) - Real(4.1) * static_cast<Real>(i);
        const auto hit = rayCastShape(f.shape, Transform(), {x, 10, z}, {0, -20, 0}, 1);
        ASSERT_TRUE(hit.has_value());
        EXPECT_NEAR(hit->point.y, piecewiseLinear(f, x, z), Real(1e-4));
    }
}

// Shape casts: a sphere dropped straight down stops one radius above the
// surface under it; overlaps find the field only when touching it.
TEST(HeightFieldQueries, ShapeCastsAndOverlaps) {
    World world;
    std::vector<Real> flat(9 * 9, Real(2));
    BodyDef d;
    d.type = BodyType::Static;
    d.shape = Shape::heightField(9, 9, 1, 1, flat);
    d.position = {-4, 0, -4};
    const BodyId field = world.createBody(d);
    const Shape ball = Shape::sphere(Real(0.5));
    const auto hit = world.castShape(ball, Transform({Real(0.3), 10, Real(-0.2)}, Quat{}), {0, -10, 0});
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->body, field);
    EXPECT_NEAR(10 - 10 * hit->fraction, Real(2.5), Real(0.01));
    EXPECT_NEAR(hit->normal.y, 1, Real(1e-3));
    const Shape box = Shape::box(Vec3::splat(Real(0.5)));
    EXPECT_EQ(world.overlapShape(box, Transform({0, Real(2.4), 0}, Quat{})).size(), 1u);
    EXPECT_TRUE(world.overlapShape(box, Transform({0, Real(2.6), 0}, Quat{})).empty());
    EXPECT_EQ(world.overlapSphere({1, Real(2.3), 1}, Real(0.4)).size(), 1u);
    EXPECT_TRUE(world.overlapSphere({1, Real(2.5), 1}, Real(0.4)).empty());
    EXPECT_TRUE(world.overlapSphere({10, Real(2), 1}, Real(0.4)).empty());  // beside the field
}

// Closest points (what ropes and cloth use): the distance to the surface,
// signed negative under it, with an outward normal.
TEST(HeightFieldQueries, ClosestPointsAreSigned) {
    const Field f = hillField(21, 21, Real(0.5), Real(0.5));
    const Transform xf;
    const Real x = Real(4.1), z = Real(5.3);
    const Real h = piecewiseLinear(f, x, z);
    const PointQuery above = closestPoint(f.shape, xf, {x, h + Real(0.2), z});
    EXPECT_GT(above.distance, 0);
    EXPECT_LE(above.distance, Real(0.2) + Real(1e-5));
    EXPECT_GT(above.distance, Real(0.1));  // slopes here are below 1: the distance is not far below 0.2
    EXPECT_GT(above.normal.y, 0);
    const PointQuery below = closestPoint(f.shape, xf, {x, h - Real(0.1), z});
    EXPECT_LT(below.distance, 0);
    EXPECT_GE(below.distance, -Real(0.1) - Real(1e-5));
    EXPECT_GT(below.normal.y, 0);  // outward, up
    // Far above the field's middle: the nearest surface point is found (the search grows).
    const PointQuery far = closestPoint(f.shape, xf, {5, 100, 5});
    EXPECT_NEAR(far.distance, 100 - f.shape.localBounds().max.y, 1);
    EXPECT_GT(far.distance, 90);
}

// Ropes and cloth rest on a heightfield instead of falling through it.
TEST(HeightFieldQueries, ClothRestsOnField) {
    World world;
    std::vector<Real> heights;
    for (int r = 0; r < 11; ++r) {
        for (int c = 0; c < 11; ++c) heights.push_back(Real(0.05) * static_cast<Real>(c));
    }
    BodyDef d;
    d.type = BodyType::Static;
    d.shape = Shape::heightField(11, 11, Real(0.5), Real(0.5), heights);
    d.position = {-Real(2.5), 0, -Real(2.5)};
    world.createBody(d);
    ClothDef cloth;
    cloth.origin = {-1, 2, -1};
    cloth.size = {11, 11};
    cloth.spacing = Real(0.2);
    cloth.radius = Real(0.03);
    const ParticleSystemId id = world.createCloth(cloth);
    for (int i = 0; i < 240; ++i) world.step(Real(1) / 60);
    const std::span<const Vec3> positions = world.particlePositions(id);
    ASSERT_FALSE(positions.empty());
    for (const Vec3& p : positions) {
        const Real surface = Real(0.05) * (p.x + Real(2.5)) / Real(0.5);
        EXPECT_GT(p.y, surface);  // above, by about the particle radius
        EXPECT_LT(p.y, surface + Real(0.2));
    }
}
