// fulcrum::dmath (include/fulcrum/math/deterministic_math.hpp): accuracy
// against the C library over each function's domain, at the bounds the header
// states; the C library's special cases; and the exact bits of a grid of
// values, which every compiler, SIMD path and platform must reproduce (the
// same test runs in the GCC and Clang builds of scripts/test.sh).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "fulcrum/math/deterministic_math.hpp"

namespace dm = fulcrum::dmath;

namespace {

// |got - ref| in units of the last place of ref (in its own precision).
template <class T>
double ulps(T got, T ref) {
    const T a = std::fabs(ref);
    const T ulp = std::nextafter(a, std::numeric_limits<T>::infinity()) - a;
    return std::fabs(static_cast<double>(got) - static_cast<double>(ref)) / static_cast<double>(ulp);
}

class Sampler {
public:
    double uniform(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng_() >> 11) * 0x1p-53); }

private:
    std::mt19937_64 rng_{25};
};

constexpr int kSamples = 200000;

}  // namespace

TEST(DeterministicMath, SinCosWithinOneUlpOnSmallArguments) {
    Sampler s;
    double worst = 0;
    for (int i = 0; i < kSamples; ++i) {
        const double x = s.uniform(-8, 8);
        worst = std::max({worst, ulps(dm::sin(x), std::sin(x)), ulps(dm::cos(x), std::cos(x))});
        double sn = 0, cs = 0;
        dm::sinCos(x, sn, cs);
        ASSERT_EQ(std::bit_cast<std::uint64_t>(sn), std::bit_cast<std::uint64_t>(dm::sin(x))) << x;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(cs), std::bit_cast<std::uint64_t>(dm::cos(x))) << x;
    }
    EXPECT_LE(worst, 1.0);
}

TEST(DeterministicMath, SinCosAbsoluteErrorOnLargeArguments) {
    Sampler s;
    double worst = 0;
    for (int i = 0; i < kSamples; ++i) {
        const double x = s.uniform(-1e6, 1e6);
        worst = std::max({worst, std::fabs(dm::sin(x) - std::sin(x)), std::fabs(dm::cos(x) - std::cos(x))});
    }
    EXPECT_LE(worst, 2.3e-16);
}

TEST(DeterministicMath, ArcFunctionsWithinStatedUlps) {
    Sampler s;
    double atanWorst = 0, atan2Worst = 0, asinWorst = 0, acosWorst = 0;
    for (int i = 0; i < kSamples; ++i) {
        const double t = std::tan(s.uniform(-1.5707, 1.5707));
        atanWorst = std::max(atanWorst, ulps(dm::atan(t), std::atan(t)));
        const double y = s.uniform(-1, 1), x = s.uniform(-1, 1);
        atan2Worst = std::max(atan2Worst, ulps(dm::atan2(y, x), std::atan2(y, x)));
        const double c = s.uniform(-1, 1);
        asinWorst = std::max(asinWorst, ulps(dm::asin(c), std::asin(c)));
        acosWorst = std::max(acosWorst, ulps(dm::acos(c), std::acos(c)));
    }
    EXPECT_LE(atanWorst, 4.0);
    EXPECT_LE(atan2Worst, 4.0);
    EXPECT_LE(asinWorst, 4.0);
    EXPECT_LE(acosWorst, 5.0);
}

TEST(DeterministicMath, FloatOverloadsWithinOneUlpOfTheLibrary) {
    Sampler s;
    double worst = 0;
    for (int i = 0; i < kSamples; ++i) {
        const auto x = static_cast<float>(s.uniform(-8, 8));
        const auto a = static_cast<float>(s.uniform(-1, 1)), b = static_cast<float>(s.uniform(-1, 1));
        worst = std::max({worst, ulps(dm::sin(x), std::sin(x)), ulps(dm::cos(x), std::cos(x)),
                          ulps(dm::atan2(a, b), std::atan2(a, b)), ulps(dm::acos(a), std::acos(a)),
                          ulps(dm::asin(a), std::asin(a)), ulps(dm::atan(x), std::atan(x))});
    }
    EXPECT_LE(worst, 1.0);
}

