// The wide joint kernels (joint_wide.hpp): the lane math every kind shares,
// each kind's blocks from its own file (ball_wide.hpp, cone_twist_wide.hpp,
// hinge_wide.hpp, beside the type's scalar kernels) and the Blocks class that
// runs them, written once over a simd.hpp policy and compiled once per
// width, as the contact kernels are
// (contact_wide_kernels.hpp): a translation unit defines
//   FULCRUM_JOINT_WIDE_NS      the namespace of this copy (joint_sse2, joint_avx2)
//   FULCRUM_JOINT_WIDE_POLICY  the simd.hpp policy
// and includes this file once. Everything here is in an unnamed namespace, so
// the AVX2 copy is its translation unit's own; it calls no shared inline
// function of the scalar math (Mat3's inverse, rotate...) that the linker
// could pick an AVX2-compiled copy of for code running on a CPU without AVX2:
// the kernels spell the operations out on the wide types.
#ifndef FULCRUM_JOINT_WIDE_NS
#error "define FULCRUM_JOINT_WIDE_NS and FULCRUM_JOINT_WIDE_POLICY before including joint_wide_kernels.hpp"
#endif
// Run as each entry point returns (the AVX2 copy: _mm256_zeroupper(), for
// the reason contact_wide_kernels.hpp gives).
#ifndef FULCRUM_JOINT_WIDE_LEAVE
#define FULCRUM_JOINT_WIDE_LEAVE() ((void)0)
#endif

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <numbers>
#include <type_traits>
#include <vector>

#include "math/simd.hpp"
#include "solver/contact_solver.hpp"
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_wide.hpp"

namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS {
namespace {

using Policy = FULCRUM_JOINT_WIDE_POLICY;
using FloatW = simd::FloatWide<Policy>;
using MaskW = simd::MaskWide<Policy>;
using Vec3W = simd::Vec3Wide<Policy>;
using simd::kEmptyLane;
constexpr int kLanes = Policy::kLanes;

#define FULCRUM_JOINT_WIDE_INLINE inline __attribute__((always_inline))

static_assert(sizeof(SolverBody) == 24 * sizeof(Real) && std::is_trivially_copyable_v<SolverBody>,
              "the kernels read a solver body as 24 floats: v, invMass, w, dp, dtheta, invI, padding");
static_assert(sizeof(Quat) == 4 * sizeof(Real) && std::is_trivially_copyable_v<Quat>,
              "the kernels read a rotation as 4 floats: w, x, y, z");
static_assert(sizeof(FloatW) == kLanes * sizeof(Real) && std::is_trivially_copyable_v<FloatW>);

// Column-major like Mat3 (c0, c1, c2), so its products are Mat3's, term for term.
struct Mat3W {
    Vec3W c0, c1, c2;
};

// m v = c0 v.x + c1 v.y + c2 v.z (fulcrum's Mat3 * Vec3, term for term).
FULCRUM_JOINT_WIDE_INLINE Vec3W operator*(const Mat3W& m, const Vec3W& v) { return m.c0 * v.x + m.c1 * v.y + m.c2 * v.z; }
// a b, column by column (fulcrum's Mat3 * Mat3).
FULCRUM_JOINT_WIDE_INLINE Mat3W operator*(const Mat3W& a, const Mat3W& b) { return {a * b.c0, a * b.c1, a * b.c2}; }

// Mat3::skew(r): the matrix of v -> r x v, with its exact zeros.
FULCRUM_JOINT_WIDE_INLINE Mat3W skew(const Vec3W& r) {
    const FloatW zero = 0.0f;
    return {{zero, r.z, -r.y}, {-r.z, zero, r.x}, {r.y, -r.x, zero}};
}

FULCRUM_JOINT_WIDE_INLINE Mat3W operator+(const Mat3W& a, const Mat3W& b) { return {a.c0 + b.c0, a.c1 + b.c1, a.c2 + b.c2}; }
FULCRUM_JOINT_WIDE_INLINE Mat3W operator-(const Mat3W& a, const Mat3W& b) { return {a.c0 - b.c0, a.c1 - b.c1, a.c2 - b.c2}; }
// Mat3::fromRows and transpose.
FULCRUM_JOINT_WIDE_INLINE Mat3W fromRows(const Vec3W& r0, const Vec3W& r1, const Vec3W& r2) {
    return {{r0.x, r1.x, r2.x}, {r0.y, r1.y, r2.y}, {r0.z, r1.z, r2.z}};
}
FULCRUM_JOINT_WIDE_INLINE Mat3W transpose(const Mat3W& m) { return fromRows(m.c0, m.c1, m.c2); }
FULCRUM_JOINT_WIDE_INLINE Mat3W select(const MaskW& m, const Mat3W& a, const Mat3W& b) {
    return {select(m, a.c0, b.c0), select(m, a.c1, b.c1), select(m, a.c2, b.c2)};
}

// inverse(m) where determinant(m) = c0 . (c1 x c2) > 0 (`valid`), as Mat3's
// adjugate spells it (fromRows(r0, r1, r2) * (1 / det)); other lanes: `otherwise`.
FULCRUM_JOINT_WIDE_INLINE Mat3W inverseWherePositive(const Mat3W& m, MaskW& valid, const Mat3W& otherwise) {
    const Vec3W r0 = cross(m.c1, m.c2), r1 = cross(m.c2, m.c0), r2 = cross(m.c0, m.c1);
    const FloatW det = dot(m.c0, r0);
    valid = det > FloatW(0.0f);
    const FloatW inv = FloatW(1.0f) / det;
    const Mat3W adj = fromRows(r0, r1, r2);
    return select(valid, Mat3W{adj.c0 * inv, adj.c1 * inv, adj.c2 * inv}, otherwise);
}

// A quaternion per lane (w, x, y, z), Quat's products term for term.
struct QuatW {
    FloatW w, x, y, z;
};
FULCRUM_JOINT_WIDE_INLINE QuatW operator*(const QuatW& a, const QuatW& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
FULCRUM_JOINT_WIDE_INLINE QuatW conjugate(const QuatW& q) { return {q.w, -q.x, -q.y, -q.z}; }
FULCRUM_JOINT_WIDE_INLINE Vec3W rotate(const QuatW& q, const Vec3W& v) {
    const Vec3W u{q.x, q.y, q.z};
    const Vec3W t = cross(u, v) * FloatW(2.0f);
    return (v + t * q.w) + cross(u, t);
}
FULCRUM_JOINT_WIDE_INLINE QuatW gatherRotation(const Quat* rotations, const std::uint32_t* index) {
    const std::array<FloatW, 4> q = FloatW::gatherTransposed<4>(rotations, index);
    return {q[0], q[1], q[2], q[3]};
}

#if FULCRUM_SIMD_HAS_SSE2 && (defined(__GNUC__) || defined(__clang__))
// dmath::atan2 (deterministic_math.hpp) on lanes of doubles, the same bits
// lane by lane: it is built from + - * / and sqrt, each IEEE-rounded per lane
// as in the scalar code (no FMA: -ffp-contract=off, never -mfma), every
// operation of the scalar code done in its order, with its constants; its
// branches become selects (both sides computed, the scalar one's kept: the
// side not taken may divide 0 by 0 or inf by inf, which traps nothing and is
// dropped), its exact operations (fabs, copysign, signbit) are bit masks.
// Two lanes of doubles per register on the baseline (SSE2), four on AVX2.
// rain(4x2): the lanes called dmath::atan2 one by one, 42 M of 1,373 M
// instructions in the step (branch rain9, docs/benchmarks.md).
#if defined(__AVX__)
typedef double LanesD __attribute__((vector_size(32)));
typedef float LanesF __attribute__((vector_size(16)));
#else
typedef double LanesD __attribute__((vector_size(16)));
typedef float LanesF __attribute__((vector_size(8)));
#endif
using LanesM = decltype(LanesD{} < LanesD{});  // a lane's mask: all bits or none
constexpr int kDoubleLanes = static_cast<int>(sizeof(LanesD) / sizeof(double));
static_assert(kLanes % kDoubleLanes == 0 && sizeof(LanesM) == sizeof(LanesD));

FULCRUM_JOINT_WIDE_INLINE LanesD splatD(double v) {
    LanesD r = {};
    for (int i = 0; i < kDoubleLanes; ++i) r[i] = v;
    return r;
}
FULCRUM_JOINT_WIDE_INLINE LanesM bitsD(const LanesD& v) { return std::bit_cast<LanesM>(v); }
FULCRUM_JOINT_WIDE_INLINE LanesD fromBitsD(const LanesM& m) { return std::bit_cast<LanesD>(m); }
FULCRUM_JOINT_WIDE_INLINE LanesD selectD(const LanesM& m, const LanesD& a, const LanesD& b) {
#if defined(__AVX__)
    return _mm256_blendv_pd(b, a, fromBitsD(m));  // m's lanes are all ones or all zeros
#else
    return fromBitsD((bitsD(a) & m) | (bitsD(b) & ~m));
#endif
}
FULCRUM_JOINT_WIDE_INLINE LanesD sqrtD(const LanesD& v) {
#if defined(__AVX__)
    return _mm256_sqrt_pd(v);
#else
    return _mm_sqrt_pd(v);
#endif
}

// dmath::detail::atanUnit.
FULCRUM_JOINT_WIDE_INLINE LanesD atanUnitLanes(LanesD t) {
    const LanesD zero = splatD(0.0), one = splatD(1.0);
    const LanesM above = t > splatD(0.41421356237309503);
    t = selectD(above, (t - one) / (t + one), t);
    const LanesD base = selectD(above, splatD(dmath::detail::kQuarterPiHi), zero);
    const LanesD baseLo = selectD(above, splatD(dmath::detail::kQuarterPiLo), zero);
    const LanesD u = t / (one + sqrtD(one + t * t));
    const LanesD z = u * u;
    const LanesD p =
        splatD(-1.0 / 3) +
        z * (splatD(1.0 / 5) +
             z * (splatD(-1.0 / 7) +
                  z * (splatD(1.0 / 9) +
                       z * (splatD(-1.0 / 11) +
                            z * (splatD(1.0 / 13) +
                                 z * (splatD(-1.0 / 15) +
                                      z * (splatD(1.0 / 17) +
                                           z * (splatD(-1.0 / 19) + z * (splatD(1.0 / 21) + z * (splatD(-1.0 / 23) + z * splatD(1.0 / 25)))))))))));
    const LanesD atanU = u + u * (z * p);
    return base + (splatD(2.0) * atanU + baseLo);
}

// dmath::atan2(double, double).
FULCRUM_JOINT_WIDE_INLINE LanesD atan2DoubleLanes(const LanesD& y, const LanesD& x) {
    LanesM magnitude = {};
    for (int i = 0; i < kDoubleLanes; ++i) magnitude[i] = 0x7fffffffffffffffLL;
    const LanesD zero = splatD(0.0), infinity = splatD(std::numeric_limits<double>::infinity());
    const LanesD ax = fromBitsD(bitsD(x) & magnitude), ay = fromBitsD(bitsD(y) & magnitude);
    // ay <= ax: atanUnit(ay / ax) (0 where ax == 0); else pi/2 - atanUnit(ax / ay).
    const LanesM steep = ~(ay <= ax);
    const LanesD unit = atanUnitLanes(selectD(steep, ax, ay) / selectD(steep, ay, ax));
    LanesD a = selectD(steep, splatD(dmath::detail::kHalfPiHi) + (splatD(dmath::detail::kHalfPiLo) - unit), unit);
    a = selectD(~steep & (ax == zero), zero, a);
    a = selectD((ax == infinity) & (ay == infinity), splatD(dmath::detail::kQuarterPiHi), a);
    // signbit(x): pi - a; then copysign(a, y).
    a = selectD(bitsD(x) < LanesM{}, splatD(dmath::detail::kPiHi) + (splatD(dmath::detail::kPiLo) - a), a);
    a = fromBitsD((bitsD(a) & magnitude) | (bitsD(y) & ~magnitude));
    return selectD((x != x) | (y != y), x + y, a);
}

// coupledInverseMass (coupled_row.hpp) for count = 5 on lanes of doubles,
// the same bits lane by lane: its Cholesky, forward and back substitution
// and Schur complement, each operation in the scalar order; fmax for the
// scale is a select that ignores NaN as fmax does (its result only enters
// the comparisons, where a zero's sign does not count). `ok`: the lanes where
// the scalar function returns true (its early returns are the mask's
// failures; a failed lane's c and schur are not the scalar's and are not
// used). L's lower triangle is read; rhs = -K_oa; kaa = K_aa.
FULCRUM_JOINT_WIDE_INLINE void coupledInverseMassLanes(LanesD (&L)[5][5], const LanesD (&rhs)[5], const LanesD& kaa,
                                                       LanesD (&c)[5], LanesD& schur, LanesM& ok) {
    LanesD scale = splatD(0.0);
    for (int i = 0; i < 5; ++i) scale = selectD(L[i][i] > scale, L[i][i], scale);
    ok = ~LanesM{};
    for (int j = 0; j < 5; ++j) {
        LanesD s = L[j][j];
        for (int k = 0; k < j; ++k) s -= L[j][k] * L[j][k];
        ok &= s > splatD(1e-9) * scale;
        const LanesD d = sqrtD(s);
        L[j][j] = d;
        for (int i = j + 1; i < 5; ++i) {
            LanesD t = L[i][j];
            for (int k = 0; k < j; ++k) t -= L[i][k] * L[j][k];
            L[i][j] = t / d;
        }
    }
    for (int i = 0; i < 5; ++i) {
        LanesD t = rhs[i];
        for (int k = 0; k < i; ++k) t -= L[i][k] * c[k];
        c[i] = t / L[i][i];
    }
    for (int i = 5; i-- > 0;) {
        LanesD t = c[i];
        for (int k = i + 1; k < 5; ++k) t -= L[k][i] * c[k];
        c[i] = t / L[i][i];
    }
    schur = kaa;
    for (int i = 0; i < 5; ++i) schur -= rhs[i] * c[i];
    ok &= schur > splatD(1e-12) * kaa;
}

FULCRUM_JOINT_WIDE_INLINE LanesD doubleLanesOf(const Real* floats) {
    LanesF f;
    std::memcpy(&f, floats, sizeof(f));
    return __builtin_convertvector(f, LanesD);
}
FULCRUM_JOINT_WIDE_INLINE void storeFloatLanes(Real* floats, const LanesD& v) {
    const LanesF f = __builtin_convertvector(v, LanesF);
    std::memcpy(floats, &f, sizeof(f));
}
#define FULCRUM_JOINT_WIDE_DOUBLE_LANES 1

// coupledInverseMassLanes over n systems, as coupleHingeRow calls it (its
// float inputs widened, c and the Schur complement rounded to floats):
// system s reads K[15 s ..] (the lower triangle by rows), Kia[5 s ..] and
// kaa[s], and writes ok[s] and, where ok, c[5 s ..] and schur[s]
// (wideCoupledInverseMass, for tests).
void coupledArray(const Real* K, const Real* Kia, const Real* kaa, Real* c, Real* schur, bool* ok, std::size_t n) {
    for (std::size_t first = 0; first < n; first += kDoubleLanes) {
        alignas(32) Real lanes[5][5][kDoubleLanes] = {}, rhsLanes[5][kDoubleLanes] = {}, kaaLanes[kDoubleLanes] = {};
        for (int w = 0; w < kDoubleLanes && first + w < n; ++w) {
            const std::size_t sys = first + w;
            int e = 0;
            for (int i = 0; i < 5; ++i) {
                for (int j = 0; j <= i; ++j) lanes[i][j][w] = K[15 * sys + e++];
                rhsLanes[i][w] = Kia[5 * sys + i];
            }
            kaaLanes[w] = kaa[sys];
        }
        LanesD L[5][5], rhs[5], solved[5], kk;
        for (int i = 0; i < 5; ++i) {
            for (int j = 0; j < 5; ++j) L[i][j] = j <= i ? doubleLanesOf(lanes[i][j]) : splatD(0.0);
            rhs[i] = -doubleLanesOf(rhsLanes[i]);
        }
        LanesM good;
        coupledInverseMassLanes(L, rhs, doubleLanesOf(kaaLanes), solved, kk, good);
        alignas(32) Real cs[5][kDoubleLanes], ks[kDoubleLanes];
        for (int i = 0; i < 5; ++i) storeFloatLanes(cs[i], solved[i]);
        storeFloatLanes(ks, kk);
        for (int w = 0; w < kDoubleLanes && first + w < n; ++w) {
            const std::size_t sys = first + w;
            ok[sys] = good[w] != 0;
            if (!ok[sys]) continue;
            for (int i = 0; i < 5; ++i) c[5 * sys + i] = cs[i][w];
            schur[sys] = ks[w];
        }
    }
    FULCRUM_JOINT_WIDE_LEAVE();
}

// atan2 per lane (lanes [0, laneCount); the rest 0): dmath::atan2 on floats
// (the double result rounded once), as the scalar code calls it, in lanes.
FULCRUM_JOINT_WIDE_INLINE FloatW atan2Lanes(const FloatW& y, const FloatW& x, std::uint32_t laneCount) {
    static_assert(std::is_same_v<Real, float>);
    alignas(32) Real ys[kLanes], xs[kLanes], out[kLanes] = {};
    y.store(ys);
    x.store(xs);
    for (int i = 0; i < static_cast<int>(laneCount); i += kDoubleLanes) {
        LanesF fy, fx;
        std::memcpy(&fy, ys + i, sizeof(fy));
        std::memcpy(&fx, xs + i, sizeof(fx));
        const LanesF r = __builtin_convertvector(
            atan2DoubleLanes(__builtin_convertvector(fy, LanesD), __builtin_convertvector(fx, LanesD)), LanesF);
        std::memcpy(out + i, &r, sizeof(r));
    }
    for (int l = static_cast<int>(laneCount); l < kLanes; ++l) out[l] = 0;
    return FloatW::load(out);
}
#else
// atan2 per lane (lanes [0, laneCount); the rest 0): the lanes call the same
// function the scalar code does (dmath::atan2 on floats), so both paths
// round alike.
FULCRUM_JOINT_WIDE_INLINE FloatW atan2Lanes(const FloatW& y, const FloatW& x, std::uint32_t laneCount) {
    alignas(32) Real ys[kLanes], xs[kLanes], out[kLanes] = {};
    y.store(ys);
    x.store(xs);
    for (std::uint32_t l = 0; l < laneCount; ++l) out[l] = dmath::atan2(ys[l], xs[l]);
    return FloatW::load(out);
}
#endif

// atan2Lanes over n pairs, kLanes at a time (wideAtan2, for tests).
void atan2Array(const Real* y, const Real* x, Real* out, std::size_t n) {
    alignas(32) Real ys[kLanes], xs[kLanes], rs[kLanes];
    for (std::size_t first = 0; first < n; first += kLanes) {
        const std::size_t count = n - first < static_cast<std::size_t>(kLanes) ? n - first : kLanes;
        for (int l = 0; l < kLanes; ++l) {
            const bool used = static_cast<std::size_t>(l) < count;
            ys[l] = used ? y[first + l] : Real(0);
            xs[l] = used ? x[first + l] : Real(1);
        }
        atan2Lanes(FloatW::load(ys), FloatW::load(xs), static_cast<std::uint32_t>(count)).store(rs);
        for (std::size_t l = 0; l < count; ++l) out[first + l] = rs[l];
    }
    FULCRUM_JOINT_WIDE_LEAVE();
}

// twistAngle: r = (conj(qA) qB) conj(relative0), turned to r.w >= 0, and
// 2 atan2(r.vec . localAxis, r.w).
FULCRUM_JOINT_WIDE_INLINE FloatW twistAngle(const QuatW& relative0Conjugate, const QuatW& qA, const QuatW& qB,
                                            const Vec3W& localAxis, std::uint32_t laneCount) {
    QuatW r = (conjugate(qA) * qB) * relative0Conjugate;
    const MaskW flip = r.w < FloatW(0.0f);
    r = {select(flip, -r.w, r.w), select(flip, -r.x, r.x), select(flip, -r.y, r.y), select(flip, -r.z, r.z)};
    return FloatW(2.0f) * atan2Lanes(dot(Vec3W{r.x, r.y, r.z}, localAxis), r.w, laneCount);
}

// One lane of a wide value, in place (simd.hpp).
using simd::getLane;
using simd::setLane;

// A body's solver state, gathered by whole rows (simd.hpp's transposed
// gathers: a 16-byte load per lane and 4 floats, then a transpose in
// registers). Floats 8-11 (dp.y, dp.z, dtheta.x, dtheta.y) only where the
// frame is recomputed (`deltas`): the other passes skip that load.
struct BodyW {
    std::array<FloatW, 24> row;
    Vec3W v() const { return {row[0], row[1], row[2]}; }
    FloatW invMass() const { return row[3]; }
    Vec3W w() const { return {row[4], row[5], row[6]}; }
    Vec3W dp() const { return {row[7], row[8], row[9]}; }
    Mat3W invI() const { return {{row[13], row[14], row[15]}, {row[16], row[17], row[18]}, {row[19], row[20], row[21]}}; }
};

// Floats [first, first + 4) of every lane's row into b.row (a named function,
// not a lambda: a lambda would not be always-inline, and when the kernels
// grew GCC made it a call per group: the grid's ball joints +11 % of the
// instructions, callgrind, ninth session).
template <class Rows>
FULCRUM_JOINT_WIDE_INLINE void gatherGroup(const Real* const* rows, std::size_t first, Rows& b) {
    typename Policy::Reg regs[4];
    const Real* shifted[kLanes];
    for (int i = 0; i < kLanes; ++i) shifted[i] = rows[i] + first;
    Policy::loadTransposed4(shifted, regs);
    for (std::size_t c = 0; c < 4; ++c) b.row[first + c] = FloatW(regs[c]);
}

// `index` holds a solver body in every lane (empty lanes: body 0, never kEmptyLane).
template <bool deltas>
FULCRUM_JOINT_WIDE_INLINE BodyW gatherBody(const SolverBody* bodies, const std::uint32_t* index) {
    const Real* rows[kLanes];
    for (int i = 0; i < kLanes; ++i) rows[i] = reinterpret_cast<const Real*>(bodies + index[i]);
    BodyW b;
    gatherGroup(rows, 0, b);
    gatherGroup(rows, 4, b);
    if constexpr (deltas) gatherGroup(rows, 8, b);
    gatherGroup(rows, 12, b);
    gatherGroup(rows, 16, b);
    gatherGroup(rows, 20, b);
    return b;
}

// Writes v and w back (floats 0-7 of each row; invMass and dp.x unchanged).
template <class Rows>
FULCRUM_JOINT_WIDE_INLINE void scatterVelocity(SolverBody* bodies, const std::uint32_t* index, const Rows& body,
                                               const Vec3W& v, const Vec3W& w) {
    const std::array<FloatW, 8> row = {v.x, v.y, v.z, body.row[3], w.x, w.y, w.z, body.row[7]};
    FloatW::scatterTransposed<8>(bodies, index, row);
}

// Floats 0-11 of a body's row (v, invMass, w, dp, and dtheta.x, dtheta.y):
// the part of it the hinge and cone-twist blocks gather in every pass.
struct EndRowsW {
    std::array<FloatW, 12> row;
    Vec3W dp() const { return {row[7], row[8], row[9]}; }
};

// A block's two ends while its rows run: the gathered rows and the
// velocities as the rows change them (the scalar kernels' a.v, a.w, b.v, b.w).
struct Ends {
    EndRowsW a, b;
    Vec3W vA, wA, vB, wB;
    Mat3W invIA, invIB;
    FloatW mA, mB;
};

// The ends of a hinge or cone-twist block: floats 0-7 of each row (and 8-11
// with `deltas`) from the rows' addresses the block keeps (unless `bodies` is
// not the array it was built on); the inverse inertias are the block's copies
// (FramedLanes).
template <bool deltas, class Block>
FULCRUM_JOINT_WIDE_INLINE Ends gatherEnds(const SolverBody* bodies, const Block& k) {
    Ends e;
    const Real* const* rowsA = k.rowA;
    const Real* const* rowsB = k.rowB;
    const Real* ownA[kLanes];
    const Real* ownB[kLanes];
    if (bodies != k.rowsOf) [[unlikely]] {
        for (int i = 0; i < kLanes; ++i) {
            ownA[i] = reinterpret_cast<const Real*>(bodies + k.bodyA[i]);
            ownB[i] = reinterpret_cast<const Real*>(bodies + k.bodyB[i]);
        }
        rowsA = ownA;
        rowsB = ownB;
    }
    gatherGroup(rowsA, 0, e.a);
    gatherGroup(rowsA, 4, e.a);
    gatherGroup(rowsB, 0, e.b);
    gatherGroup(rowsB, 4, e.b);
    if constexpr (deltas) {
        gatherGroup(rowsA, 8, e.a);
        gatherGroup(rowsB, 8, e.b);
    }
    e.vA = {e.a.row[0], e.a.row[1], e.a.row[2]};
    e.wA = {e.a.row[4], e.a.row[5], e.a.row[6]};
    e.vB = {e.b.row[0], e.b.row[1], e.b.row[2]};
    e.wB = {e.b.row[4], e.b.row[5], e.b.row[6]};
    e.invIA = k.invIA;
    e.invIB = k.invIB;
    e.mA = e.a.row[3];
    e.mB = e.b.row[3];
    return e;
}

// A JointRow per lane (+linear and +angularB on B, -linear and -angularA on A).
struct RowW {
    Vec3W linear, angularA, angularB;
};
// angularRow(axis): a zero linear part, kept so the products are the scalar ones.
FULCRUM_JOINT_WIDE_INLINE RowW angularRow(const Vec3W& axis) { return {Vec3W{}, axis, axis}; }

// rowVelocity, rowInverseMass, applyRow (joint_common.hpp), term for term.
FULCRUM_JOINT_WIDE_INLINE FloatW rowVelocity(const RowW& r, const Ends& e) {
    return dot(r.linear, e.vB - e.vA) + dot(r.angularB, e.wB) - dot(r.angularA, e.wA);
}
FULCRUM_JOINT_WIDE_INLINE FloatW rowInverseMass(const RowW& r, const Ends& e) {
    return (e.mA + e.mB) * lengthSquared(r.linear) + dot(r.angularA, e.invIA * r.angularA) +
           dot(r.angularB, e.invIB * r.angularB);
}
// applyRow where `on`; other lanes keep their velocities.
FULCRUM_JOINT_WIDE_INLINE void applyRow(const RowW& r, Ends& e, const FloatW& impulse, const MaskW& on) {
    e.vA = select(on, e.vA - r.linear * (e.mA * impulse), e.vA);
    e.wA = select(on, e.wA - e.invIA * (r.angularA * impulse), e.wA);
    e.vB = select(on, e.vB + r.linear * (e.mB * impulse), e.vB);
    e.wB = select(on, e.wB + e.invIB * (r.angularB * impulse), e.wB);
}

// applyPoint where `on`.
FULCRUM_JOINT_WIDE_INLINE void applyPoint(Ends& e, const Vec3W& rA, const Vec3W& rB, const Vec3W& P, const MaskW& on) {
    e.vA = select(on, e.vA - P * e.mA, e.vA);
    e.wA = select(on, e.wA - e.invIA * cross(rA, P), e.wA);
    e.vB = select(on, e.vB + P * e.mB, e.vB);
    e.wB = select(on, e.wB + e.invIB * cross(rB, P), e.wB);
}

// pointInverseMass: diag(mA + mB) - [rA] IA^-1 [rA] - [rB] IB^-1 [rB].
FULCRUM_JOINT_WIDE_INLINE Mat3W pointInverseMass(const Ends& e, const Vec3W& rA, const Vec3W& rB) {
    const FloatW zero = 0.0f;
    const Mat3W sa = skew(rA), sb = skew(rB);
    const Mat3W ta = sa * e.invIA * sa;
    const Mat3W tb = sb * e.invIB * sb;
    const FloatW m = e.mA + e.mB;
    const Mat3W diagonal{{m, zero, zero}, {zero, m, zero}, {zero, zero, m}};
    return diagonal - ta - tb;
}

// A tree joint's frame into its record (JointFrame, and the refresh it is
// of), for the lanes with `direct` > 0: the tree solver's pass after the
// blocks then finds it current (currentFrame) instead of computing it again
// (ragdolls, callgrind: the tree solver 261 M -> 341 M without it). Same bits:
// the lanes computed what updateFrame computes.
FULCRUM_JOINT_WIDE_INLINE void writeTreeFrames(JointConstraint* constraints, const std::uint32_t* constraint,
                                               std::uint32_t laneCount, const FloatW& direct, const Vec3W& rA,
                                               const Vec3W& rB, const Vec3W& d, const QuatW& qA, const QuatW& qB,
                                               std::uint64_t generation) {
    // JointFrame as 17 floats (rA, rB, d, qA, qB): floats 0-15 of every
    // written lane by four transposed stores, float 16 (qB.z) lane by lane
    // (the lanes one by one cost 13.7 M of rain(4x2)'s 1,318 M, branch rain9).
    static_assert(std::is_trivially_copyable_v<JointFrame> && sizeof(JointFrame) == 17 * sizeof(Real) &&
                      offsetof(JointFrame, rB) == 3 * sizeof(Real) && offsetof(JointFrame, d) == 6 * sizeof(Real) &&
                      offsetof(JointFrame, qA) == 9 * sizeof(Real) && offsetof(JointFrame, qB) == 13 * sizeof(Real),
                  "JointFrame: rA, rB, d, qA (w, x, y, z), qB, packed floats");
    alignas(32) Real sink[16];
    Real* rows[kLanes];
    bool any = false;
    for (int i = 0; i < kLanes; ++i) {
        const bool write = static_cast<std::uint32_t>(i) < laneCount && getLane(direct, i) > 0;
        rows[i] = write ? reinterpret_cast<Real*>(&constraints[constraint[i]].frame) : sink;
        any = any || write;
    }
    if (!any) return;
    const FloatW columns[16] = {rA.x, rA.y, rA.z, rB.x, rB.y, rB.z, d.x, d.y, d.z, qA.w, qA.x, qA.y, qA.z, qB.w, qB.x, qB.y};
    for (int j = 0; j < 16; j += 4) {
        const typename Policy::Reg regs[4] = {columns[j].reg(), columns[j + 1].reg(), columns[j + 2].reg(), columns[j + 3].reg()};
        Real* shifted[kLanes];
        for (int i = 0; i < kLanes; ++i) shifted[i] = rows[i] + j;
        Policy::storeTransposed4(shifted, regs);
    }
    for (std::uint32_t lane = 0; lane < laneCount; ++lane) {
        const int l = static_cast<int>(lane);
        if (!(getLane(direct, l) > 0)) continue;
        JointConstraint& j = constraints[constraint[lane]];
        j.frame.qB.z = getLane(qB.z, l);
        j.frameAt = generation;
    }
}

// The constants of a pass (JointContext's): limits' softness and 1 / h.
struct PassW {
    FloatW invH;
    FloatW soft[3];       // ctx.soft: biasRate, massScale, impulseScale
    FloatW limitSoft[3];  // ctx.limitSoft
    bool useBias = true;
    explicit PassW(const JointContext& ctx)
        : invH(ctx.invH),
          soft{ctx.soft.biasRate, ctx.soft.massScale, ctx.soft.impulseScale},
          limitSoft{ctx.limitSoft.biasRate, ctx.limitSoft.massScale, ctx.limitSoft.impulseScale},
          useBias(ctx.useBias) {}
};

// nextLimitImpulse: speculative (bias C / h, rigid) where C > 0, soft in the
// biased pass elsewhere, rigid and bias-free in the relax pass; the sum
// clamped to >= 0 (`lambda + d > 0 ? lambda + d : 0`).
FULCRUM_JOINT_WIDE_INLINE FloatW nextLimitImpulse(const FloatW& velocity, const FloatW& C, const FloatW& k,
                                                  const FloatW& lambda, const PassW& pass) {
    const FloatW zero = 0.0f, one = 1.0f;
    const MaskW open = C > zero;
    const FloatW bias = select(open, C * pass.invH, pass.useBias ? pass.limitSoft[0] * C : zero);
    const FloatW massScale = select(open, one, pass.useBias ? pass.limitSoft[1] : one);
    const FloatW impulseScale = select(open, zero, pass.useBias ? pass.limitSoft[2] : zero);
    const FloatW d = -massScale * (velocity + bias) / k - impulseScale * lambda;
    const FloatW next = lambda + d;
    return select(next > zero, next, zero);
}

// solveLimitRow where `on` (and k > 0).
FULCRUM_JOINT_WIDE_INLINE void solveLimitRow(const RowW& r, Ends& e, const FloatW& C, FloatW& lambda, const MaskW& on,
                                             const PassW& pass) {
    const FloatW k = rowInverseMass(r, e);
    const MaskW run = on & !(k <= FloatW(0.0f));
    const FloatW next = nextLimitImpulse(rowVelocity(r, e), C, k, lambda, pass);
    applyRow(r, e, next - lambda, run);
    lambda = select(run, next, lambda);
}

// solvePointBlock where `on`, with the sub-step's K^-1.
FULCRUM_JOINT_WIDE_INLINE void solvePointBlock(Ends& e, const Vec3W& rA, const Vec3W& rB, const Vec3W& C, Vec3W& lambda,
                                               const Mat3W& invK, const MaskW& on, const PassW& pass) {
    const Vec3W cdot = e.vB + cross(e.wB, rB) - e.vA - cross(e.wA, rA);
    const Vec3W bias = pass.useBias ? C * pass.soft[0] : Vec3W{};
    const FloatW massScale = pass.useBias ? pass.soft[1] : FloatW(1.0f);
    const FloatW impulseScale = pass.useBias ? pass.soft[2] : FloatW(0.0f);
    const Vec3W d = -(invK * (cdot + bias)) * massScale - lambda * impulseScale;
    lambda = select(on, lambda + d, lambda);
    applyPoint(e, rA, rB, d, on);
}

FULCRUM_JOINT_WIDE_INLINE void scatterEnds(SolverBody* bodies, const std::uint32_t* writeA, const std::uint32_t* writeB,
                                           const Ends& e) {
    scatterVelocity(bodies, writeA, e.a, e.vA, e.wA);
    scatterVelocity(bodies, writeB, e.b, e.vB, e.wB);
}

// The lanes every block kind fills alike (the block builds below and in
// cone_twist_wide.hpp, hinge_wide.hpp): the two solver bodies,
// which of them are written back (static and kinematic ends never are), the
// constraint record, and the step's anchors and centre delta.
template <class Block>
void setBodyLane(Block& k, int l, const JointConstraint& j, std::uint32_t index, const SolverBody* bodies) {
    k.bodyA[l] = j.bodyA;
    k.bodyB[l] = j.bodyB;
    k.writeA[l] = bodies[j.bodyA].invMass > 0 ? j.bodyA : kEmptyLane;
    k.writeB[l] = bodies[j.bodyB].invMass > 0 ? j.bodyB : kEmptyLane;
    k.constraint[l] = index;
    setLane(k.rA0, l, j.rA0);
    setLane(k.rB0, l, j.rB0);
    setLane(k.centreDelta, l, j.centreDelta);
}
// An unused lane: body 0 (the static body) on both ends, never written back.
template <class Block>
void setEmptyBodyLane(Block& k, int l) {
    k.bodyA[l] = k.bodyB[l] = 0;
    k.writeA[l] = k.writeB[l] = kEmptyLane;
    k.constraint[l] = 0;
}

// What hinge and cone-twist blocks both hold per lane: the two ends (gather:
// solver body, 0 for static; scatter: the body if dynamic, else kEmptyLane),
// where store() puts the lane's impulses, the refresh the frame was computed
// at, and the step's start (anchors, centre delta, rest pose, local axes,
// and the ends' world inverse inertias).
//
// The inertias: SolverBody::invI is the step's start's, written when the
// step fills the solver bodies (BodyStore) and by nothing after it until the
// next step, whose prepare builds the blocks again; so a copy taken at the
// block's build has the bits every pass would gather, and the passes gather
// 8 floats of a body's row (12 with the frame's deltas) instead of 20 (24)
// (branch rain9, docs/benchmarks.md: rain(4x2)'s step 1,346 M -> 1,318 M).
struct FramedLanes {
    std::uint32_t bodyA[kLanes], bodyB[kLanes];
    std::uint32_t writeA[kLanes], writeB[kLanes];
    std::uint32_t constraint[kLanes];
    std::uint32_t laneCount = 0;
    std::uint64_t frameAt = 0;
    Vec3W rA0, rB0, centreDelta;
    QuatW qA0, qB0, relative0Conjugate;
    Vec3W localAxisA, localAxisB;
    Mat3W invIA, invIB;
    // Each lane's two solver-body rows in the array the block was built on
    // (rowsOf): the gathers' addresses, computed once a step.
    const Real* rowA[kLanes];
    const Real* rowB[kLanes];
    const SolverBody* rowsOf = nullptr;
};

// Lane l's inverse inertias and rows from its solver bodies (after
// setBodyLane or setEmptyBodyLane: an empty lane reads body 0, as its
// gathers did).
template <class Block>
void setInertiaLane(Block& k, int l, const SolverBody* bodies) {
    k.rowsOf = bodies;
    k.rowA[l] = reinterpret_cast<const Real*>(bodies + k.bodyA[l]);
    k.rowB[l] = reinterpret_cast<const Real*>(bodies + k.bodyB[l]);
    const Mat3& a = bodies[k.bodyA[l]].invI;
    const Mat3& b = bodies[k.bodyB[l]].invI;
    setLane(k.invIA.c0, l, a.c0);
    setLane(k.invIA.c1, l, a.c1);
    setLane(k.invIA.c2, l, a.c2);
    setLane(k.invIB.c0, l, b.c0);
    setLane(k.invIB.c1, l, b.c1);
    setLane(k.invIB.c2, l, b.c2);
}

// The rest pose and the axes hinge and cone-twist blocks both carry (their
// frames: cone_twist_wide.hpp, hinge_wide.hpp). The rest
// rotation is stored conjugated, spelled out here rather than through the
// math headers' inline conjugate (no shared inline copy in the AVX2 file).
FULCRUM_JOINT_WIDE_INLINE void setQuatLane(QuatW& q, int l, const Quat& v) {
    setLane(q.w, l, v.w);
    setLane(q.x, l, v.x);
    setLane(q.y, l, v.y);
    setLane(q.z, l, v.z);
}
template <class Block>
void setRestPoseLane(Block& k, int l, const JointConstraint& j) {
    setQuatLane(k.qA0, l, j.qA0);
    setQuatLane(k.qB0, l, j.qB0);
    const Quat& rest = j.relative0;
    setQuatLane(k.relative0Conjugate, l, Quat{rest.w, -rest.x, -rest.y, -rest.z});
    setLane(k.localAxisA, l, j.localAxisA);
    setLane(k.localAxisB, l, j.localAxisB);
}
// An unused lane's rest pose: identities and a unit axis (finite values).
template <class Block>
void setEmptyRestPoseLane(Block& k, int l) {
    setQuatLane(k.qA0, l, Quat{});
    setQuatLane(k.qB0, l, Quat{});
    setQuatLane(k.relative0Conjugate, l, Quat{});
    setLane(k.localAxisA, l, Vec3{0, 0, 1});
    setLane(k.localAxisB, l, Vec3{0, 0, 1});
}

}  // namespace
}  // namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS

#include "solver/joints/ball_wide.hpp"
#include "solver/joints/cone_twist_wide.hpp"
#include "solver/joints/hinge_wide.hpp"

namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS {
namespace {

// The blocks of every kind, and the order they run in: entry b of order_ is
// block b (its kind and its place in its kind's array).
class Blocks final : public WideJoints {
public:
    explicit Blocks(SimdPath path) : path_(path) {}
    SimdPath path() const override { return path_; }
    int lanes() const override { return kLanes; }
    std::size_t size() const override { return order_.size(); }
    // The cone-twist and hinge arrays are not reserved for every joint (a
    // few kB per block, for kinds a scene may not have): they grow to the
    // largest step's size and keep it (clear() keeps capacity), so steady
    // state allocates nothing (tests/allocation).
    void reserve(std::size_t blocks) override {
        if (order_.capacity() < blocks) order_.reserve(2 * blocks);
        if (ball_.capacity() < blocks) ball_.reserve(2 * blocks);
    }
    void clear() override {
        order_.clear();
        ball_.clear();
        coneTwist_.clear();
        hinge_.clear();
        FULCRUM_JOINT_WIDE_LEAVE();
    }
    void build(const JointConstraint* constraints, const std::uint32_t* indices, int laneCount,
               const SolverBody* bodies) override {
        switch (wideKind(constraints[indices[0]])) {
            case WideKind::Ball:
                order_.push_back({WideKind::Ball, static_cast<std::uint32_t>(ball_.size())});
                buildBlock(ball_.emplace_back(), constraints, indices, laneCount, bodies);
                break;
            case WideKind::ConeTwist:
                order_.push_back({WideKind::ConeTwist, static_cast<std::uint32_t>(coneTwist_.size())});
                buildConeTwistBlock(coneTwist_.emplace_back(), constraints, indices, laneCount, bodies);
                break;
            case WideKind::Hinge:
                order_.push_back({WideKind::Hinge, static_cast<std::uint32_t>(hinge_.size())});
                buildHingeBlock(hinge_.emplace_back(), constraints, indices, laneCount, bodies);
                break;
            case WideKind::NotWide: break;
        }
        FULCRUM_JOINT_WIDE_LEAVE();
    }
    void warmStart(std::size_t first, std::size_t count, SolverBody* bodies, JointConstraint* constraints,
                   const JointContext& ctx) override {
        forRuns(first, count, [&](WideKind kind, std::uint32_t begin, std::uint32_t n) {
            switch (kind) {
                case WideKind::Ball: warmStartBlocks(ball_.data() + begin, n, bodies, ctx.rotations, ctx.generation); break;
                case WideKind::ConeTwist:
                    warmStartConeTwistBlocks(coneTwist_.data() + begin, n, bodies, constraints, ctx);
                    break;
                case WideKind::Hinge: warmStartHingeBlocks(hinge_.data() + begin, n, bodies, constraints, ctx); break;
                case WideKind::NotWide: break;
            }
        });
        FULCRUM_JOINT_WIDE_LEAVE();
    }
    void solve(std::size_t first, std::size_t count, SolverBody* bodies, JointConstraint* constraints,
               const JointContext& ctx) override {
        forRuns(first, count, [&](WideKind kind, std::uint32_t begin, std::uint32_t n) {
            switch (kind) {
                case WideKind::Ball:
                    if (ctx.useBias) {
                        solveBlocks<true>(ball_.data() + begin, n, bodies, ctx.rotations, ctx.generation, ctx.soft);
                    } else {
                        solveBlocks<false>(ball_.data() + begin, n, bodies, ctx.rotations, ctx.generation, ctx.soft);
                    }
                    break;
                case WideKind::ConeTwist: solveConeTwistBlocks(coneTwist_.data() + begin, n, bodies, constraints, ctx); break;
                case WideKind::Hinge: solveHingeBlocks(hinge_.data() + begin, n, bodies, constraints, ctx); break;
                case WideKind::NotWide: break;
            }
        });
        FULCRUM_JOINT_WIDE_LEAVE();
    }
    void store(JointConstraint* constraints) const override {
        for (const BallBlock& k : ball_) {
            for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
                const int l = static_cast<int>(lane);
                Vec3& impulse = constraints[k.constraint[lane]].impulse.linear;
                impulse.x = getLane(k.impulse.x, l);
                impulse.y = getLane(k.impulse.y, l);
                impulse.z = getLane(k.impulse.z, l);
            }
        }
        for (const ConeTwistBlock& k : coneTwist_) storeConeTwistBlock(k, constraints);
        for (const HingeBlock& k : hinge_) storeHingeBlock(k, constraints);
        FULCRUM_JOINT_WIDE_LEAVE();
    }

private:
    struct Entry {
        WideKind kind;
        std::uint32_t index;  // in its kind's array
    };
    // f(kind, first index, count) over the runs of one kind (consecutive
    // in their array) among blocks [first, first + count).
    template <class F>
    void forRuns(std::size_t first, std::size_t count, F&& f) const {
        std::size_t b = first;
        const std::size_t end = first + count;
        while (b < end) {
            const Entry start = order_[b];
            std::uint32_t n = 1;
            while (b + n < end && order_[b + n].kind == start.kind && order_[b + n].index == start.index + n) ++n;
            f(start.kind, start.index, n);
            b += n;
        }
    }
    SimdPath path_;
    std::vector<Entry> order_;
    std::vector<BallBlock> ball_;
    std::vector<ConeTwistBlock> coneTwist_;
    std::vector<HingeBlock> hinge_;
};

}  // namespace
}  // namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS
