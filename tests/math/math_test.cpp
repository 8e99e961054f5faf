// Math types against identities that must hold exactly or to float rounding.
#include <gtest/gtest.h>

#include <random>

#include "fulcrum/math.hpp"

using namespace fulcrum;

namespace {
constexpr Real kTol = 1e-5f;

void expectNear(const Vec3& a, const Vec3& b, Real tol = kTol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

Quat randomRotation(std::mt19937& rng) {
    std::normal_distribution<Real> n(0, 1);
    const Real z = n(rng), y = n(rng), x = n(rng), w = n(rng);  // drawn last argument first, as GCC evaluated the call: the same cases with every compiler
    return normalize(Quat(w, x, y, z));
}
}  // namespace

TEST(Vec3, CrossProductIsOrthogonalAndRightHanded) {
    expectNear(cross(Vec3::unitX(), Vec3::unitY()), Vec3::unitZ());
    const Vec3 a{1, 2, 3}, b{-4, 0.5f, 2};
    EXPECT_NEAR(dot(cross(a, b), a), 0, kTol);
    EXPECT_NEAR(dot(cross(a, b), b), 0, kTol);
    // |a x b|^2 = |a|^2 |b|^2 - (a.b)^2 (Lagrange's identity)
    EXPECT_NEAR(lengthSquared(cross(a, b)), lengthSquared(a) * lengthSquared(b) - dot(a, b) * dot(a, b), 1e-3f);
}

TEST(Vec3, NormalizeOfZeroStaysZero) {
    EXPECT_EQ(normalize(Vec3::zero()), Vec3::zero());
    EXPECT_NEAR(length(normalize(Vec3{3, 4, 12})), 1, kTol);
}

TEST(Vec3, OrthonormalBasisIsOrthonormalAndRightHanded) {
    std::mt19937 rng(7);
    std::normal_distribution<Real> n(0, 1);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 v = normalize(Vec3{n(rng), n(rng), n(rng)});
        Vec3 t1, t2;
        orthonormalBasis(v, t1, t2);
        EXPECT_NEAR(length(t1), 1, 1e-4f);
        EXPECT_NEAR(length(t2), 1, 1e-4f);
        EXPECT_NEAR(dot(t1, v), 0, 1e-4f);
        EXPECT_NEAR(dot(t2, v), 0, 1e-4f);
        expectNear(cross(t1, t2), v, 1e-4f);
    }
}

TEST(Mat3, InverseTimesMatrixIsIdentity) {
    const Mat3 m = Mat3::fromRows({2, 1, 0}, {1, 3, 1}, {0, 1, 4});
    const Mat3 p = inverse(m) * m;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p(r, c), r == c ? 1 : 0, kTol);
    EXPECT_EQ(inverse(Mat3::zero()), Mat3::zero());  // singular -> zero (infinite mass)
}

TEST(Mat3, SkewMatchesCrossProduct) {
    const Vec3 a{1, -2, 0.5f}, v{3, 1, -1};
    expectNear(Mat3::skew(a) * v, cross(a, v));
    expectNear(transposeMul(Mat3::skew(a), v), cross(v, a));
}

TEST(Quat, RotateMatchesMatrixAndPreservesLength) {
    std::mt19937 rng(1);
    for (int i = 0; i < 200; ++i) {
        const Quat q = randomRotation(rng);
        const Vec3 v{0.3f, -1.2f, 2.0f};
        expectNear(rotate(q, v), toMat3(q) * v);
        EXPECT_NEAR(length(rotate(q, v)), length(v), kTol);
        expectNear(inverseRotate(q, rotate(q, v)), v);
        EXPECT_NEAR(determinant(toMat3(q)), 1, kTol);
    }
}

TEST(Quat, AxisAngleQuarterTurn) {
    const Quat q = Quat::fromAxisAngle(Vec3::unitZ(), 1.5707963f);
    expectNear(rotate(q, Vec3::unitX()), Vec3::unitY());
}

TEST(Quat, FromMatrixRoundTrips) {
    std::mt19937 rng(2);
    for (int i = 0; i < 200; ++i) {
        const Quat q = randomRotation(rng);
        const Quat r = Quat::fromMatrix(toMat3(q));
        EXPECT_NEAR(std::fabs(dot(q, r)), 1, 1e-5f);  // q and -q are the same rotation
    }
}

TEST(Quat, FromToTakesFromOntoTo) {
    const Vec3 a = normalize(Vec3{1, 2, 3}), b = normalize(Vec3{-2, 0.1f, 1});
    expectNear(rotate(Quat::fromTo(a, b), a), b);
    expectNear(rotate(Quat::fromTo(a, -a), a), -a);  // antiparallel
}

TEST(Quat, IntegrateRotationIsExactForConstantSpin) {
    // Spinning at w about a fixed axis for time t rotates by |w| t exactly.
    const Vec3 w{0, 0, 3};
    Quat q;
    for (int i = 0; i < 100; ++i) q = integrateRotation(q, w, 0.01f);
    const Quat expected = Quat::fromAxisAngle(Vec3::unitZ(), 3.0f);
    EXPECT_NEAR(std::fabs(dot(q, expected)), 1, 1e-5f);
    EXPECT_NEAR(length(q), 1, 1e-6f);
}

TEST(Quat, RotationVectorInvertsAxisAngle) {
    const Vec3 axis = normalize(Vec3{1, 1, 0});
    expectNear(toRotationVector(Quat::fromAxisAngle(axis, 2.0f)), axis * 2.0f, 1e-5f);
}

TEST(Transform, InverseAndRelative) {
    std::mt19937 rng(3);
    const Transform a{{1, 2, 3}, randomRotation(rng)}, b{{-1, 0, 5}, randomRotation(rng)};
    const Vec3 p{0.5f, -0.25f, 2};
    expectNear(inverseTransformPoint(a, transformPoint(a, p)), p);
    expectNear(transformPoint(inverse(a) * a, p), p);
    expectNear(transformPoint(relative(a, b), p), transformPoint(inverse(a) * b, p));
}

TEST(AABB, OverlapMergeAndTransformedBounds) {
    const AABB a{{0, 0, 0}, {1, 1, 1}}, b{{0.5f, 0.5f, 0.5f}, {2, 2, 2}}, c{{1.5f, 0, 0}, {2, 1, 1}};
    EXPECT_TRUE(overlaps(a, b));
    EXPECT_FALSE(overlaps(a, c));
    EXPECT_TRUE(merge(a, c).contains(a));
    EXPECT_NEAR(a.surfaceArea(), 6, kTol);
    // A unit cube rotated 45 degrees about z spans sqrt(2) in x and y.
    const AABB r = transformBounds({Vec3::zero(), Quat::fromAxisAngle(Vec3::unitZ(), 0.7853982f)},
                                   AABB{{-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}});
    EXPECT_NEAR(r.max.x, 0.7071068f, kTol);
    EXPECT_NEAR(r.max.z, 0.5f, kTol);
}

TEST(AABB, RayCastSlabs) {
    const AABB box{{-1, -1, -1}, {1, 1, 1}};
    EXPECT_NEAR(rayCastAABB(box, {-3, 0, 0}, {4, 0, 0}, 1), 0.5f, kTol);
    EXPECT_LT(rayCastAABB(box, {-3, 2, 0}, {4, 0, 0}, 1), 0);
    EXPECT_LT(rayCastAABB(box, {-3, 0, 0}, {1, 0, 0}, 1), 0);  // stops short
}
