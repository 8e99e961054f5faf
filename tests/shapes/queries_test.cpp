// Ray casts and closest-point queries against independent references: exact
// signed distance functions evaluated in double, with sphere tracing for rays.
#include <gtest/gtest.h>

#include <functional>
#include <numbers>
#include <vector>

#include "collision/shape_queries.hpp"
#include "fulcrum/shape.hpp"
#include "test_util.hpp"

namespace fulcrum {
namespace {

using Sdf = std::function<double(const Vec3&)>;
using Tri = std::array<std::uint32_t, 3>;

double len(double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); }

// Exact signed distance functions of the primitives (shape-local).
double sdfSphere(const Vec3& p, double r) { return len(p.x, p.y, p.z) - r; }
double sdfBox(const Vec3& p, const Vec3& h) {
    const double qx = std::fabs(double(p.x)) - h.x, qy = std::fabs(double(p.y)) - h.y, qz = std::fabs(double(p.z)) - h.z;
    return len(std::max(qx, 0.0), std::max(qy, 0.0), std::max(qz, 0.0)) + std::min(std::max({qx, qy, qz}), 0.0);
}
double sdfCapsule(const Vec3& p, double r, double h) {
    const double y = std::clamp(double(p.y), -h, h);
    return len(p.x, p.y - y, p.z) - r;
}
double sdfCylinder(const Vec3& p, double r, double h) {
    const double dx = std::sqrt(double(p.x) * p.x + double(p.z) * p.z) - r, dy = std::fabs(double(p.y)) - h;
    return std::min(std::max(dx, dy), 0.0) + std::sqrt(std::max(dx, 0.0) * std::max(dx, 0.0) + std::max(dy, 0.0) * std::max(dy, 0.0));
}
// Hull: distance to the nearest face triangle (brute force), negative when behind every plane.
double sdfHull(const Vec3& p, const ConvexHull& h) {
    double best = 1e30;
    bool inside = true;
    for (const HullFace& f : h.faces) {
        inside = inside && dot(f.normal, p) <= f.offset;
        const Vec3& a = h.vertices[h.faceVertices[f.firstIndex]];
        for (std::uint32_t i = 1; i + 1 < f.indexCount; ++i) {
            const Vec3 c = test::closestOnTriangle(p, a, h.vertices[h.faceVertices[f.firstIndex + i]], h.vertices[h.faceVertices[f.firstIndex + i + 1]]);
            best = std::min(best, double(length(p - c)));
        }
    }
    return inside ? -best : best;
}

Vec3 gradient(const Sdf& sdf, const Vec3& p) {
    const Real e = Real(1e-3);
    return normalize(Vec3{Real(sdf(p + Vec3{e, 0, 0}) - sdf(p - Vec3{e, 0, 0})), Real(sdf(p + Vec3{0, e, 0}) - sdf(p - Vec3{0, e, 0})),
                          Real(sdf(p + Vec3{0, 0, e}) - sdf(p - Vec3{0, 0, e}))});
}

// First root of the SDF along o + t d by sphere tracing (in double). Returns
// false for a miss, and sets `ambiguous` for near misses and grazing hits,
// where float and double answers may legitimately differ.
bool traceRay(const Sdf& sdf, const Vec3& o, const Vec3& d, double maxFraction, double& t, bool& ambiguous) {
    const double dl = len(d.x, d.y, d.z);
    t = 0;
    double closest = 1e30;
    ambiguous = false;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 p{Real(o.x + t * d.x), Real(o.y + t * d.y), Real(o.z + t * d.z)};
        const double s = sdf(p);
        closest = std::min(closest, s);
        if (s < 1e-6) {
            const Vec3 g = gradient(sdf, p);
            ambiguous = std::fabs(dot(g, d)) < 0.1f * Real(dl);
            return true;
        }
        t += s / dl;
        if (t > maxFraction) break;
    }
    ambiguous = closest < 2e-3;
    return false;
}

struct Case {
    const char* name;
    Shape shape;
    Sdf sdf;
};

std::vector<Case> solidCases() {
    test::Rng rng(31);
    std::vector<Vec3> pts;
    for (int i = 0; i < 30; ++i) pts.push_back(mul(rng.inBall(1), Vec3{Real(1.2), Real(0.8), 1}));
    const Shape hull = Shape::convexHull(pts);
    const Vec3 he{Real(0.8), Real(0.5), Real(1.1)};
    return {
        {"sphere", Shape::sphere(Real(0.9)), [](const Vec3& p) { return sdfSphere(p, 0.9); }},
        {"box", Shape::box(he), [he](const Vec3& p) { return sdfBox(p, he); }},
        {"capsule", Shape::capsule(Real(0.4), Real(0.7)), [](const Vec3& p) { return sdfCapsule(p, 0.4, 0.7); }},
        {"cylinder", Shape::cylinder(Real(0.6), Real(0.5)), [](const Vec3& p) { return sdfCylinder(p, 0.6, 0.5); }},
        {"convex_hull", hull, [hull](const Vec3& p) { return sdfHull(p, hull.hull()); }},
    };
}