TEST(DeterministicMath, SpecialCasesFollowTheCLibrary) {
    const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    const double pi = 3.141592653589793;
    EXPECT_EQ(dm::sin(0.0), 0.0);
    EXPECT_EQ(dm::cos(0.0), 1.0);
    EXPECT_TRUE(std::isnan(dm::sin(inf)));
    EXPECT_TRUE(std::isnan(dm::cos(-inf)));
    EXPECT_TRUE(std::isnan(dm::sin(nan)));
    EXPECT_EQ(dm::atan(inf), pi / 2);
    EXPECT_EQ(dm::atan(-inf), -pi / 2);
    EXPECT_EQ(dm::atan2(0.0, 0.0), 0.0);
    EXPECT_FALSE(std::signbit(dm::atan2(0.0, 0.0)));
    EXPECT_TRUE(std::signbit(dm::atan2(-0.0, 0.0)));
    EXPECT_EQ(dm::atan2(0.0, -0.0), pi);
    EXPECT_EQ(dm::atan2(-0.0, -1.0), -pi);
    EXPECT_EQ(dm::atan2(1.0, 0.0), pi / 2);
    EXPECT_EQ(dm::atan2(-1.0, 0.0), -pi / 2);
    EXPECT_EQ(dm::atan2(inf, inf), pi / 4);
    EXPECT_EQ(dm::atan2(-inf, -inf), -3 * pi / 4);
    EXPECT_TRUE(std::isnan(dm::atan2(nan, 1.0)));
    EXPECT_EQ(dm::acos(1.0), 0.0);
    EXPECT_EQ(dm::acos(-1.0), pi);
    EXPECT_EQ(dm::asin(1.0), pi / 2);
    EXPECT_EQ(dm::asin(-1.0), -pi / 2);
    EXPECT_TRUE(std::isnan(dm::acos(1.0000001)));
    EXPECT_TRUE(std::isnan(dm::asin(-2.0)));
    EXPECT_TRUE(std::isnan(dm::acos(nan)));
}

// The bits of every function on a fixed grid, hashed. The value was recorded
// with GCC 12 on x86-64; Clang, the other SIMD paths (this code has none) and
// WebAssembly must give the same, as nothing here depends on the platform.
TEST(DeterministicMath, BitsAreTheRecordedOnes) {
    std::uint64_t h = 14695981039346656037ull;
    const auto add = [&](std::uint64_t bits) {
        for (int i = 0; i < 8; ++i) {
            h ^= (bits >> (8 * i)) & 0xFF;
            h *= 1099511628211ull;
        }
    };
    for (int i = -2000; i <= 2000; ++i) {
        const double x = i * 0.0123456789;  // angles to +-24.7 rad
        const double c = i / 2000.0;        // [-1, 1]
        add(std::bit_cast<std::uint64_t>(dm::sin(x)));
        add(std::bit_cast<std::uint64_t>(dm::cos(x)));
        add(std::bit_cast<std::uint64_t>(dm::atan(x)));
        add(std::bit_cast<std::uint64_t>(dm::atan2(c, x)));
        add(std::bit_cast<std::uint64_t>(dm::acos(c)));
        add(std::bit_cast<std::uint64_t>(dm::asin(c)));
        const auto xf = static_cast<float>(x), cf = static_cast<float>(c);
        add(std::bit_cast<std::uint32_t>(dm::sin(xf)));
        add(std::bit_cast<std::uint32_t>(dm::cos(xf)));
        add(std::bit_cast<std::uint32_t>(dm::atan2(cf, xf)));
        add(std::bit_cast<std::uint32_t>(dm::acos(cf)));
    }
    EXPECT_EQ(h, 0x09dc6fb44bb5e610ull) << std::hex << h;
}
