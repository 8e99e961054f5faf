// GJK's warm start for two hulls (collision/manifold.hpp, GjkWarmStart): a
// run that starts from the last run's simplex answers as a cold run does (to
// GJK's own tolerance), its first run with an empty start is the cold run bit
// for bit, and a start that does not fit the hulls is ignored.
#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "collision/collide_pairs.hpp"
#include "collision/gjk.hpp"
#include "collision/manifold.hpp"
#include "collision/support.hpp"
#include "helpers.hpp"

using namespace fulcrum;

namespace {

std::vector<Vec3> rock(std::mt19937& rng, int n) {
    std::normal_distribution<Real> g(0, 1);
    std::vector<Vec3> p;
    for (int i = 0; i < n; ++i) {
        const Vec3 d = normalize(Vec3{g(rng), g(rng), g(rng)});
        p.push_back(Vec3{d.x * Real(1.4), d.y * Real(0.8), d.z});  // an elongated rock, 2.8 m by 1.6 by 2
    }
    return p;
}

// A random pose pair for the empty-start tests: A at the origin, B's centre
// 0.5-3.5 m away in a random direction, both randomly turned (the draws in
// this order, fresh distributions each call).
std::pair<Transform, Transform> randomPoses(std::mt19937& rng) {
    std::uniform_real_distribution<Real> off(Real(0.5), Real(3.5));
    std::normal_distribution<Real> g(0, 1);
    const Transform xa{{0, 0, 0}, test::randomRotation(rng)};
    const Transform xb{normalize(Vec3{g(rng), g(rng), g(rng)}) * off(rng), test::randomRotation(rng)};
    return {xa, xb};
}

void expectSameBits(const detail::GjkResult& x, const detail::GjkResult& y) {
    EXPECT_EQ(x.overlap, y.overlap);
    EXPECT_EQ(x.beyond, y.beyond);
    EXPECT_EQ(x.distance, y.distance);
    EXPECT_EQ(x.pointA, y.pointA);
    EXPECT_EQ(x.pointB, y.pointB);
    EXPECT_EQ(x.normal, y.normal);
    EXPECT_EQ(x.iterations, y.iterations);
}

// A rock rolling past another rock (or past a box) in small steps, as
// contacts do from one step to the next, from apart to overlapping and
// out again: at every step the warm run's distance is the cold run's to
// 2e-5 m (GJK stops at a relative gain of 1e-6 of |v|^2, micrometres here),
// its witness points are that far apart, and both agree on overlap. Summed
// over the path the warm runs take fewer iterations (the start is already
// near the answer).
void rollPast(const Shape& a, const Shape& b, std::uint32_t seed) {
    std::mt19937 rng(seed);
    const Quat qa0 = test::randomRotation(rng), qb0 = test::randomRotation(rng);
    detail::GjkWarmStart warm;
    std::uint32_t coldIterations = 0, warmIterations = 0, overlapping = 0, apart = 0;
    for (int step = 0; step < 400; ++step) {
        const Real t = Real(step) / 400;
        const Transform xa{{0, 0, 0}, normalize(qa0 * Quat::fromAxisAngle(normalize(Vec3{1, 2, 3}), Real(2.5) * t))};
        // B passes A's side along x, its centre 2.6 m out at the ends and 1.2 m in the middle:
        // closer than the two rocks' smallest half widths (0.8 m each, less the hulls' facets),
        // so the path passes through overlap whatever the random shapes and rotations (which
        // differ between the float and the double build: the draws are of Real).
        const Real x = Real(6) * t - 3, y = Real(1.2) + Real(1.4) * (Real(2) * t - 1) * (Real(2) * t - 1);
        const Transform xb{{x, y, Real(0.2)}, normalize(qb0 * Quat::fromAxisAngle(normalize(Vec3{-2, 1, 1}), Real(3) * t))};
        const detail::ConvexShape ca = detail::makeConvexCore(a, xa), cb = detail::makeConvexCore(b, xb);
        const detail::GjkResult cold = detail::gjkDistance(ca, cb, false);
        const detail::GjkResult hot = detail::gjkDistance(ca, cb, false, std::numeric_limits<Real>::infinity(), &warm);
        ASSERT_GE(warm.count, 1u);
        ASSERT_LE(warm.count, 3u);
        ASSERT_EQ(hot.overlap, cold.overlap) << "step " << step << ", cold distance " << cold.distance;
        coldIterations += cold.iterations;
        warmIterations += hot.iterations;
        if (cold.overlap) {
            ++overlapping;
            continue;
        }
        ++apart;
        EXPECT_NEAR(hot.distance, cold.distance, Real(2e-5)) << "step " << step;
        EXPECT_NEAR(length(hot.pointB - hot.pointA), hot.distance, Real(2e-5)) << "step " << step;
        EXPECT_NEAR(dot(hot.normal, cold.normal), 1, Real(1e-3)) << "step " << step;
    }
    EXPECT_GT(overlapping, 20u) << "the path must pass through overlap";
    EXPECT_GT(apart, 20u);
    EXPECT_LT(warmIterations, coldIterations);
}

}  // namespace