TEST(RayCast, SolidShapesMatchSphereTracing) {
    // Tolerances: fraction x |d| within 2e-4 m, the hit point within 1e-4 m of
    // the surface, the normal within 0.5 degrees of the SDF gradient.
    for (const Case& c : solidCases()) {
        test::Rng rng(41);
        int hits = 0, misses = 0;
        for (int i = 0; i < 400; ++i) {
            const Vec3 o = rng.inBox(Vec3::splat(-3), Vec3::splat(3));
            if (c.sdf(o) < 0.01) continue;
            const Vec3 target = rng.inBox(Vec3::splat(-1.2f), Vec3::splat(1.2f));
            const Vec3 d = (target - o) * rng.uniform(Real(0.5), Real(2));
            double t = 0;
            bool ambiguous = false;
            const bool expected = traceRay(c.sdf, o, d, 1, t, ambiguous);
            if (ambiguous) continue;
            const auto hit = rayCastShape(c.shape, Transform::identity(), o, d, 1);
            ASSERT_EQ(hit.has_value(), expected) << c.name << " ray " << i;
            if (!hit) { ++misses; continue; }
            ++hits;
            EXPECT_NEAR(hit->fraction * length(d), t * length(d), 2e-4) << c.name;
            EXPECT_NEAR(c.sdf(hit->point), 0, 1e-4) << c.name;
            // A true outward normal leads straight away from the surface:
            // one centimetre along it the distance is one centimetre (a wrong
            // face normal near an edge would fail this by 1 - cos(angle)).
            EXPECT_NEAR(c.sdf(hit->point + hit->normal * Real(0.01)), 0.01, 2e-5) << c.name;
            EXPECT_LT(dot(hit->normal, d), 0) << c.name;
        }
        EXPECT_GT(hits, 50) << c.name;
        EXPECT_GT(misses, 10) << c.name;
    }
}

TEST(RayCast, StartingInsideReportsFractionZero) {
    for (const Case& c : solidCases()) {
        test::Rng rng(42);
        int inside = 0;
        for (int i = 0; i < 200; ++i) {
            const Vec3 o = rng.inBox(Vec3::splat(-1), Vec3::splat(1));
            if (c.sdf(o) > -1e-3) continue;
            ++inside;
            const Vec3 d = rng.inBox(Vec3::splat(-2), Vec3::splat(2));
            const auto hit = rayCastShape(c.shape, Transform::identity(), o, d, 1);
            ASSERT_TRUE(hit.has_value()) << c.name;
            EXPECT_EQ(hit->fraction, 0);
            EXPECT_EQ(hit->point, o);
            EXPECT_LT(length(hit->normal + normalize(d)), 1e-6) << c.name;
        }
        EXPECT_GT(inside, 10) << c.name;
    }
}

TEST(RayCast, Plane) {
    // Analytic: t = (offset - n.o) / (n.d) for rays from above moving down.
    const Vec3 n = normalize(Vec3{1, 2, -1});
    const Shape plane = Shape::plane(n * 3, 6);  // normalised inside: n.p = 2
    test::Rng rng(43);
    for (int i = 0; i < 100; ++i) {
        const Vec3 o = rng.inBox(Vec3::splat(-5), Vec3::splat(5));
        const Vec3 d = rng.inBox(Vec3::splat(-5), Vec3::splat(5));
        const double s = dot(n, o) - 2, den = dot(n, d);
        const auto hit = rayCastShape(plane, Transform::identity(), o, d, 1);
        if (s <= 0) { ASSERT_TRUE(hit); EXPECT_EQ(hit->fraction, 0); continue; }
        const double t = -s / den;
        const bool expected = den < 0 && t <= 1;
        if (std::fabs(t - 1) < 1e-4) continue;
        ASSERT_EQ(hit.has_value(), expected);
        if (!hit) continue;
        EXPECT_NEAR(hit->fraction, t, 1e-5 * std::max(1.0, t));
        EXPECT_LT(length(hit->normal - n), 1e-6);
    }
}

