// A recycled manifold's refresh (src/contacts/recycled_points.hpp): where
// SSE2 exists the float build places each point with x, y and z in three
// lanes; every field it writes must be the scalar transformPoint path's bits
// (the path before the lanes), and so must the answer whether a point is
// touching, for any pose, any point count and points near and far from the
// surface, and the pair poses that decide whether a pair recycles. The
// double build, and builds without SSE2, run the scalar path
// itself: there the test holds trivially and still compiles.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "contacts/contact_manager.hpp"
#include "contacts/recycled_points.hpp"

using namespace fulcrum;
using namespace fulcrum::detail;

namespace {

bool sameBits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }
bool sameBits(Real a, Real b) { return std::memcmp(&a, &b, sizeof(Real)) == 0; }

class Draw {
public:
    explicit Draw(std::uint32_t seed) : rng_(seed) {}
    Real real(double lo, double hi) { return static_cast<Real>(std::uniform_real_distribution<double>(lo, hi)(rng_)); }
    Vec3 vec(double r) { return {real(-r, r), real(-r, r), real(-r, r)}; }
    // Unit quaternions mostly; some left unnormalised or with signed zeros,
    // which the refresh must treat as the scalar path does.
    Quat rotation() {
        const Quat q{real(-1, 1), real(-1, 1), real(-1, 1), real(-1, 1)};
        switch (std::uniform_int_distribution<int>(0, 9)(rng_)) {
            case 0: return q;
            case 1: return Quat{Real(-0.0), Real(0), Real(-0.0), Real(1)};
            default: return length(q) > Real(0.1) ? normalize(q) : Quat::identity();
        }
    }
    std::uint32_t count() { return std::uniform_int_distribution<std::uint32_t>(0, 4)(rng_); }
    // Reaches from a box's half extent to a large world's coordinates.
    double scale() { return std::uniform_int_distribution<int>(0, 2)(rng_) == 0 ? 2000.0 : 3.0; }

private:
    std::mt19937 rng_;
};

CachedManifold randomManifold(Draw& draw) {
    CachedManifold m;
    m.localNormal = normalize(draw.vec(1) + Vec3(0, Real(1e-3), 0));
    m.normal = normalize(draw.vec(1) + Vec3(Real(1e-3), 0, 0));
    m.pointCount = draw.count();
    const double r = draw.scale();
    for (CachedPoint& p : m.points) {
        p.localA = draw.vec(r);
        p.localB = draw.vec(r);
        p.position = draw.vec(1);
        p.depth = draw.real(-1, 1);
        p.depthAfter = draw.real(-1, 1);
    }
    return m;
}

void expectSameManifold(const CachedManifold& lanes, const CachedManifold& scalar, int trial) {
    ASSERT_TRUE(sameBits(lanes.normal, scalar.normal)) << "trial " << trial;
    for (std::uint32_t k = 0; k < 4; ++k) {
        const CachedPoint& a = lanes.points[k];
        const CachedPoint& b = scalar.points[k];
        ASSERT_TRUE(sameBits(a.position, b.position)) << "trial " << trial << " point " << k;
        ASSERT_TRUE(sameBits(a.depth, b.depth)) << "trial " << trial << " point " << k;
        ASSERT_TRUE(sameBits(a.depthAfter, b.depthAfter)) << "trial " << trial << " point " << k;
        ASSERT_TRUE(sameBits(a.localA, b.localA) && sameBits(a.localB, b.localB)) << "trial " << trial;
    }
}

}  // namespace

