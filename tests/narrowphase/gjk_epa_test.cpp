// GJK distances against an independent answer, and EPA/SAT depths against
// known configurations.
#include <gtest/gtest.h>

#include <limits>

#include "collision/collide_pairs.hpp"
#include "collision/epa.hpp"
#include "collision/gjk.hpp"
#include "collision/narrow_phase.hpp"
#include "helpers.hpp"

using namespace fulcrum;
using fulcrum::test::expectVecNear;

namespace {

std::vector<Vec3> randomCloud(std::mt19937& rng, int n, Real scale) {
    std::normal_distribution<Real> g(0, 1);
    std::vector<Vec3> p;
    for (int i = 0; i < n; ++i) p.push_back(Vec3{g(rng), g(rng), g(rng)} * scale);
    return p;
}

// Separation of two point sets along unit direction d: min over B minus max over A.
Real gapAlong(const std::vector<Vec3>& a, const Transform& xa, const std::vector<Vec3>& b, const Transform& xb, const Vec3& d) {
    Real maxA = -1e30f, minB = 1e30f;
    for (const Vec3& p : a) maxA = std::max(maxA, dot(transformPoint(xa, p), d));
    for (const Vec3& p : b) minB = std::min(minB, dot(transformPoint(xb, p), d));
    return minB - maxA;
}

}  // namespace

TEST(Gjk, DistanceBetweenRandomHullsMatchesTheSeparatingAxisOptimum) {
    // The distance between convex sets equals the largest support gap over all
    // directions (the separating-axis dual). So (1) no sampled direction may
    // beat GJK's distance, (2) GJK's own normal must attain it, and (3) the
    // witness points must be that far apart. Tolerance 1e-4 m on ~1 m shapes.
    std::mt19937 rng(11);
    std::uniform_real_distribution<Real> off(2.0f, 3.5f);
    std::normal_distribution<Real> g(0, 1);
    for (int trial = 0; trial < 30; ++trial) {
        const std::vector<Vec3> ca = randomCloud(rng, 12, 0.5f), cb = randomCloud(rng, 12, 0.5f);
        const Shape a = Shape::convexHull(ca), b = Shape::convexHull(cb);
        const Transform xa{{0, 0, 0}, test::randomRotation(rng)};
        const Transform xb{normalize(Vec3{g(rng), g(rng), g(rng)}) * off(rng), test::randomRotation(rng)};
        const detail::GjkResult r = detail::gjkDistance(detail::makeConvex(a, xa), detail::makeConvex(b, xb), false);
        if (r.overlap) continue;
        const Real d = r.distance;
        EXPECT_NEAR(length(r.pointB - r.pointA), d, 1e-5f);
        const Vec3 n = (r.pointB - r.pointA) / d;
        EXPECT_NEAR(gapAlong(a.hull().vertices, xa, b.hull().vertices, xb, n), d, 1e-4f) << "trial " << trial;
        for (int k = 0; k < 2000; ++k) {
            const Vec3 dir = normalize(Vec3{g(rng), g(rng), g(rng)});
            EXPECT_LE(gapAlong(a.hull().vertices, xa, b.hull().vertices, xb, dir), d + 1e-4f);
        }
    }
}

TEST(Gjk, EarlyStopBeyondADistanceIsALowerBoundOfTheFullRun) {
    // The narrow phase asks GJK to stop once a support plane shows the
    // shapes farther apart than its margin (collideConvexConvex): that answer
    // is only the same as the full run's if the full distance is never below
    // the bound the early stop reports, and if a run that does not stop is the
    // full run, bit for bit. Hulls, boxes and cylinders, 0 to 3 m apart.
    std::mt19937 rng(5);
    std::uniform_real_distribution<Real> off(0.5f, 4.0f);
    std::normal_distribution<Real> g(0, 1);
    int stopped = 0;
    for (int trial = 0; trial < 600; ++trial) {
        const Shape shapes[3] = {Shape::convexHull(randomCloud(rng, 16, 0.5f)), Shape::box({0.4f, 0.2f, 0.6f}),
                                 Shape::cylinder(0.5f, 0.3f)};
        const Shape& a = shapes[trial % 3];
        const Shape& b = shapes[(trial / 3) % 3];
        const detail::ConvexShape ca = detail::makeConvex(a, {{0, 0, 0}, test::randomRotation(rng)});
        const detail::ConvexShape cb =
            detail::makeConvex(b, {normalize(Vec3{g(rng), g(rng), g(rng)}) * off(rng), test::randomRotation(rng)});
        const detail::GjkResult full = detail::gjkDistance(ca, cb, false);
        for (const Real beyond : {Real(0.01), Real(0.3), Real(1)}) {
            const detail::GjkResult early = detail::gjkDistance(ca, cb, false, beyond);
            if (early.beyond) {
                ++stopped;
                EXPECT_GT(early.distance, beyond);
                EXPECT_FALSE(full.overlap) << "trial " << trial;
                EXPECT_GE(full.distance, early.distance - Real(1e-5)) << "trial " << trial;
            } else {
                EXPECT_EQ(early.overlap, full.overlap) << "trial " << trial;
                EXPECT_EQ(early.distance, full.distance) << "trial " << trial;
                EXPECT_EQ(early.iterations, full.iterations) << "trial " << trial;
            }
        }
    }
    EXPECT_GT(stopped, 300);  // the early stop does happen
}

