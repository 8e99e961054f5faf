// The joint blocks' double lanes (joint_wide_kernels.hpp) against the scalar
// functions they stand for. First atan2 (atan2Lanes: the
// cone-twist's swing and twist angles, the hinge's angle) against
// dmath::atan2 one value at a time: the exact bits on every path (SSE2: two
// doubles a register, AVX2: four), over each branch of the scalar function
// (|y| <= |x| and above, atanUnit's reduction above tan(pi/8) and below,
// either side of the boundaries, x = 0, signed zeros, infinities, NaN,
// subnormals) and many random pairs at every scale, with partial blocks (the
// lanes past the last pair are not written).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "fulcrum/math/deterministic_math.hpp"
#include "solver/joints/coupled_row.hpp"
#include "solver/joints/joint_wide.hpp"
#include "solver/joints/joint_wide_checks.hpp"

using namespace fulcrum;
using detail::SimdPath;

// The double lanes stand for float builds' scalar functions only (a double
// build's joint blocks keep the scalar path), so the whole file is float-only.
#if !FULCRUM_DOUBLE

namespace {

std::vector<SimdPath> widePaths() {
    std::vector<SimdPath> paths = {SimdPath::Sse2};
    if (detail::avx2Available() && detail::avx2JointKernelsCompiled()) paths.push_back(SimdPath::Avx2);
    return paths;
}

// Every pair through the path's lanes, compared bit for bit with dmath::atan2
// (NaN: any NaN, as the scalar one gives x + y's).
void expectSameBits(SimdPath path, const std::vector<Real>& y, const std::vector<Real>& x) {
    std::vector<Real> out(y.size() + 1, Real(12345));
    ASSERT_TRUE(detail::wideAtan2(path, y.data(), x.data(), out.data(), y.size()));
    EXPECT_EQ(out.back(), Real(12345)) << "wrote past the last pair";
    int mismatches = 0;
    for (std::size_t i = 0; i < y.size(); ++i) {
        const Real ref = dmath::atan2(y[i], x[i]);
        const bool same = std::isnan(ref) ? std::isnan(out[i]) : std::bit_cast<std::uint32_t>(out[i]) == std::bit_cast<std::uint32_t>(ref);
        if (!same && ++mismatches <= 10) {
            ADD_FAILURE() << "path " << static_cast<int>(path) << ": atan2(" << y[i] << ", " << x[i] << ") = " << out[i]
                          << " in lanes, " << ref << " scalar";
        }
    }
    EXPECT_EQ(mismatches, 0);
}

}  // namespace

TEST(JointSimdDoubleLanes, SpecialValuesHaveTheScalarBits) {
    const Real inf = std::numeric_limits<Real>::infinity(), nan = std::numeric_limits<Real>::quiet_NaN();
    const Real tiny = std::numeric_limits<Real>::denorm_min(), small = std::numeric_limits<Real>::min();
    const Real big = std::numeric_limits<Real>::max();
    // tan(pi/8) (atanUnit's switch), tan(pi/16), 1 (the |y| <= |x| switch), and their float neighbours.
    const Real t8 = Real(0.41421356237309503), t16 = Real(0.19891236737965800);
    std::vector<Real> values = {0, -0.0f, 1, -1, 0.5f, -2, tiny, -tiny, small, -small, big, -big, inf, -inf, nan, -nan,
                                t8, t16, Real(3.14159265f), Real(1e-20f), Real(1e20f)};
    for (const Real v : {t8, t16, Real(1)}) {
        values.push_back(std::nextafter(v, Real(0)));
        values.push_back(std::nextafter(v, Real(2)));
    }
    std::vector<Real> ys, xs;
    for (const Real y : values) {
        for (const Real x : values) {
            ys.push_back(y);
            xs.push_back(x);
        }
    }
    for (const SimdPath path : widePaths()) {
        // Every count from 1 to 17: the partial blocks of 4 and 8 lanes.
        for (std::size_t n = 1; n <= 17; ++n) expectSameBits(path, std::vector<Real>(ys.begin(), ys.begin() + n), std::vector<Real>(xs.begin(), xs.begin() + n));
        expectSameBits(path, ys, xs);
    }
}

TEST(JointSimdDoubleLanes, RandomPairsHaveTheScalarBits) {
    std::mt19937 rng(2026);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::uniform_int_distribution<int> exponent(-40, 40);
    std::vector<Real> ys, xs;
    for (int i = 0; i < 200000; ++i) {
        // Angles as the joints see them (unit-scale pairs), then pairs at every scale.
        const bool scaled = i % 2 == 1;
        ys.push_back(scaled ? std::ldexp(unit(rng), exponent(rng)) : unit(rng));
        xs.push_back(scaled ? std::ldexp(unit(rng), exponent(rng)) : unit(rng));
    }
    for (const SimdPath path : widePaths()) expectSameBits(path, ys, xs);
}