// Closed box mesh, outward-facing triangles.
Shape boxMeshShape(const Vec3& h) {
    std::vector<Vec3> v;
    std::vector<Tri> t;
    for (int i = 0; i < 8; ++i) v.push_back({(i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z});
    const std::array<std::array<std::uint32_t, 4>, 6> quads{{{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}}};
    for (const auto& q : quads) {
        t.push_back({q[0], q[1], q[2]});
        t.push_back({q[0], q[2], q[3]});
    }
    return Shape::mesh(v, t);
}

// A hull's faces fanned into a closed triangle mesh.
Shape meshOfHull(const ConvexHull& h) {
    std::vector<Tri> t;
    for (const HullFace& f : h.faces) {
        for (std::uint32_t i = 1; i + 1 < f.indexCount; ++i) {
            t.push_back({h.faceVertices[f.firstIndex], h.faceVertices[f.firstIndex + i], h.faceVertices[f.firstIndex + i + 1]});
        }
    }
    return Shape::mesh(h.vertices, t);
}

TEST(RayCast, BoxMeshMatchesBoxFromOutside) {
    // Same surface, different code (BVH + Moeller-Trumbore vs slabs): 1e-5.
    const Vec3 h{1, Real(0.6), Real(1.4)};
    const Shape mesh = boxMeshShape(h), box = Shape::box(h);
    test::Rng rng(44);
    int hits = 0;
    for (int i = 0; i < 300; ++i) {
        const Vec3 o = rng.inBox(Vec3::splat(-4), Vec3::splat(4));
        if (sdfBox(o, h) < 0.01) continue;
        const Vec3 d = (rng.inBox(Vec3::splat(-2), Vec3::splat(2)) - o) * 2;
        const auto a = rayCastShape(mesh, Transform::identity(), o, d, 1);
        const auto b = rayCastShape(box, Transform::identity(), o, d, 1);
        ASSERT_EQ(a.has_value(), b.has_value());
        if (!a) continue;
        ++hits;
        EXPECT_NEAR(a->fraction, b->fraction, 1e-5);
        EXPECT_NE(a->triangle, kNoSubShape);
        if (std::fabs(dot(b->normal, normalize(d))) > 0.05f) { EXPECT_LT(length(a->normal - b->normal), 1e-5); }
    }
    EXPECT_GT(hits, 50);
    // From inside, a mesh is a surface: the ray hits the back of the face and the normal faces the ray.
    const auto inside = rayCastShape(mesh, Transform::identity(), {0, 0, 0}, {3, 0, 0}, 1);
    ASSERT_TRUE(inside);
    EXPECT_NEAR(inside->fraction, 1.0 / 3.0, 1e-6);
    EXPECT_LT(length(inside->normal - Vec3{-1, 0, 0}), 1e-6);
}

TEST(RayCast, CompoundReportsTheNearestChild) {
    const std::vector<CompoundChild> children{
        {Shape::sphere(Real(0.5)), Transform({2, 0, 0}, Quat::identity())},
        {Shape::box({Real(0.3), Real(0.3), Real(0.3)}), Transform({-2, 0, 0}, Quat::fromAxisAngle({0, 1, 0}, Real(0.4)))}};
    const Shape compound = Shape::compound(children);
    const auto right = rayCastShape(compound, Transform::identity(), {5, 0, 0}, {-10, 0, 0}, 1);
    ASSERT_TRUE(right);
    EXPECT_EQ(right->child, 0u);
    EXPECT_NEAR(right->fraction, 0.25, 1e-6);  // enters the sphere at x = 2.5
    const auto left = rayCastShape(compound, Transform::identity(), {-5, 0, 0}, {10, 0, 0}, 1);
    ASSERT_TRUE(left);
    EXPECT_EQ(left->child, 1u);
    // The rotated box's face along x: |x| = 0.3 / cos(0.4) for a ray along the diagonal-free x axis.
    EXPECT_NEAR(left->point.x, -2 - 0.3 / std::cos(0.4), 1e-5);
    EXPECT_FALSE(rayCastShape(compound, Transform::identity(), {0, 3, 0}, {0, 0, 1}, 1));
}

std::vector<Case> allCases() {
    std::vector<Case> cases = solidCases();
    const Vec3 he{Real(0.7), Real(0.9), Real(0.4)};
    cases.push_back({"plane", Shape::plane({0, 1, 0}, Real(0.2)), [](const Vec3& p) { return double(p.y) - 0.2; }});
    cases.push_back({"box_mesh", boxMeshShape(he), [he](const Vec3& p) { return sdfBox(p, he); }});
    const Shape hull = cases[4].shape;
    cases.push_back({"hull_mesh", meshOfHull(hull.hull()), [hull](const Vec3& p) { return sdfHull(p, hull.hull()); }});
    const std::vector<CompoundChild> children{
        {Shape::sphere(Real(0.5)), Transform({1, 0, 0}, Quat::identity())},
        {Shape::capsule(Real(0.3), Real(0.5)), Transform({-1, 0, 0}, Quat::fromAxisAngle({0, 0, 1}, Real(0.7)))}};
    cases.push_back({"compound", Shape::compound(children), [](const Vec3& p) {
                         const Vec3 q = inverseRotate(Quat::fromAxisAngle({0, 0, 1}, Real(0.7)), p - Vec3{-1, 0, 0});
                         return std::min(sdfSphere(p - Vec3{1, 0, 0}, 0.5), sdfCapsule(q, 0.3, 0.5));
                     }});
    return cases;
}

TEST(ClosestPoint, MatchesExactSignedDistance) {
    // Tolerance 2e-5 m on distances of order 1 m (float rounding); the
    // closest point lies on the surface and p - point = distance * normal.
    for (const Case& c : allCases()) {
        test::Rng rng(51);
        int inside = 0;
        for (int i = 0; i < 600; ++i) {
            const Real extent = i % 2 ? Real(2) : Real(1.2);  // half the points near the shapes
            const Vec3 p = rng.inBox(Vec3::splat(-extent), Vec3::splat(extent));
            const PointQuery q = closestPoint(c.shape, Transform::identity(), p);
            const double expected = c.sdf(p);
            inside += expected < 0;
            ASSERT_NEAR(q.distance, expected, 2e-5) << c.name << " at " << p.x << "," << p.y << "," << p.z;
            EXPECT_NEAR(c.sdf(q.point), 0, 2e-5) << c.name;
            EXPECT_NEAR(length(q.normal), 1, 1e-5) << c.name;
            EXPECT_LT(length(p - q.point - q.normal * q.distance), 5e-5) << c.name;
        }
        EXPECT_GT(inside, 5) << c.name;
    }
}

TEST(ClosestPoint, BoxCornersEdgesAndFaces) {
    // Exact cases: outside a corner, beside an edge, above a face, and inside
    // nearer one face.
    const Shape box = Shape::box({1, 2, 3});
    const Transform id = Transform::identity();
    PointQuery q = closestPoint(box, id, {2, 3, 4});
    EXPECT_LT(length(q.point - Vec3{1, 2, 3}), 1e-6);
    EXPECT_NEAR(q.distance, std::sqrt(3.0), 1e-6);
    q = closestPoint(box, id, {2, 3, 0.5f});
    EXPECT_LT(length(q.point - Vec3{1, 2, 0.5f}), 1e-6);
    EXPECT_NEAR(q.distance, std::sqrt(2.0), 1e-6);
    q = closestPoint(box, id, {0.5f, 0.5f, 5});
    EXPECT_NEAR(q.distance, 2, 1e-6);
    EXPECT_EQ(q.normal, Vec3(0, 0, 1));
    q = closestPoint(box, id, {0.5f, -1.9f, 0});
    EXPECT_NEAR(q.distance, -0.1, 1e-6);
    EXPECT_EQ(q.normal, Vec3(0, -1, 0));
    EXPECT_LT(length(q.point - Vec3{0.5f, -2, 0}), 1e-6);
}

TEST(Queries, InvariantUnderMovingShapeAndQueryTogether) {
    // Rotating and translating both the shape and the query changes nothing
    // but the frame: tolerance 2e-5 (float rounding of the transforms).
    test::Rng rng(61);
    for (const Case& c : allCases()) {
        for (int i = 0; i < 100; ++i) {
            const Transform xf(rng.inBox(Vec3::splat(-10), Vec3::splat(10)), rng.rotation());
            const Vec3 p = rng.inBox(Vec3::splat(-2.5f), Vec3::splat(2.5f));
            const PointQuery a = closestPoint(c.shape, Transform::identity(), p);
            const PointQuery b = closestPoint(c.shape, xf, transformPoint(xf, p));
            EXPECT_NEAR(a.distance, b.distance, 2e-5) << c.name;
            EXPECT_LT(length(transformPoint(xf, a.point) - b.point), 5e-5) << c.name;
            if (std::fabs(a.distance) > 1e-3) { EXPECT_LT(length(rotate(xf.q, a.normal) - b.normal), 1e-4) << c.name; }

            const Vec3 d = (rng.inBox(Vec3::splat(-1), Vec3::splat(1)) - p) * 2;
            const auto ra = rayCastShape(c.shape, Transform::identity(), p, d, 1);
            const auto rb = rayCastShape(c.shape, xf, transformPoint(xf, p), rotate(xf.q, d), 1);
            if (ra.has_value() != rb.has_value()) {
                // Only a grazing ray may flip between hit and miss.
                const auto& h = ra ? ra : rb;
                EXPECT_LT(std::fabs(dot(ra ? h->normal : rotate(conjugate(xf.q), h->normal), normalize(d))), 0.01f) << c.name;
                continue;
            }
            if (!ra) continue;
            EXPECT_NEAR(ra->fraction, rb->fraction, 2e-5) << c.name;
            EXPECT_LT(length(rotate(xf.q, ra->normal) - rb->normal), 1e-3) << c.name;
            EXPECT_EQ(ra->child, rb->child);
        }
    }
}

}  // namespace
}  // namespace fulcrum