TEST(Gjk, AGuessedNormalGivesTheSameDistanceAndTheRightGuessFewerIterations) {
    // The time of impact starts each advance's GJK along the pair's last
    // normal. From any start GJK must find the same distance (to its
    // tolerance, 1e-4 m here on ~1 m shapes), whether the guess is the
    // normal, a slightly turned one, a random one or its opposite; from the
    // normal itself it needs no more iterations, summed over the trials,
    // than from the line of centres.
    std::mt19937 rng(23);
    std::uniform_real_distribution<Real> off(0.8f, 4.0f);
    std::normal_distribution<Real> g(0, 1);
    std::uint32_t plain = 0, guessed = 0;
    int apart = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const Shape shapes[4] = {Shape::convexHull(randomCloud(rng, 16, 0.5f)), Shape::box({0.4f, 0.2f, 0.6f}),
                                 Shape::capsule(0.2f, 0.5f), Shape::box({3.0f, 0.2f, 3.0f})};
        const Shape& a = shapes[trial % 3];
        const Shape& b = shapes[(trial / 3) % 4];
        const detail::ConvexShape ca = detail::makeConvex(a, {{0, 0, 0}, test::randomRotation(rng)});
        const detail::ConvexShape cb =
            detail::makeConvex(b, {normalize(Vec3{g(rng), g(rng), g(rng)}) * off(rng), test::randomRotation(rng)});
        const detail::GjkResult full = detail::gjkDistance(ca, cb, false);
        const Vec3 random = normalize(Vec3{g(rng), g(rng), g(rng)});
        const Vec3 turned = full.overlap ? random : normalize(full.normal + Real(0.1) * random);
        const Vec3 guesses[4] = {full.overlap ? random : full.normal, turned, random, -turned};
        for (int k = 0; k < 4; ++k) {
            const detail::GjkResult r = detail::gjkDistance(ca, cb, false, std::numeric_limits<Real>::infinity(), nullptr, &guesses[k]);
            EXPECT_EQ(r.overlap, full.overlap) << "trial " << trial << " guess " << k;
            if (full.overlap || r.overlap) continue;
            EXPECT_NEAR(r.distance, full.distance, Real(1e-4)) << "trial " << trial << " guess " << k;
            if (k == 0) {
                ++apart;
                plain += full.iterations;
                guessed += r.iterations;
            }
        }
    }
    EXPECT_GT(apart, 200);
    EXPECT_LE(guessed, plain);
}

TEST(Epa, OverlappingBoxHullsDepthAlongTheAxis) {
    // Hull boxes (general path: GJK + EPA + face clipping) overlapping by 0.1 along x.
    const ConvexHull h = test::boxHull({1, 1, 1});
    const detail::ConvexShape a = test::hullShape(h, {}), b = test::hullShape(h, {{1.9f, 0.3f, -0.2f}, {}});
    const detail::PenetrationResult p = detail::epaPenetration(a, b);
    ASSERT_TRUE(p.valid);
    expectVecNear(p.normal, {1, 0, 0}, 1e-4f);
    EXPECT_NEAR(p.depth, 0.1f, 1e-4f);
    Manifold m;
    ASSERT_TRUE(detail::collideConvexConvex(a, b, 0.02f, m));
    EXPECT_EQ(m.pointCount, 4u);
    for (const ContactPoint& c : m.contacts()) {
        EXPECT_NEAR(c.depth, 0.1f, 1e-4f);
        EXPECT_NEAR(c.position.x, 0.95f, 1e-4f);
    }
}

