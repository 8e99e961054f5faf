// A capsule against one triangle (collideTriangleCapsule, the mesh path's
// capsule test): the core segment's closest points to the triangle against a
// brute-force reference (the distance of the segment's points to the
// triangle, minimised over the segment: a convex function of the segment's
// parameter), and the contact against the general path it replaces
// (collideConvexConvex: GJK, EPA, face clipping).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "collision/collide_pairs.hpp"
#include "collision/support.hpp"

using namespace fulcrum;

namespace {

struct V {
    double x, y, z;
};
V toV(const Vec3& p) { return {double(p.x), double(p.y), double(p.z)}; }
V operator-(V a, V b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V operator+(V a, V b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V operator*(V a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dotV(V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V crossV(V a, V b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

// Distance of p to the triangle, in double: the projection on the plane
// when it falls inside, else the nearest of the three edges.
double pointTriangleDistance(V p, const V t[3]) {
    const V n = crossV(t[1] - t[0], t[2] - t[0]);
    const double nn = dotV(n, n);
    const V q = p - n * (dotV(p - t[0], n) / nn);
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
        if (dotV(crossV(t[(k + 1) % 3] - t[k], q - t[k]), n) < 0) inside = false;
    }
    if (inside) return std::sqrt(dotV(p - q, p - q));
    double best = 1e300;
    for (int k = 0; k < 3; ++k) {
        const V a = t[k], e = t[(k + 1) % 3] - t[k];
        const double s = std::clamp(dotV(p - a, e) / dotV(e, e), 0.0, 1.0);
        const V c = a + e * s;
        best = std::min(best, std::sqrt(dotV(p - c, p - c)));
    }
    return best;
}

// The segment's distance to the triangle: 400 samples, then a golden-section
// search around the best (the distance is convex along the segment).
double segmentTriangleDistance(V p0, V p1, const V t[3]) {
    const auto at = [&](double s) { return pointTriangleDistance(p0 + (p1 - p0) * s, t); };
    constexpr int kSamples = 400;
    int bestI = 0;
    double best = at(0);
    for (int i = 1; i <= kSamples; ++i) {
        const double d = at(double(i) / kSamples);
        if (d < best) {
            best = d;
            bestI = i;
        }
    }
    double lo = std::max(0.0, double(bestI - 1) / kSamples), hi = std::min(1.0, double(bestI + 1) / kSamples);
    const double g = (std::sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 80; ++it) {
        const double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
        if (at(a) < at(b)) {
            hi = b;
        } else {
            lo = a;
        }
    }
    return std::min(best, at(0.5 * (lo + hi)));
}

Vec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<float> g(0, 1);
    for (;;) {
        const Vec3 v{g(rng), g(rng), g(rng)};
        if (lengthSquared(v) > Real(1e-4)) return normalize(v);
    }
}

detail::ConvexShape capsule(const Vec3& centre, const Vec3& axis, Real halfHeight, Real radius) {
    Shape s = Shape::capsule(radius, halfHeight);
    // The capsule's local y axis turned onto `axis`.
    const Vec3 y{0, 1, 0};
    const Vec3 c = cross(y, axis);
    const Real w = 1 + dot(y, axis);
    const Quat q = w > Real(1e-6) ? normalize(Quat{w, c.x, c.y, c.z}) : Quat{0, 1, 0, 0};
    return detail::makeConvex(s, Transform{centre, q});
}

}  // namespace

// The closest points against the brute-force distance, over random
// triangles and segments (crossing, touching, far, parallel to the face).
TEST(CapsuleTriangle, ClosestPointsMatchBruteForce) {
    std::mt19937 rng(2026);
    std::uniform_real_distribution<float> u(-1, 1);
    int apartCount = 0, crossingCount = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        Vec3 tri[3];
        for (auto& v : tri) v = {2 * u(rng), Real(0.3) * u(rng), 2 * u(rng)};
        Vec3 p0{2 * u(rng), u(rng), 2 * u(rng)};
        Vec3 p1 = p0 + randomUnit(rng) * (Real(0.1) + Real(1.5) * std::fabs(u(rng)));
        if (trial % 4 == 0) p1.y = p0.y;  // level: lying parallel to a flat-ish face
        const V t[3] = {toV(tri[0]), toV(tri[1]), toV(tri[2])};
        const double ref = segmentTriangleDistance(toV(p0), toV(p1), t);
        Vec3 onSegment, onTriangle;
        const bool apart = detail::closestSegmentTriangle(p0, p1, tri, onSegment, onTriangle);
        if (!apart) {
            ++crossingCount;
            EXPECT_LT(ref, 1e-4) << "trial " << trial;
            continue;
        }
        ++apartCount;
        const double got = std::sqrt(double(lengthSquared(onSegment - onTriangle)));
        EXPECT_NEAR(got, ref, 1e-4) << "trial " << trial;
        // The points lie on their shapes.
        EXPECT_LT(pointTriangleDistance(toV(onTriangle), t), 1e-4) << "trial " << trial;
        const V d = toV(p1) - toV(p0), w = toV(onSegment) - toV(p0);
        const double s = dotV(w, d) / dotV(d, d);
        EXPECT_GT(s, -1e-5);
        EXPECT_LT(s, 1 + 1e-5);
        const V off = w - d * s;
        EXPECT_LT(std::sqrt(dotV(off, off)), 1e-4) << "trial " << trial;
    }
    // Both kinds were exercised.
    EXPECT_GT(apartCount, 1000);
    EXPECT_GT(crossingCount, 20);
}

// The contact against the general path (GJK, EPA, clipping) and against the
// reference depth (radius less the cores' distance), capsules near a
// triangle in every pose.
TEST(CapsuleTriangle, ContactMatchesGeneralPathAndReferenceDepth) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-1, 1);
    constexpr Real kMargin = Real(0.05);
    int hits = 0, twoPoint = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const Vec3 tri[3] = {{-1.5f + Real(0.2) * u(rng), Real(0.2) * u(rng), -1},
                             {1.5f, Real(0.2) * u(rng), Real(-0.8) + Real(0.2) * u(rng)},
                             {Real(0.3) * u(rng), Real(0.2) * u(rng), 1.5f}};
        const detail::ConvexShape t = detail::makeTriangle(tri[0], tri[1], tri[2]);
        const Real radius = Real(0.3) + Real(0.2) * std::fabs(u(rng));
        const Real halfHeight = Real(0.2) + Real(0.6) * std::fabs(u(rng));
        Vec3 axis = randomUnit(rng);
        if (trial % 3 == 0) axis = normalize(Vec3{axis.x, Real(0.01) * axis.y, axis.z});  // lying
        const Vec3 centre{Real(1.2) * u(rng), radius + Real(0.5) * u(rng) + halfHeight * std::fabs(axis.y), Real(1.2) * u(rng)};
        const detail::ConvexShape c = capsule(centre, axis, halfHeight, radius);
        const Vec3 seg = rotate(c.xf.q, Vec3{0, halfHeight, 0});
        const V tv[3] = {toV(tri[0]), toV(tri[1]), toV(tri[2])};
        const double dist = segmentTriangleDistance(toV(centre - seg), toV(centre + seg), tv);

