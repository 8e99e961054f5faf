// Analytic contact tests for each shape pair: normal, depth, number of points
// and where they are. Tolerances: 1e-4 m on positions and depths unless noted
// (float arithmetic on metre-sized shapes is good to ~1e-6; EPA converges to
// ~1e-5 relative, so paths that use it get 1e-3).
#include <gtest/gtest.h>

#include <cmath>

#include "collision/narrow_phase.hpp"
#include "helpers.hpp"

using namespace fulcrum;
using fulcrum::test::expectVecNear;

namespace {

constexpr Real kTol = Real(1e-4);
constexpr Real kMargin = Real(0.02);

const Manifold& single(const ManifoldBuffer& out) {
    EXPECT_EQ(out.size(), 1u);
    return out[0];
}

Transform at(Real x, Real y, Real z, const Quat& q = Quat::identity()) { return {{x, y, z}, q}; }

// Every point of `m` lies on A's and B's surfaces: checks the anchors agree with position/depth.
void expectAnchorsConsistent(const Manifold& m, const Transform& xa, const Transform& xb) {
    for (const ContactPoint& c : m.contacts()) {
        const Vec3 pa = transformPoint(xa, c.localAnchorA), pb = transformPoint(xb, c.localAnchorB);
        expectVecNear((pa + pb) * Real(0.5), c.position, kTol);
        EXPECT_NEAR(dot(pa - pb, m.normal), c.depth, kTol);
    }
}

}  // namespace

TEST(Contacts, SphereSphereDepthNormalAndMidpoint) {
    ManifoldBuffer out;
    const Transform xa = at(0, 0, 0), xb = at(1.9f, 0, 0);
    collide(Shape::sphere(1), xa, Shape::sphere(1), xb, kMargin, out);
    const Manifold& m = single(out);
    ASSERT_EQ(m.pointCount, 1u);
    expectVecNear(m.normal, {1, 0, 0}, kTol);
    EXPECT_NEAR(m.points[0].depth, 0.1f, kTol);
    expectVecNear(m.points[0].position, {0.95f, 0, 0}, kTol);  // midway between x=1 (A) and x=0.9 (B)
    expectAnchorsConsistent(m, xa, xb);
}

TEST(Contacts, SpeculativeContactsOnlyWithinMargin) {
    ManifoldBuffer out;
    collide(Shape::sphere(1), at(0, 0, 0), Shape::sphere(1), at(2.015f, 0, 0), kMargin, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out[0].points[0].depth, -0.015f, kTol);
    collide(Shape::sphere(1), at(0, 0, 0), Shape::sphere(1), at(2.03f, 0, 0), kMargin, out);
    EXPECT_EQ(out.size(), 0u);
    // Box-box: 0.01 apart face to face -> 4 speculative points at -0.01; 0.03 apart -> none.
    collide(Shape::box({1, 1, 1}), at(0, 0, 0), Shape::box({1, 1, 1}), at(0, 2.01f, 0), kMargin, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].pointCount, 4u);
    for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, -0.01f, kTol);
    collide(Shape::box({1, 1, 1}), at(0, 0, 0), Shape::box({1, 1, 1}), at(0, 2.03f, 0), kMargin, out);
    EXPECT_EQ(out.size(), 0u);
}

TEST(Contacts, SphereCapsuleSideAndCap) {
    ManifoldBuffer out;
    const Shape cap = Shape::capsule(0.5f, 1);
    // Sphere touching the side at height 0.3: normal along -x from sphere (at +x) to capsule.
    collide(Shape::sphere(0.5f), at(0.9f, 0.3f, 0), cap, at(0, 0, 0), kMargin, out);
    const Manifold& m = single(out);
    expectVecNear(m.normal, {-1, 0, 0}, kTol);
    EXPECT_NEAR(m.points[0].depth, 0.1f, kTol);
    expectVecNear(m.points[0].position, {0.45f, 0.3f, 0}, kTol);
    // On the top cap: sphere above at y = 1 + 0.5 + 0.5 - 0.05.
    collide(Shape::sphere(0.5f), at(0, 1.95f, 0), cap, at(0, 0, 0), kMargin, out);
    expectVecNear(single(out).normal, {0, -1, 0}, kTol);
    EXPECT_NEAR(out[0].points[0].depth, 0.05f, kTol);
}