TEST(Epa, SphereAgainstHullOutsideAndInside) {
    const Vec3 pts[8] = {{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {-1, 1, 1}, {1, 1, 1}};
    const Shape hull = Shape::convexHull(pts);
    ManifoldBuffer out;
    // Centre outside (GJK on the point core): depth 0.2.
    collide(Shape::sphere(0.5f), {{1.3f, 0.2f, 0}, {}}, hull, {}, 0.02f, out);
    ASSERT_EQ(out.size(), 1u);
    expectVecNear(out[0].normal, {-1, 0, 0}, 1e-4f);
    EXPECT_NEAR(out[0].points[0].depth, 0.2f, 1e-4f);
    // Centre inside (EPA on the full sphere): nearest face +x at 0.2, depth 0.7.
    collide(Shape::sphere(0.5f), {{0.8f, 0.1f, 0}, {}}, hull, {}, 0.02f, out);
    ASSERT_EQ(out.size(), 1u);
    expectVecNear(out[0].normal, {-1, 0, 0}, 2e-3f);
    EXPECT_NEAR(out[0].points[0].depth, 0.7f, 2e-3f);
}

TEST(Epa, HullHullAndBoxHullRestingGiveFourPoints) {
    const Vec3 pts[8] = {{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {-1, 1, 1}, {1, 1, 1}};
    const Shape hull = Shape::convexHull(pts);
    ManifoldBuffer out;
    const Transform top{{0.3f, 1.99f, 0.2f}, Quat::fromAxisAngle({0, 1, 0}, 0.5f)};
    for (const Shape& base : {hull, Shape::box({1, 1, 1})}) {
        collide(base, {}, hull, top, 0.02f, out);
        ASSERT_EQ(out.size(), 1u);
        expectVecNear(out[0].normal, {0, 1, 0}, 1e-3f);
        EXPECT_EQ(out[0].pointCount, 4u);
        for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, 0.01f, 1e-3f);
    }
}

TEST(Sat, BoxBoxDepthAlongEachFaceAxis) {
    // Boxes of different sizes overlapping along x, y, z in turn (SAT path).
    ManifoldBuffer out;
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3& ax : axes) {
        const Real reach = dot(Vec3{1, 2, 3}, ax) + dot(Vec3{0.5f, 0.6f, 0.7f}, ax);
        collide(Shape::box({1, 2, 3}), {}, Shape::box({0.5f, 0.6f, 0.7f}), {ax * (reach - 0.05f), {}}, 0.02f, out);
        ASSERT_EQ(out.size(), 1u);
        expectVecNear(out[0].normal, ax, 1e-5f);
        EXPECT_EQ(out[0].pointCount, 4u);
        for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, 0.05f, 1e-5f);
    }
}

// Found by fuzz/narrowphase_fuzz.cpp (its reproducer is in
// fuzz/corpus/narrowphase/): for concentric shapes GJK's first segment runs
// through the origin and the closest point then stays ~1e-6 m from it; GJK
// called that "separated", EPA trusted it, and two cylinders 4.8 m deep in
// each other got a depth of -2e-6 (the fuzz build) or the radial 6.35 m
// instead of the axial 4.83 m (Release).
TEST(Gjk, ConcentricShapesOverlapInsteadOfTouchingWithinFloatNoise) {
    const Quat q{Real(0.5), Real(0.5), Real(0.5), Real(0.5)};
    const Transform at{{10, 10, 10}, q};
    const Shape small = Shape::cylinder(Real(2.3528), Real(0.829118)), big = Shape::cylinder(4, 4);
    const detail::GjkResult g = detail::gjkDistance(detail::makeConvex(small, at), detail::makeConvex(big, at), true);
    EXPECT_TRUE(g.overlap);
    ManifoldBuffer ab, ba;
    collide(small, at, big, at, Real(0.1), ab);
    collide(big, at, small, at, Real(0.1), ba);
    ASSERT_EQ(ab.size(), 1u);
    ASSERT_EQ(ba.size(), 1u);
    // The least push-out is along the common axis: half-heights 0.829 + 4.
    EXPECT_NEAR(ab[0].maxDepth(), Real(4.829118), Real(1e-3));
    EXPECT_NEAR(ba[0].maxDepth(), Real(4.829118), Real(1e-3));
    // A small sphere at a cylinder's centre is inside it, not 1e-6 m away.
    const detail::GjkResult s =
        detail::gjkDistance(detail::makeConvex(Shape::cylinder(Real(2.3528), Real(0.836891)), at),
                            detail::makeConvex(Shape::sphere(Real(0.02)), at), true);
    EXPECT_TRUE(s.overlap);
}