        Manifold mine, general;
        const bool hitMine = detail::collideTriangleCapsule(t, c, kMargin, mine);
        const bool hitGeneral = detail::collideConvexConvex(t, c, kMargin, general);
        const double refDepth = double(radius) - dist;
        // Within 0.1 mm of the margin either answer is right.
        if (std::fabs(refDepth + double(kMargin)) < 1e-4) continue;
        EXPECT_EQ(hitMine, refDepth >= -double(kMargin)) << "trial " << trial;
        EXPECT_EQ(hitMine, hitGeneral) << "trial " << trial;
        if (!hitMine || !hitGeneral) continue;
        ++hits;
        Real deepestMine = -1e30f, deepestGeneral = -1e30f;
        for (std::uint32_t i = 0; i < mine.pointCount; ++i) deepestMine = std::max(deepestMine, mine.points[i].depth);
        for (std::uint32_t i = 0; i < general.pointCount; ++i) deepestGeneral = std::max(deepestGeneral, general.points[i].depth);
        if (dist > 1e-3) {
            // Cores apart. The normal is the closest points' direction: along
            // it the capsule lies beyond the triangle by exactly the
            // reference distance less the radius (every other direction
            // shows less). Within 1 mm: where the segment lies nearly level
            // with the face, points a float's rounding farther than the
            // closest ones point up to 1e-3 rad elsewhere (GJK's normal
            // shows the same), which the shapes' 2-3 m lever turns into
            // tenths of a millimetre; a degree off would show 3 cm.
            Real lo, hi;
            c.extent(mine.normal, lo, hi);
            const Real triTop = std::max({dot(mine.normal, tri[0]), dot(mine.normal, tri[1]), dot(mine.normal, tri[2])});
            EXPECT_NEAR(lo - triTop, -refDepth, 1e-3) << "trial " << trial;
            // The manifold is the general path's: its normal, its deepest
            // point, its count (the same clipping of the same features).
            EXPECT_GT(dot(mine.normal, general.normal), Real(0.999)) << "trial " << trial;
            EXPECT_NEAR(deepestMine, deepestGeneral, 2e-4) << "trial " << trial;
            if (dot(mine.normal, general.normal) > Real(0.99999)) {
                EXPECT_EQ(mine.pointCount, general.pointCount) << "trial " << trial;
            }
            // The overlap is never under-stated: the closest points join the
            // clipped ones when those are shallower by the clipping's 1 mm
            // tolerance. Along the face normal the clipped depths are exact.
            EXPECT_GE(deepestMine, refDepth - 1.05e-3) << "trial " << trial;
            if (dot(mine.normal, normalize(cross(tri[1] - tri[0], tri[2] - tri[0]))) > Real(0.9999)) {
                EXPECT_NEAR(deepestMine, refDepth, 2e-4) << "trial " << trial;
                for (std::uint32_t i = 0; i < mine.pointCount; ++i) EXPECT_LE(mine.points[i].depth, refDepth + 2e-4);
            }
        } else {
            // Cores touching: the general path's own answer.
            EXPECT_EQ(mine.pointCount, general.pointCount);
            EXPECT_EQ(mine.normal, general.normal);
        }
        if (mine.pointCount == 2) ++twoPoint;
    }
    EXPECT_GT(hits, 500);
    EXPECT_GT(twoPoint, 50);  // lying capsules clipped to two points, as the general path does
}

// A capsule lying on a flat triangle, its core 0.49 m over it (radius 0.5):
// two points 1 cm deep at the segment's ends, along the face normal.
TEST(CapsuleTriangle, LyingCapsuleGetsTwoPointsAtItsEnds) {
    const detail::ConvexShape t = detail::makeTriangle({-3, 0, -3}, {3, 0, -3}, {0, 0, 3});
    const detail::ConvexShape c = capsule({0, Real(0.49), 0}, {1, 0, 0}, Real(0.75), Real(0.5));
    Manifold m;
    ASSERT_TRUE(detail::collideTriangleCapsule(t, c, Real(0.02), m));
    EXPECT_NEAR(m.normal.y, 1, 1e-6);
    ASSERT_EQ(m.pointCount, 2u);
    Real xs[2];
    for (std::uint32_t i = 0; i < 2; ++i) {
        EXPECT_NEAR(m.points[i].depth, 0.01, 1e-5);
        xs[i] = m.points[i].position.x;
    }
    EXPECT_NEAR(std::min(xs[0], xs[1]), -0.75, 1e-5);
    EXPECT_NEAR(std::max(xs[0], xs[1]), 0.75, 1e-5);
}