TEST(Contacts, SphereBoxFaceEdgeCorner) {
    ManifoldBuffer out;
    const Shape box = Shape::box({1, 1, 1});
    const Shape ball = Shape::sphere(0.5f);
    // Face: sphere centre at y = 1.4 -> depth 0.1, normal from box (A) to sphere (B) = +y.
    collide(box, at(0, 0, 0), ball, at(0.3f, 1.4f, -0.2f), kMargin, out);
    expectVecNear(single(out).normal, {0, 1, 0}, kTol);
    EXPECT_NEAR(out[0].points[0].depth, 0.1f, kTol);
    expectVecNear(out[0].points[0].position, {0.3f, 0.95f, -0.2f}, kTol);
    // Edge: centre off the +x/+y edge along the diagonal, distance 0.45 from the edge.
    const Real s = 0.45f / std::sqrt(2.0f);
    collide(box, at(0, 0, 0), ball, at(1 + s, 1 + s, 0.2f), kMargin, out);
    expectVecNear(single(out).normal, normalize(Vec3{1, 1, 0}), kTol);
    EXPECT_NEAR(out[0].points[0].depth, 0.05f, kTol);
    // Corner: along the (1,1,1) diagonal, 0.48 from the corner.
    const Real c = 0.48f / std::sqrt(3.0f);
    collide(box, at(0, 0, 0), ball, at(1 + c, 1 + c, 1 + c), kMargin, out);
    expectVecNear(single(out).normal, normalize(Vec3{1, 1, 1}), kTol);
    EXPECT_NEAR(out[0].points[0].depth, 0.02f, kTol);
    // Centre inside the box, nearest face +x at 0.1: depth r + 0.1.
    collide(box, at(0, 0, 0), ball, at(0.9f, 0, 0), kMargin, out);
    expectVecNear(single(out).normal, {1, 0, 0}, kTol);
    EXPECT_NEAR(out[0].points[0].depth, 0.6f, kTol);
}

TEST(Contacts, CapsuleCapsuleParallelGivesTwoPointsCrossedGivesOne) {
    ManifoldBuffer out;
    const Shape cap = Shape::capsule(0.25f, 1);
    const Quat lying = Quat::fromAxisAngle({0, 0, 1}, 1.5707963f);  // axis along x
    // Parallel, offset along x by 0.5: overlap of the segments is x in [-0.5, 1].
    const Transform xa = at(0, 0, 0, lying), xb = at(0.5f, 0.45f, 0, lying);
    collide(cap, xa, cap, xb, kMargin, out);
    const Manifold& m = single(out);
    ASSERT_EQ(m.pointCount, 2u);
    expectVecNear(m.normal, {0, 1, 0}, kTol);
    Real xs[2] = {m.points[0].position.x, m.points[1].position.x};
    if (xs[0] > xs[1]) std::swap(xs[0], xs[1]);
    EXPECT_NEAR(xs[0], -0.5f, kTol);
    EXPECT_NEAR(xs[1], 1.0f, kTol);
    for (const ContactPoint& c : m.contacts()) {
        EXPECT_NEAR(c.depth, 0.05f, kTol);
        EXPECT_NEAR(c.position.y, 0.225f, kTol);
    }
    expectAnchorsConsistent(m, xa, xb);
    // Crossed at right angles (B along z), one point above the crossing.
    const Quat alongZ = Quat::fromAxisAngle({1, 0, 0}, 1.5707963f);
    collide(cap, at(0, 0, 0, lying), cap, at(0.2f, 0.45f, 0.1f, alongZ), kMargin, out);
    ASSERT_EQ(single(out).pointCount, 1u);
    expectVecNear(out[0].normal, {0, 1, 0}, kTol);
    EXPECT_NEAR(out[0].points[0].depth, 0.05f, kTol);
    expectVecNear(out[0].points[0].position, {0.2f, 0.225f, 0}, kTol);  // above the crossing of the axes
}

TEST(Contacts, BoxRestingOnBoxGivesFourCornersOfTheOverlap) {
    ManifoldBuffer out;
    // Big box top at y = 1; small box (half 0.5) sunk 0.01 into it, shifted so
    // its footprint is x in [0.2, 1.2] (clipped to 1 by the big box), z in [-0.5, 0.5].
    const Shape big = Shape::box({1, 1, 1}), small = Shape::box({0.5f, 0.5f, 0.5f});
    const Transform xa = at(0, 0, 0), xb = at(0.7f, 1.49f, 0);
    collide(big, xa, small, xb, kMargin, out);
    const Manifold& m = single(out);
    ASSERT_EQ(m.pointCount, 4u);
    expectVecNear(m.normal, {0, 1, 0}, kTol);
    const Vec3 corners[4] = {{0.2f, 0.995f, -0.5f}, {1, 0.995f, -0.5f}, {1, 0.995f, 0.5f}, {0.2f, 0.995f, 0.5f}};
    for (const Vec3& corner : corners) {
        bool found = false;
        for (const ContactPoint& c : m.contacts()) found = found || length(c.position - corner) < kTol;
        EXPECT_TRUE(found) << "missing corner " << corner.x << " " << corner.y << " " << corner.z;
    }
    for (const ContactPoint& c : m.contacts()) EXPECT_NEAR(c.depth, 0.01f, kTol);
    expectAnchorsConsistent(m, xa, xb);
}

