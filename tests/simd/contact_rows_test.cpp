// The wide contact-row kernel (tests/simd/contact_rows.hpp) against its scalar
// twin and against the physics of one row: a solved, approaching contact ends
// with zero relative normal speed, a separating one receives no impulse, and
// the impulse pair conserves linear momentum.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>

#include "simd/contact_rows.hpp"
#include "simd/fp_contract.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

template <class P>
class ContactRowsTest : public ::testing::Test {};

using Policies = ::testing::Types<simd::PortablePolicy<4>, simd::PortablePolicy<8>
#if FULCRUM_SIMD_HAS_SSE2
                                  ,
                                  simd::Sse2Policy
#endif
#if FULCRUM_SIMD_HAS_AVX2
                                  ,
                                  simd::Avx2Policy
#endif
                                  >;
TYPED_TEST_SUITE(ContactRowsTest, Policies);

bool sameBits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
bool sameBits(const Vec3& a, const Vec3& b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z); }

float relativeNormalSpeed(const std::vector<SolverBody>& bodies, const ContactRow& r) {
    const SolverBody& A = bodies[r.a];
    const SolverBody& B = bodies[r.b];
    return dot(r.n, B.v - A.v) + dot(r.rBxn, B.w) - dot(r.rAxn, A.w);
}

}  // namespace

TYPED_TEST(ContactRowsTest, WideSolveIsBitIdenticalToScalar) {
    if (test::scalarCodeIsContracted()) GTEST_SKIP() << "this build fuses scalar a * b + c into FMAs; build with -ffp-contract=off";
    using P = TypeParam;
    // 8 rows per colour so every width's bundles are colours; 1003 rows leave
    // a partial last bundle (empty lanes).
    RowScene scalar = makeRowScene(64, 1003, 8, 42);
    std::vector<SolverBody> bodies = scalar.bodies, bodiesByField = scalar.bodies;
    std::vector<RowBundle<P>> bundles = bundleRows<P>(scalar.rows), bundlesByField = bundles;
    for (int iteration = 0; iteration < 10; ++iteration) {
        solveRowsScalar(scalar.bodies.data(), scalar.rows.data(), scalar.rows.size());
        solveRowsWide<P>(bodies.data(), bundles.data(), bundles.size());
        solveRowsWideByField<P>(bodiesByField.data(), bundlesByField.data(), bundlesByField.size());
    }
    int mismatches = 0;
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        for (const SolverBody* wide : {&bodies[k], &bodiesByField[k]})
            if (!sameBits(wide->v, scalar.bodies[k].v) || !sameBits(wide->w, scalar.bodies[k].w) ||
                !sameBits(wide->invMass, scalar.bodies[k].invMass) || !sameBits(wide->invInertia, scalar.bodies[k].invInertia))
                ++mismatches;
    }
    for (std::size_t r = 0; r < scalar.rows.size(); ++r) {
        const int lane = int(r % P::kLanes);
        if (!sameBits(bundles[r / P::kLanes].impulse.lane(lane), scalar.rows[r].impulse)) ++mismatches;
        if (!sameBits(bundlesByField[r / P::kLanes].impulse.lane(lane), scalar.rows[r].impulse)) ++mismatches;
    }
    EXPECT_EQ(mismatches, 0);
}

TYPED_TEST(ContactRowsTest, IsolatedRowsReachZeroApproachSpeedAndConserveMomentum) {
    using P = TypeParam;
    constexpr std::size_t kRows = 400;
    RowScene scene = makeRowScene(2 * kRows, kRows, kRows, 7);  // every row has its own two bodies
    for (ContactRow& r : scene.rows) r.bias = 0;
    const std::vector<SolverBody> before = scene.bodies;
    std::vector<RowBundle<P>> bundles = bundleRows<P>(scene.rows);
    solveRowsWide<P>(scene.bodies.data(), bundles.data(), bundles.size());

    int approaching = 0, separating = 0;
    for (std::size_t k = 0; k < kRows; ++k) {
        const ContactRow& r = scene.rows[k];
        const float impulse = bundles[k / P::kLanes].impulse.lane(int(k % P::kLanes));
        const float speedBefore = relativeNormalSpeed(before, r);
        const float speedAfter = relativeNormalSpeed(scene.bodies, r);
        if (speedBefore < 0) {
            ++approaching;
            // Δλ = −m_eff Cdot makes Cdot exactly 0 in exact arithmetic; float
            // leaves a few ulps of the speeds involved (|v|, |w| <= ~3 here).
            EXPECT_NEAR(speedAfter, 0.0f, 1e-5f) << "row " << k;
            EXPECT_GT(impulse, 0.0f);
        } else {
            ++separating;
            EXPECT_EQ(impulse, 0.0f) << "row " << k;
            EXPECT_EQ(speedAfter, speedBefore);
        }
        // Linear momentum of the pair: the impulses are equal and opposite.
        const SolverBody &A0 = before[r.a], &B0 = before[r.b], &A1 = scene.bodies[r.a], &B1 = scene.bodies[r.b];
        const Vec3 p0 = A0.v / A0.invMass + B0.v / B0.invMass;
        const Vec3 p1 = A1.v / A1.invMass + B1.v / B1.invMass;
        EXPECT_LT(length(p1 - p0), 1e-5f) << "row " << k;
    }
    EXPECT_GT(approaching, 50);  // both cases exercised
    EXPECT_GT(separating, 50);
}
