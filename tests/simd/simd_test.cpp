// Every wide operation against the scalar expression it stands for, lane by
// lane, for every policy this build has (portable 4 and 8, SSE2; AVX2 when
// built with -mavx2). Bit-exact where IEEE 754 fixes the result (add, sub,
// mul, div, sqrt, fma, min/max, compares, abs, negate, select, dot, cross —
// the last two because they are the same correctly rounded operations in the
// same order); NaN results must be NaN, their payload bits are not compared.
// reciprocalApprox: relative error below 2^-21 (stated in simd.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "math/simd.hpp"
#include "simd/fp_contract.hpp"

using namespace fulcrum;
using namespace fulcrum::simd;

namespace {

bool sameFloat(float a, float b) {
    return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) || (std::isnan(a) && std::isnan(b));
}

// Random floats of every kind: ordinary values over many magnitudes, and now
// and then ±0, ±inf, NaN, subnormals, and exact ties (so compares hit equality).
class FloatSource {
public:
    explicit FloatSource(unsigned seed) : rng_(seed) {}
    float next() {
        const int kind = std::uniform_int_distribution<int>(0, 19)(rng_);
        switch (kind) {
            case 0: return 0.0f;
            case 1: return -0.0f;
            case 2: return std::numeric_limits<float>::infinity();
            case 3: return -std::numeric_limits<float>::infinity();
            case 4: return std::numeric_limits<float>::quiet_NaN();
            case 5: return std::numeric_limits<float>::denorm_min() * float(std::uniform_int_distribution<int>(-1000, 1000)(rng_));
            case 6: return last_;  // a repeat: equal operands
            default: {
                const float m = std::uniform_real_distribution<float>(-1.0f, 1.0f)(rng_);
                return last_ = std::ldexp(m, std::uniform_int_distribution<int>(-30, 30)(rng_));
            }
        }
    }
    float finite(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng_); }

private:
    std::mt19937 rng_;
    float last_ = 1.0f;
};

template <class P>
class WideTest : public ::testing::Test {};

using Policies = ::testing::Types<PortablePolicy<4>, PortablePolicy<8>
#if FULCRUM_SIMD_HAS_SSE2
                                  ,
                                  Sse2Policy
#endif
#if FULCRUM_SIMD_HAS_AVX2
                                  ,
                                  Avx2Policy
#endif
                                  >;
TYPED_TEST_SUITE(WideTest, Policies);

constexpr int kRounds = 2000;

// Checks op(wide...) against ref(scalar...) lane by lane for random inputs.
template <class P, int Arity, class WideOp, class ScalarOp>
void checkLanewise(const char* name, WideOp wideOp, ScalarOp scalarOp) {
    using W = FloatWide<P>;
    constexpr int N = P::kLanes;
    FloatSource source(7);
    int mismatches = 0;
    for (int round = 0; round < kRounds; ++round) {
        float in[3][N];
        for (auto& arg : in)
            for (float& v : arg) v = source.next();
        const W a = W::load(in[0]), b = W::load(in[1]), c = W::load(in[2]);
        W result;
        if constexpr (Arity == 1) result = wideOp(a);
        if constexpr (Arity == 2) result = wideOp(a, b);
        if constexpr (Arity == 3) result = wideOp(a, b, c);
        for (int i = 0; i < N; ++i) {
            float expected;
            if constexpr (Arity == 1) expected = scalarOp(in[0][i]);
            if constexpr (Arity == 2) expected = scalarOp(in[0][i], in[1][i]);
            if constexpr (Arity == 3) expected = scalarOp(in[0][i], in[1][i], in[2][i]);
            if (!sameFloat(result.lane(i), expected) && mismatches++ < 5)
                ADD_FAILURE() << name << " lane " << i << ": inputs " << in[0][i] << ", " << in[1][i] << ", "
                              << in[2][i] << " gave " << result.lane(i) << ", scalar " << expected;
        }
    }
    EXPECT_EQ(mismatches, 0) << name;
}