TEST(Contacts, BoxOnItsEdgeGivesTwoPoints) {
    ManifoldBuffer out;
    // Unit-half box rotated 45 degrees about z: lowest edge at y = centre - sqrt(2).
    const Real h = std::sqrt(2.0f);
    const Transform xb = at(0, 1 + h - 0.02f, 0, Quat::fromAxisAngle({0, 0, 1}, 0.78539816f));
    collide(Shape::box({2, 1, 2}), at(0, 0, 0), Shape::box({1, 1, 1}), xb, kMargin, out);
    const Manifold& m = single(out);
    ASSERT_EQ(m.pointCount, 2u);
    expectVecNear(m.normal, {0, 1, 0}, kTol);
    for (const ContactPoint& c : m.contacts()) {
        EXPECT_NEAR(c.depth, 0.02f, kTol);
        EXPECT_NEAR(c.position.x, 0, kTol);
        EXPECT_NEAR(std::fabs(c.position.z), 1, kTol);
    }
}

TEST(Contacts, BoxEdgeAcrossBoxEdge) {
    ManifoldBuffer out;
    // A's top edge along z at (x=0, y=h); B's bottom edge along x: boxes rotated 45 degrees about z and x.
    const Real h = std::sqrt(2.0f);
    const Transform xa = at(0, 0, 0, Quat::fromAxisAngle({0, 0, 1}, 0.78539816f));
    const Transform xb = at(0, 2 * h - 0.03f, 0, Quat::fromAxisAngle({1, 0, 0}, 0.78539816f));
    collide(Shape::box({1, 1, 1}), xa, Shape::box({1, 1, 1}), xb, kMargin, out);
    const Manifold& m = single(out);
    ASSERT_EQ(m.pointCount, 1u);
    expectVecNear(m.normal, {0, 1, 0}, kTol);
    EXPECT_NEAR(m.points[0].depth, 0.03f, kTol);
    expectVecNear(m.points[0].position, {0, h - 0.015f, 0}, kTol);
}

TEST(Contacts, CapsuleLyingOnBoxGivesTwoPoints) {
    ManifoldBuffer out;
    const Quat lying = Quat::fromAxisAngle({0, 0, 1}, 1.5707963f);
    const Transform xa = at(0.3f, 1.24f, 0.1f, lying);
    collide(Shape::capsule(0.25f, 0.5f), xa, Shape::box({1, 1, 1}), at(0, 0, 0), kMargin, out);
    const Manifold& m = single(out);
    ASSERT_EQ(m.pointCount, 2u);
    expectVecNear(m.normal, {0, -1, 0}, Real(1e-3));
    Real xs[2] = {m.points[0].position.x, m.points[1].position.x};
    if (xs[0] > xs[1]) std::swap(xs[0], xs[1]);
    EXPECT_NEAR(xs[0], -0.2f, Real(1e-3));
    EXPECT_NEAR(xs[1], 0.8f, Real(1e-3));
    for (const ContactPoint& c : m.contacts()) EXPECT_NEAR(c.depth, 0.01f, Real(1e-3));
}