// 100,000 random manifolds and pose pairs: the refresh with the normal turned
// from A's frame (contact recycling) and without (a piece recycled against a
// static mesh), against the scalar forms, every written field bit for bit.
TEST(RecycledPoints, SameBitsAsTheScalarTransforms) {
    Draw draw(20261129);
    int touchingSeen = 0, apartSeen = 0;
    for (int trial = 0; trial < 100000; ++trial) {
        const double r = draw.scale();
        const Transform xA{draw.vec(r), draw.rotation()};
        const Transform xB{draw.vec(r), draw.rotation()};
        const CachedManifold start = randomManifold(draw);

        CachedManifold lanes = start, scalar = start;
        const bool touchingLanes = refreshRecycledManifold(lanes, xA, xB);
        const bool touchingScalar = refreshRecycledManifoldScalar(scalar, xA, xB);
        ASSERT_EQ(touchingLanes, touchingScalar) << "trial " << trial;
        expectSameManifold(lanes, scalar, trial);
        (touchingLanes ? touchingSeen : apartSeen) += 1;

        CachedManifold pointsLanes = start, pointsScalar = start;
        ASSERT_EQ(refreshRecycledPoints(pointsLanes, xA, xB), refreshRecycledPointsScalar(pointsScalar, xA, xB))
            << "trial " << trial;
        expectSameManifold(pointsLanes, pointsScalar, trial);
    }
    // Both answers were met, so the touching test was exercised.
    EXPECT_GT(touchingSeen, 1000);
    EXPECT_GT(apartSeen, 1000);
}

// Points placed just either side of the touching slop (a resting contact's
// depths, where the answer flips): the depth and the answer as the scalar path.
TEST(RecycledPoints, SameAnswerAtTheTouchingSlop) {
    Draw draw(7);
    for (int trial = 0; trial < 20000; ++trial) {
        const Transform xA{draw.vec(5), draw.rotation()};
        const Transform xB{draw.vec(5), draw.rotation()};
        CachedManifold m;
        m.localNormal = normalize(draw.vec(1) + Vec3(0, Real(1e-3), 0));
        m.normal = rotate(xA.q, m.localNormal);
        m.pointCount = 1 + draw.count() % 4;
        for (std::uint32_t k = 0; k < m.pointCount; ++k) {
            // A world point, and B's anchor a depth of about -kTouchSlop behind A's along the normal.
            const Vec3 world = transformPoint(xA, draw.vec(1));
            const Real depth = -kTouchSlop + draw.real(-1e-5, 1e-5);
            m.points[k].localA = inverseTransformPoint(xA, world);
            m.points[k].localB = inverseTransformPoint(xB, world - m.normal * depth);
        }
        CachedManifold lanes = m, scalar = m;
        ASSERT_EQ(refreshRecycledManifold(lanes, xA, xB), refreshRecycledManifoldScalar(scalar, xA, xB)) << "trial " << trial;
        expectSameManifold(lanes, scalar, trial);
    }
}

// The pair's poses (both shape-frame transforms and B's pose in A's frame):
// the lanes' rotations against the scalar path's, bit for bit, with centres
// of mass off the shape's origin and on it.
TEST(RecycledPoints, PairPosesSameBitsAsTheScalarPath) {
    Draw draw(314159);
    const auto sameTransform = [](const Transform& a, const Transform& b) {
        return sameBits(a.p, b.p) && std::memcmp(&a.q, &b.q, sizeof(Quat)) == 0;
    };
    for (int trial = 0; trial < 100000; ++trial) {
        const double r = draw.scale();
        const Vec3 comA = draw.vec(r), comB = draw.vec(r);
        const Quat qA = draw.rotation(), qB = draw.rotation();
        const Vec3 localA = trial % 3 == 0 ? Vec3{} : draw.vec(1), localB = trial % 5 == 0 ? Vec3{} : draw.vec(1);
        const PairPoses lanes = pairPoses({comA, qA, localA}, {comB, qB, localB});
        const PairPoses scalar = pairPosesScalar({comA, qA, localA}, {comB, qB, localB});
        ASSERT_TRUE(sameTransform(lanes.a, scalar.a)) << "trial " << trial;
        ASSERT_TRUE(sameTransform(lanes.b, scalar.b)) << "trial " << trial;
        ASSERT_TRUE(sameTransform(lanes.relative, scalar.relative)) << "trial " << trial;
    }
}