// Same for operations returning a mask, against the scalar boolean.
template <class P, class WideOp, class ScalarOp>
void checkMask(const char* name, WideOp wideOp, ScalarOp scalarOp) {
    using W = FloatWide<P>;
    constexpr int N = P::kLanes;
    FloatSource source(11);
    int mismatches = 0;
    for (int round = 0; round < kRounds; ++round) {
        float a[N], b[N];
        for (int i = 0; i < N; ++i) a[i] = source.next(), b[i] = source.next();
        const MaskWide<P> m = wideOp(W::load(a), W::load(b));
        for (int i = 0; i < N; ++i)
            if (m.lane(i) != scalarOp(a[i], b[i]) && mismatches++ < 5)
                ADD_FAILURE() << name << " lane " << i << ": " << a[i] << ", " << b[i];
    }
    EXPECT_EQ(mismatches, 0) << name;
}

}  // namespace

TYPED_TEST(WideTest, ArithmeticMatchesScalarBitForBit) {
    using P = TypeParam;
    using W = FloatWide<P>;
    checkLanewise<P, 2>("add", [](W a, W b) { return a + b; }, [](float a, float b) { return a + b; });
    checkLanewise<P, 2>("sub", [](W a, W b) { return a - b; }, [](float a, float b) { return a - b; });
    checkLanewise<P, 2>("mul", [](W a, W b) { return a * b; }, [](float a, float b) { return a * b; });
    checkLanewise<P, 2>("div", [](W a, W b) { return a / b; }, [](float a, float b) { return a / b; });
    checkLanewise<P, 1>("neg", [](W a) { return -a; }, [](float a) { return -a; });
    checkLanewise<P, 1>("abs", [](W a) { return abs(a); }, [](float a) { return std::fabs(a); });
    checkLanewise<P, 1>("sqrt", [](W a) { return sqrt(a); }, [](float a) { return std::sqrt(a); });
    checkLanewise<P, 1>("reciprocal", [](W a) { return reciprocal(a); }, [](float a) { return 1.0f / a; });
    checkLanewise<P, 3>("mulAdd", [](W a, W b, W c) { return mulAdd(a, b, c); },
                        [](float a, float b, float c) { return a * b + c; });
    checkLanewise<P, 3>("fusedMulAdd", [](W a, W b, W c) { return fusedMulAdd(a, b, c); },
                        [](float a, float b, float c) { return std::fma(a, b, c); });
    W acc(1.5f);
    acc += W(2.0f);
    acc *= W(3.0f);
    acc -= W(0.5f);
    EXPECT_EQ(acc.lane(P::kLanes - 1), (1.5f + 2.0f) * 3.0f - 0.5f);
}

TYPED_TEST(WideTest, MinMaxFollowTheScalarExpressionsIncludingNaNAndSignedZero) {
    using P = TypeParam;
    using W = FloatWide<P>;
    checkLanewise<P, 2>("min", [](W a, W b) { return min(a, b); }, [](float a, float b) { return a < b ? a : b; });
    checkLanewise<P, 2>("max", [](W a, W b) { return max(a, b); }, [](float a, float b) { return a > b ? a : b; });
    checkLanewise<P, 3>("clamp", [](W x, W lo, W hi) { return clamp(x, lo, hi); }, [](float x, float lo, float hi) {
        const float m = x > lo ? x : lo;
        return m < hi ? m : hi;
    });
}