TEST(Contacts, ShapesOnPlane) {
    ManifoldBuffer out;
    const Shape ground = Shape::plane({0, 1, 0}, 0);
    // Sphere: depth 0.05.
    collide(ground, at(0, 0, 0), Shape::sphere(1), at(2, 0.95f, 1), kMargin, out);
    expectVecNear(single(out).normal, {0, 1, 0}, kTol);
    EXPECT_NEAR(out[0].points[0].depth, 0.05f, kTol);
    expectVecNear(out[0].points[0].position, {2, -0.025f, 1}, kTol);
    // Box tilted slightly: the four bottom corners, deepest first.
    collide(ground, at(0, 0, 0), Shape::box({1, 0.5f, 1}), at(0, 0.49f, 0), kMargin, out);
    ASSERT_EQ(single(out).pointCount, 4u);
    for (const ContactPoint& c : out[0].contacts()) {
        EXPECT_NEAR(c.depth, 0.01f, kTol);
        EXPECT_NEAR(std::fabs(c.position.x), 1, kTol);
        EXPECT_NEAR(std::fabs(c.position.z), 1, kTol);
    }
    // Capsule lying: both ends.
    collide(Shape::capsule(0.3f, 1), at(0, 0.28f, 0, Quat::fromAxisAngle({1, 0, 0}, 1.5707963f)), ground, at(0, 0, 0),
            kMargin, out);
    ASSERT_EQ(single(out).pointCount, 2u);
    expectVecNear(out[0].normal, {0, -1, 0}, kTol);  // capsule (A) -> plane (B)
    for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, 0.02f, kTol);
    // Plane with an offset and rotation: n = +x, offset 2, as a plane rotated and moved.
    collide(Shape::plane({0, 1, 0}, 1), at(1, 0, 0, Quat::fromAxisAngle({0, 0, 1}, -1.5707963f)), Shape::sphere(0.5f),
            at(2.4f, 3, 0), kMargin, out);
    expectVecNear(single(out).normal, {1, 0, 0}, kTol);
    EXPECT_NEAR(out[0].points[0].depth, 0.1f, kTol);
}

// The support polygon of `m` must contain `p` (projected along the normal).
bool supports(const Manifold& m, const Vec3& p) {
    if (m.pointCount < 3) return false;
    // p inside the convex hull of the points iff no point set has p outside
    // all of them: check p against each edge of the hull of the points seen along n.
    for (std::uint32_t i = 0; i < m.pointCount; ++i) {
        for (std::uint32_t j = 0; j < m.pointCount; ++j) {
            if (i == j) continue;
            const Vec3 e = m.points[j].position - m.points[i].position;
            const Vec3 side = cross(e, m.normal);
            // Edge (i, j) is a hull edge if all points are on one side.
            bool allOneSide = true;
            for (std::uint32_t k = 0; k < m.pointCount; ++k) {
                if (dot(side, m.points[k].position - m.points[i].position) < -1e-6f) allOneSide = false;
            }
            if (allOneSide && dot(side, p - m.points[i].position) < -1e-6f) return false;
        }
    }
    return true;
}

TEST(Contacts, CylinderStandingOnPlaneAndBoxIsSupported) {
    ManifoldBuffer out;
    const Shape cyl = Shape::cylinder(0.5f, 1);
    const Transform xc = at(0.2f, 0.99f, -0.1f);
    collide(Shape::plane({0, 1, 0}, 0), at(0, 0, 0), cyl, xc, kMargin, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_GE(out[0].pointCount, 3u);
    EXPECT_TRUE(supports(out[0], xc.p));
    for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, 0.01f, kTol);
    // On a box top (y = 1): general GJK/EPA path plus cap clipping.
    const Transform xc2 = at(0.2f, 1.99f, -0.1f);
    collide(Shape::box({2, 1, 2}), at(0, 0, 0), cyl, xc2, kMargin, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_GE(out[0].pointCount, 3u);
    expectVecNear(out[0].normal, {0, 1, 0}, Real(1e-3));
    EXPECT_TRUE(supports(out[0], xc2.p));
    for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, 0.01f, Real(1e-3));
    // Cylinder lying on its side on the plane: two points along the bottom line.
    collide(cyl, at(0, 0.49f, 0, Quat::fromAxisAngle({1, 0, 0}, 1.5707963f)), Shape::plane({0, 1, 0}, 0), at(0, 0, 0),
            kMargin, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_GE(out[0].pointCount, 2u);
    for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, 0.01f, kTol);
}

TEST(Contacts, CompoundGivesOneManifoldPerTouchingChild) {
    ManifoldBuffer out;
    const CompoundChild kids[2] = {{Shape::sphere(0.5f), at(-1, 0, 0)}, {Shape::sphere(0.5f), at(1, 0, 0)}};
    const Shape dumbbell = Shape::compound(kids);
    collide(dumbbell, at(0, 0.49f, 0), Shape::plane({0, 1, 0}, 0), at(0, 0, 0), kMargin, out);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_NE(out[0].childA, out[1].childA);
    for (const Manifold& m : out) {
        expectVecNear(m.normal, {0, -1, 0}, kTol);
        EXPECT_NEAR(m.points[0].depth, 0.01f, kTol);
        EXPECT_NEAR(m.points[0].position.x, m.childA == 0 ? -1.0f : 1.0f, kTol);
        // Anchors are in the compound's body frame.
        EXPECT_NEAR(m.points[0].localAnchorA.x, m.childA == 0 ? -1.0f : 1.0f, kTol);
        EXPECT_NEAR(m.points[0].localAnchorA.y, -0.5f, kTol);
    }
}