TEST(GjkWarmStart, TwoRocksAnswerAsTheColdRunAlongAPath) {
    std::mt19937 rng(21);
    const Shape a = Shape::convexHull(rock(rng, 24)), b = Shape::convexHull(rock(rng, 24));
    rollPast(a, b, 22);
}

TEST(GjkWarmStart, ABoxAndARockAnswerAsTheColdRunAlongAPath) {
    std::mt19937 rng(23);
    const Shape a = Shape::box({Real(1.2), Real(0.7), Real(0.9)}), b = Shape::convexHull(rock(rng, 24));
    rollPast(a, b, 24);
}

// With an empty start the run is the cold run, bit for bit (the indexed
// supports are coreSupport's hull case), and leaves its simplex's hull
// vertices; a start whose indices lie beyond the hulls (a snapshot of other
// shapes) is ignored: the cold run again, bit for bit.
TEST(GjkWarmStart, AnEmptyOrForeignStartIsTheColdRun) {
    std::mt19937 rng(5);
    const Shape a = Shape::convexHull(rock(rng, 16)), b = Shape::convexHull(rock(rng, 16));
    for (int trial = 0; trial < 40; ++trial) {
        const auto [xa, xb] = randomPoses(rng);
        const detail::ConvexShape ca = detail::makeConvexCore(a, xa), cb = detail::makeConvexCore(b, xb);
        const detail::GjkResult cold = detail::gjkDistance(ca, cb, false, Real(0.1));
        detail::GjkWarmStart empty;
        expectSameBits(detail::gjkDistance(ca, cb, false, Real(0.1), &empty), cold);
        EXPECT_GE(empty.count, 1u);
        for (std::uint32_t i = 0; i < empty.count; ++i) {
            EXPECT_LT(empty.indexA[i], a.hull().vertices.size());
            EXPECT_LT(empty.indexB[i], b.hull().vertices.size());
        }
        detail::GjkWarmStart foreign;
        foreign.count = 2;
        foreign.indexA[0] = 3;
        foreign.indexB[0] = 1;
        foreign.indexA[1] = static_cast<std::uint32_t>(a.hull().vertices.size());  // one past A's last vertex
        foreign.indexB[1] = 0;
        expectSameBits(detail::gjkDistance(ca, cb, false, Real(0.1), &foreign), cold);
    }
}

// A box's corners as indices (bit k: + along axis k): the empty start's run
// is the cold run bit for bit, and the corners it keeps are the box's.
TEST(GjkWarmStart, ABoxsEmptyStartIsTheColdRun) {
    std::mt19937 rng(6);
    const Shape a = Shape::box({Real(1.2), Real(0.7), Real(0.9)}), b = Shape::convexHull(rock(rng, 16));
    for (int trial = 0; trial < 40; ++trial) {
        const auto [xa, xb] = randomPoses(rng);
        const detail::ConvexShape ca = detail::makeConvexCore(a, xa), cb = detail::makeConvexCore(b, xb);
        const detail::GjkResult cold = detail::gjkDistance(ca, cb, false, Real(0.1));
        detail::GjkWarmStart empty;
        expectSameBits(detail::gjkDistance(ca, cb, false, Real(0.1), &empty), cold);
        EXPECT_GE(empty.count, 1u);
        for (std::uint32_t i = 0; i < empty.count; ++i) {
            EXPECT_LT(empty.indexA[i], 8u);
            const Vec3 corner = transformPoint(xa, {(empty.indexA[i] & 1u) ? Real(1.2) : Real(-1.2),
                                                    (empty.indexA[i] & 2u) ? Real(0.7) : Real(-0.7),
                                                    (empty.indexA[i] & 4u) ? Real(0.9) : Real(-0.9)});
            EXPECT_EQ(corner, cold.simplex.v[i].a);
        }
    }
}