// The hinge blocks' 5 x 5 coupling solve in lanes of doubles
// (coupledInverseMassLanes) against the scalar coupledInverseMass on the
// same float couplings: the same verdict and, where it succeeds, the same
// float c and Schur complement, bit for bit, on SSE2 and AVX2. The systems:
// K_oo = A A^T + diagonal (well and badly conditioned: diagonals from 1e-6
// to 1e3), singular ones (a repeated row: the Cholesky's early return),
// a negative diagonal, NaN entries, and Schur complements near the 1e-12
// guard (K_aa just above K_ao K_oo^-1 K_oa).
TEST(JointSimdDoubleLanes, HingeCouplingSolvesHaveTheScalarBits) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::uniform_int_distribution<int> exponent(-20, 10);
    const int n = 4001;
    std::vector<Real> K(15 * n), Kia(5 * n), kaa(n);
    for (int s = 0; s < n; ++s) {
        float A[5][5], a[5];
        for (auto& row : A) {
            for (float& v : row) v = unit(rng);
        }
        for (float& v : a) v = unit(rng);
        const int kind = s % 5;
        if (kind == 1) {
            for (int j = 0; j < 5; ++j) A[3][j] = A[1][j];  // rank 4: singular with no diagonal
        }
        float M[5][5];
        for (int i = 0; i < 5; ++i) {
            for (int j = 0; j < 5; ++j) {
                float t = 0;
                for (int k = 0; k < 5; ++k) t += A[i][k] * A[j][k];
                M[i][j] = t;
            }
            if (kind != 1) M[i][i] += std::ldexp(1.0f, exponent(rng));
        }
        if (kind == 2 && s % 10 == 2) M[2][2] = -M[2][2];
        if (kind == 2 && s % 10 == 7) M[4][1] = std::numeric_limits<float>::quiet_NaN();
        float aa = 0;
        for (int i = 0; i < 5; ++i) aa += a[i] * a[i];
        int e = 0;
        for (int i = 0; i < 5; ++i) {
            for (int j = 0; j <= i; ++j) K[15 * s + e++] = M[i][j];
            // K_oa = M a: then K_ao K_oo^-1 K_oa = a^T M a, and K_aa = a^T M a (1 + tiny) sits at the guard.
            float t = 0;
            for (int j = 0; j < 5; ++j) t += M[i][j] * a[j];
            Kia[5 * s + i] = t;
        }
        float ama = 0;
        for (int i = 0; i < 5; ++i) ama += a[i] * Kia[5 * s + i];
        kaa[s] = kind == 3 ? ama * (1.0f + std::ldexp(1.0f, -exponent(rng) - 20)) : ama + aa + 1.0f;
    }
    for (const SimdPath path : widePaths()) {
        std::vector<Real> c(5 * n, Real(-7)), schur(n, Real(-7));
        std::unique_ptr<bool[]> ok(new bool[n]);
        ASSERT_TRUE(detail::wideCoupledInverseMass(path, K.data(), Kia.data(), kaa.data(), c.data(), schur.data(), ok.get(), n));
        int failures = 0, mismatches = 0;
        for (int s = 0; s < n; ++s) {
            double L[detail::kMaxHeldRows][detail::kMaxHeldRows] = {};
            double rhs[detail::kMaxHeldRows] = {};
            int e = 0;
            for (int i = 0; i < 5; ++i) {
                for (int j = 0; j <= i; ++j) L[i][j] = static_cast<double>(K[15 * s + e++]);
                rhs[i] = -static_cast<double>(Kia[5 * s + i]);
            }
            double solved[detail::kMaxHeldRows];
            double kk = 0;
            const bool ref = detail::coupledInverseMass(L, rhs, 5, static_cast<double>(kaa[s]), solved, kk);
            failures += ref ? 0 : 1;
            bool same = ref == ok[s];
            if (same && ref) {
                for (int i = 0; i < 5; ++i) {
                    same = same && std::bit_cast<std::uint32_t>(c[5 * s + i]) == std::bit_cast<std::uint32_t>(static_cast<Real>(solved[i]));
                }
                same = same && std::bit_cast<std::uint32_t>(schur[s]) == std::bit_cast<std::uint32_t>(static_cast<Real>(kk));
            }
            if (!same && ++mismatches <= 10) ADD_FAILURE() << "path " << static_cast<int>(path) << ": system " << s << " differs";
        }
        EXPECT_EQ(mismatches, 0);
        // Both outcomes are exercised: the singular systems fail, most others pass.
        EXPECT_GT(failures, n / 5);
        EXPECT_LT(failures, n / 2);
    }
}
#endif  // !FULCRUM_DOUBLE