TYPED_TEST(WideTest, ComparesMasksAndSelect) {
    using P = TypeParam;
    using W = FloatWide<P>;
    checkMask<P>("<", [](W a, W b) { return a < b; }, [](float a, float b) { return a < b; });
    checkMask<P>("<=", [](W a, W b) { return a <= b; }, [](float a, float b) { return a <= b; });
    checkMask<P>(">", [](W a, W b) { return a > b; }, [](float a, float b) { return a > b; });
    checkMask<P>(">=", [](W a, W b) { return a >= b; }, [](float a, float b) { return a >= b; });
    checkMask<P>("==", [](W a, W b) { return a == b; }, [](float a, float b) { return a == b; });
    checkMask<P>("!=", [](W a, W b) { return a != b; }, [](float a, float b) { return a != b; });
    checkMask<P>("and", [](W a, W b) { return (a < b) & (a > W(0.0f)); }, [](float a, float b) { return a < b && a > 0; });
    checkMask<P>("or", [](W a, W b) { return (a < b) | (b < W(0.0f)); }, [](float a, float b) { return a < b || b < 0; });
    checkMask<P>("not", [](W a, W b) { return !(a < b); }, [](float a, float b) { return !(a < b); });
    checkLanewise<P, 3>("select", [](W a, W b, W c) { return select(a < b, c, a); },
                        [](float a, float b, float c) { return a < b ? c : a; });

    // Whole-mask queries, on a known pattern.
    float pattern[P::kLanes];
    for (int i = 0; i < P::kLanes; ++i) pattern[i] = i % 3 == 0 ? -1.0f : 1.0f;
    const MaskWide<P> negative = W::load(pattern) < W(0.0f);
    std::uint32_t expectedBits = 0;
    for (int i = 0; i < P::kLanes; i += 3) expectedBits |= 1u << i;
    EXPECT_EQ(negative.bits(), expectedBits);
    EXPECT_TRUE(negative.any());
    EXPECT_FALSE(negative.all());
    EXPECT_TRUE((W(1.0f) > W(0.0f)).all());
    EXPECT_TRUE((W(1.0f) < W(0.0f)).none());
}

TYPED_TEST(WideTest, ReciprocalApproxIsWithinTwoToTheMinus21) {
    using P = TypeParam;
    using W = FloatWide<P>;
    FloatSource source(3);
    double worst = 0;
    for (int round = 0; round < kRounds; ++round) {
        float x[P::kLanes];
        for (float& v : x) v = std::ldexp(source.finite(1.0f, 2.0f), int(source.finite(-60, 60))) * (source.finite(-1, 1) < 0 ? -1.0f : 1.0f);
        const W r = reciprocalApprox(W::load(x));
        for (int i = 0; i < P::kLanes; ++i) worst = std::max(worst, std::fabs(double(r.lane(i)) * x[i] - 1.0));
    }
    EXPECT_LT(worst, 0x1p-21);
}

TYPED_TEST(WideTest, Vec3DotCrossLengthMatchScalar) {
    if (test::scalarCodeIsContracted()) GTEST_SKIP() << "this build fuses scalar a * b + c into FMAs; build with -ffp-contract=off";
    using P = TypeParam;
    using V = Vec3Wide<P>;
    using W = FloatWide<P>;
    constexpr int N = P::kLanes;
    FloatSource source(5);
    int mismatches = 0;
    auto expectSame = [&](float wide, float scalar, const char* what) {
        if (!sameFloat(wide, scalar) && mismatches++ < 5) ADD_FAILURE() << what << ": " << wide << " vs " << scalar;
    };
    for (int round = 0; round < kRounds; ++round) {
        Vec3 a[N], b[N];
        float s[N];
        for (int i = 0; i < N; ++i) {
            a[i] = {source.finite(-10, 10), source.finite(-10, 10), source.finite(-10, 10)};
            b[i] = {source.finite(-10, 10), source.finite(-10, 10), source.finite(-10, 10)};
            s[i] = source.finite(-3, 3);
        }
        const V wa = V::fromLanes([&](int i) { return a[i]; });
        const V wb = V::fromLanes([&](int i) { return b[i]; });
        const W ws = W::load(s);
        const W d = dot(wa, wb), len = length(wa);
        const V c = cross(wa, wb), sum = wa + wb, diff = wa - wb, scaled = wa * ws, fma = mulAdd(wa, ws, wb);
        const V lo = min(wa, wb), hi = max(wa, wb), neg = -wa, picked = select(wa.x < wb.x, wa, wb);
        for (int i = 0; i < N; ++i) {
            expectSame(d.lane(i), fulcrum::dot(a[i], b[i]), "dot");
            expectSame(len.lane(i), fulcrum::length(a[i]), "length");
            const Vec3 pick = a[i].x < b[i].x ? a[i] : b[i];
            const Vec3 expected[] = {fulcrum::cross(a[i], b[i]), a[i] + b[i], a[i] - b[i], a[i] * s[i],
                                     a[i] * s[i] + b[i], fulcrum::min(a[i], b[i]), fulcrum::max(a[i], b[i]), -a[i], pick};
            const V* got[] = {&c, &sum, &diff, &scaled, &fma, &lo, &hi, &neg, &picked};
            const char* names[] = {"cross", "add", "sub", "scale", "mulAdd", "min", "max", "neg", "select"};
            for (int k = 0; k < 9; ++k) {
                const Vec3 g = got[k]->lane(i);
                expectSame(g.x, expected[k].x, names[k]);
                expectSame(g.y, expected[k].y, names[k]);
                expectSame(g.z, expected[k].z, names[k]);
            }
        }
    }
    EXPECT_EQ(mismatches, 0);
    // A geometric check besides the bits: the cross product is orthogonal to both factors.
    const V x(Vec3{1, 0, 0}), y(Vec3{0, 1, 0});
    const Vec3 z = cross(x, y).lane(N - 1);
    EXPECT_EQ(z, (Vec3{0, 0, 1}));
}

namespace {
struct Body {  // array-of-structs, as the solver keeps bodies
    Vec3 velocity;
    float invMass = 0;
    Vec3 angularVelocity;
    std::uint32_t flags = 0;
};
}  // namespace

TYPED_TEST(WideTest, GatherScatterRoundTripsAndSkipsEmptyLanes) {
    using P = TypeParam;
    using V = Vec3Wide<P>;
    using W = FloatWide<P>;
    constexpr int N = P::kLanes;
    std::mt19937 rng(99);
    std::vector<Body> bodies(50);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        const float f = static_cast<float>(k);
        bodies[k] = {{f, f + 0.25f, f + 0.5f}, 1.0f / (f + 1.0f), {-f, -2 * f, -3 * f}, std::uint32_t(k)};
    }
    for (int round = 0; round < 200; ++round) {
        // Distinct bodies per bundle (a graph colour), some lanes empty.
        std::vector<std::uint32_t> pool(bodies.size());
        for (std::uint32_t k = 0; k < pool.size(); ++k) pool[k] = k;
        std::shuffle(pool.begin(), pool.end(), rng);
        std::uint32_t indices[N];
        for (int i = 0; i < N; ++i) indices[i] = (round + i) % 5 == 0 ? kEmptyLane : pool[i];

        const V v = V::gather(bodies.data(), indices, &Body::velocity);
        const W m = W::gather(bodies.data(), indices, &Body::invMass);
        for (int i = 0; i < N; ++i) {
            const Vec3 expected = indices[i] == kEmptyLane ? Vec3{} : bodies[indices[i]].velocity;
            EXPECT_EQ(v.lane(i), expected);
            EXPECT_EQ(m.lane(i), indices[i] == kEmptyLane ? 0.0f : bodies[indices[i]].invMass);
        }
        // Scatter a modified copy: exactly the addressed fields change.
        std::vector<Body> after = bodies;
        (v * m).scatter(after.data(), indices, &Body::angularVelocity);
        (m + W(1.0f)).scatter(after.data(), indices, &Body::invMass);
        for (std::size_t k = 0; k < bodies.size(); ++k) {
            int lane = -1;
            for (int i = 0; i < N; ++i)
                if (indices[i] == k) lane = i;
            const Body& before = bodies[k];
            EXPECT_EQ(after[k].velocity, before.velocity);
            EXPECT_EQ(after[k].flags, before.flags);
            if (lane < 0) {
                EXPECT_EQ(after[k].angularVelocity, before.angularVelocity);
                EXPECT_EQ(after[k].invMass, before.invMass);
            } else {
                EXPECT_EQ(after[k].angularVelocity, before.velocity * before.invMass);
                EXPECT_EQ(after[k].invMass, before.invMass + 1.0f);
            }
        }
        // Round trip: gather, scatter into a copy, and the copy equals the original.
        std::vector<Body> copy = bodies;
        V::gather(bodies.data(), indices, &Body::angularVelocity).scatter(copy.data(), indices, &Body::angularVelocity);
        for (std::size_t k = 0; k < bodies.size(); ++k) EXPECT_EQ(copy[k].angularVelocity, bodies[k].angularVelocity);
    }
}

TYPED_TEST(WideTest, TransposedGatherScatterRoundTrips) {
    using P = TypeParam;
    using W = FloatWide<P>;
    constexpr int N = P::kLanes;
    static_assert(sizeof(Body) == 8 * sizeof(float));
    std::vector<Body> bodies(40);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        const float f = static_cast<float>(k);
        bodies[k] = {{f, f + 0.25f, f + 0.5f}, 1.0f / (f + 1.0f), {-f, -2 * f, -3 * f}, 0x7fc00000u + std::uint32_t(k)};
    }
    std::uint32_t indices[N];
    for (int i = 0; i < N; ++i) indices[i] = i == 1 ? kEmptyLane : std::uint32_t(3 * i + 2);
    const std::array<W, 8> columns = W::template gatherTransposed<8>(bodies.data(), indices);
    for (int i = 0; i < N; ++i) {
        const Body expected = indices[i] == kEmptyLane ? Body{{0, 0, 0}, 0, {0, 0, 0}, 0} : bodies[indices[i]];
        EXPECT_EQ((Vec3{columns[0].lane(i), columns[1].lane(i), columns[2].lane(i)}), expected.velocity);
        EXPECT_EQ(columns[3].lane(i), expected.invMass);
        EXPECT_EQ((Vec3{columns[4].lane(i), columns[5].lane(i), columns[6].lane(i)}), expected.angularVelocity);
        EXPECT_EQ(std::bit_cast<std::uint32_t>(columns[7].lane(i)), expected.flags);  // bits pass through
    }
    // Scatter a changed copy into a fresh array: addressed bodies get it, the rest stay.
    std::array<W, 8> changed = columns;
    changed[3] = changed[3] * W(2.0f);
    std::vector<Body> after = bodies;
    W::template scatterTransposed<8>(after.data(), indices, changed);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        int lane = -1;
        for (int i = 0; i < N; ++i)
            if (indices[i] == k) lane = i;
        EXPECT_EQ(after[k].invMass, lane < 0 ? bodies[k].invMass : 2.0f * bodies[k].invMass);
        EXPECT_EQ(after[k].velocity, bodies[k].velocity);
        EXPECT_EQ(after[k].angularVelocity, bodies[k].angularVelocity);
        EXPECT_EQ(after[k].flags, bodies[k].flags);
    }
}

TYPED_TEST(WideTest, LoadStoreAndLaneSum) {
    using P = TypeParam;
    using W = FloatWide<P>;
    constexpr int N = P::kLanes;
    float in[N + 1], out[N + 1] = {};
    for (int i = 0; i <= N; ++i) in[i] = 0.1f * float(i + 1);
    W::load(in + 1).store(out + 1);  // unaligned on purpose
    for (int i = 1; i <= N; ++i) EXPECT_EQ(out[i], in[i]);
    EXPECT_EQ(out[0], 0.0f);
    float expected = in[1];
    for (int i = 2; i <= N; ++i) expected += in[i];
    EXPECT_EQ(W::load(in + 1).sumLanes(), expected);
    EXPECT_EQ(W().lane(0), 0.0f);  // default is zero
}

TEST(SimdDefault, WidthMatchesTheBuild) {
#if FULCRUM_SIMD_HAS_AVX2 && !defined(FULCRUM_SIMD_PORTABLE)
    EXPECT_EQ(kSimdLanes, 8);
#else
    EXPECT_EQ(kSimdLanes, 4);
#endif
    static_assert(FloatW::kLanes == kSimdLanes && Vec3W::kLanes == kSimdLanes);
}
