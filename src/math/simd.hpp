#pragma once
// Wide (SIMD) float types for the solver and other batch kernels: FloatW, a
// pack of kSimdLanes floats; MaskW, a per-lane boolean; Vec3W, three FloatW in
// structure-of-arrays form (x of every lane, then y, then z).
//
// ---- One template, one small policy per instruction set ------------------------
// Everything is written once, in FloatWide<Policy>, MaskWide<Policy> and
// Vec3Wide<Policy>. A policy supplies only the register types and about twenty
// one-line primitives (load, add, compare, blend...). Three policies:
//   PortablePolicy<N>  plain C++ arrays of N floats (any CPU; the reference)
//   Sse2Policy         4 lanes, __m128 (always available on x86-64)
//   Avx2Policy         8 lanes, __m256 (only when compiled with -mavx2)
// The default (FloatW, MaskW, Vec3W) is the widest one the build allows: AVX2
// with -mavx2, else SSE2 on x86, else PortablePolicy<4>. Defining
// FULCRUM_SIMD_PORTABLE forces the portable one (to debug, or to compare).
// The default differs between files compiled with and without -mavx2 (the
// contact solver compiles its kernels both ways: contact_wide.hpp), so code
// shared between such files names a policy instead of using the defaults, and
// kSimdLanes has internal linkage.
//
// ---- Results are the scalar results, lane by lane -------------------------------
// Every lane computes exactly what the scalar code `a op b` computes: add, sub,
// mul, div, sqrt are IEEE correctly rounded in both, and min/max/compare follow
// the scalar expressions `a < b ? a : b` / `a > b ? a : b` / `a < b` including
// NaN and signed-zero cases (SSE's minps returns its second operand when the
// comparison is false, which is exactly that expression). So a SIMD kernel that
// does the same operations in the same order as its scalar twin is
// bit-identical to it (tests/simd checks this; bench/simd.cpp checks it for a
// whole contact-row solve). The exceptions, stated where they are declared:
//   - fusedMulAdd rounds once (like std::fma): it differs from mulAdd (a*b+c,
//     two roundings), so use it in both twins or in neither.
//   - reciprocalApprox uses the rcpps estimate plus one Newton step: relative
//     error below 2^-21, but the estimate differs between Intel and AMD, so it
//     is not for results that must match across machines. reciprocal (a true
//     division) is.
// Scalar C++ must not be contracted into FMAs behind our back for this to
// hold. The default x86-64 build has no FMA instructions, so nothing is
// contracted; but GCC's C++ default is -ffp-contract=fast, so a build with
// -mfma or -march=native fuses `a * b + c` in scalar code (and in the wide
// code, differently) unless it also passes -ffp-contract=off. Found the hard
// way: the -mavx2 -mfma build of tests/simd failed the bit-identity tests
// until -ffp-contract=off was added (tests/simd/fp_contract.hpp now detects
// such builds and skips those checks, saying why).
//
// ---- Gather and scatter ----------------------------------------------------------
// Bodies stay array-of-structs (the solver reaches them by index, see
// docs/solver.md, "The wide (SIMD) solve"), constraints are bundled kSimdLanes at a time. A kernel
// gathers the lanes' bodies with Vec3W::gather(bodies, indices, &Body::field),
// works on whole bundles, and scatters the results back. An index of
// kEmptyLane gathers zeros and is skipped by scatter, for bundles that are not
// full. Lanes of one bundle must not share a body (graph colouring guarantees
// it), or scatter would keep only the last lane's write.
// Two ways to gather: by field (Vec3W::gather, FloatW::gather: one scalar
// load per lane and component) and by whole struct (gatherTransposed: one
// 16-byte load per lane and 4 floats, then an in-register transpose, the
// layout trick of Box2D v3 and bepu). The second is 2-2.7x faster in
// bench/simd.cpp and is what makes SIMD pay at all there: with field gathers
// the 4- and 8-wide kernels are no faster than scalar code.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "fulcrum/math/vec3.hpp"

// The SSE2 and AVX2 policies hold float lanes; the double build
// (FULCRUM_DOUBLE, docs/double-precision.md) runs every wide kernel on
// PortablePolicy<4> over double, so the wide paths keep the scalar bits there too.
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
#include <immintrin.h>
#define FULCRUM_SIMD_HAS_SSE2 1
#endif
#if defined(__AVX2__) && !FULCRUM_DOUBLE
#define FULCRUM_SIMD_HAS_AVX2 1
#endif

// The transposed gathers and scatters are a handful of shuffles each; as calls
// they cost more than they do. When the joint kernels grew (hinges and
// cone-twists, ninth session) GCC stopped inlining the AVX2 loadTransposed4
// into the ball joints' gathers: the grid took 11.6 % more instructions
// (callgrind, 10 steps: 4,097 M before, 4,573 M, 350 M of them the call).
#if defined(__GNUC__)
#define FULCRUM_SIMD_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define FULCRUM_SIMD_ALWAYS_INLINE inline
#endif

namespace fulcrum::simd {


// ---- Policies -------------------------------------------------------------------

// Plain arrays: the portable fallback and the reference the others are tested
// against. Masks are 0 / ~0u per lane, like the hardware compares.
template <int N>
struct PortablePolicy {
    static constexpr int kLanes = N;
    struct Reg {
        Real lane[N];
    };
    struct MaskReg {
        std::uint32_t lane[N];
    };

    template <class F>
    static Reg map(F f) {
        Reg r;
        for (int i = 0; i < N; ++i) r.lane[i] = f(i);
        return r;
    }
    template <class F>
    static MaskReg mapMask(F f) {
        MaskReg r;
        for (int i = 0; i < N; ++i) r.lane[i] = f(i) ? ~0u : 0u;
        return r;
    }

    static Reg splat(Real s) { return map([&](int) { return s; }); }
    static Reg load(const Real* p) { return map([&](int i) { return p[i]; }); }
    static void store(Real* p, Reg a) { std::memcpy(p, a.lane, sizeof(a.lane)); }
    static Reg add(Reg a, Reg b) { return map([&](int i) { return a.lane[i] + b.lane[i]; }); }
    static Reg sub(Reg a, Reg b) { return map([&](int i) { return a.lane[i] - b.lane[i]; }); }
    static Reg mul(Reg a, Reg b) { return map([&](int i) { return a.lane[i] * b.lane[i]; }); }
    static Reg div(Reg a, Reg b) { return map([&](int i) { return a.lane[i] / b.lane[i]; }); }
    static Reg fma(Reg a, Reg b, Reg c) { return map([&](int i) { return std::fma(a.lane[i], b.lane[i], c.lane[i]); }); }
    static Reg min(Reg a, Reg b) { return map([&](int i) { return a.lane[i] < b.lane[i] ? a.lane[i] : b.lane[i]; }); }
    static Reg max(Reg a, Reg b) { return map([&](int i) { return a.lane[i] > b.lane[i] ? a.lane[i] : b.lane[i]; }); }
    static Reg abs(Reg a) { return map([&](int i) { return std::fabs(a.lane[i]); }); }
    static Reg neg(Reg a) { return map([&](int i) { return -a.lane[i]; }); }
    static Reg sqrt(Reg a) { return map([&](int i) { return std::sqrt(a.lane[i]); }); }
    static Reg rcpApprox(Reg a) { return map([&](int i) { return Real(1) / a.lane[i]; }); }
    static MaskReg lt(Reg a, Reg b) { return mapMask([&](int i) { return a.lane[i] < b.lane[i]; }); }
    static MaskReg le(Reg a, Reg b) { return mapMask([&](int i) { return a.lane[i] <= b.lane[i]; }); }
    static MaskReg eq(Reg a, Reg b) { return mapMask([&](int i) { return a.lane[i] == b.lane[i]; }); }
    static MaskReg neq(Reg a, Reg b) { return mapMask([&](int i) { return a.lane[i] != b.lane[i]; }); }
    static MaskReg maskAnd(MaskReg a, MaskReg b) { return mapMask([&](int i) { return (a.lane[i] & b.lane[i]) != 0; }); }
    static MaskReg maskOr(MaskReg a, MaskReg b) { return mapMask([&](int i) { return (a.lane[i] | b.lane[i]) != 0; }); }
    static MaskReg maskNot(MaskReg a) { return mapMask([&](int i) { return a.lane[i] == 0; }); }
    static Reg select(MaskReg m, Reg a, Reg b) { return map([&](int i) { return m.lane[i] ? a.lane[i] : b.lane[i]; }); }
    static std::uint32_t bits(MaskReg m) {
        std::uint32_t r = 0;
        for (int i = 0; i < N; ++i) r |= (m.lane[i] & 1u) << i;
        return r;
    }
    // out[j] lane i = rows[i][j] for j < 4 (a 4 x N transpose), and back.
    FULCRUM_SIMD_ALWAYS_INLINE static void loadTransposed4(const Real* const* rows, Reg* out) {
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < N; ++i) std::memcpy(&out[j].lane[i], rows[i] + j, sizeof(Real));
    }
    FULCRUM_SIMD_ALWAYS_INLINE static void storeTransposed4(Real* const* rows, const Reg* in) {
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < N; ++i) std::memcpy(rows[i] + j, &in[j].lane[i], sizeof(Real));
    }
};

#if FULCRUM_SIMD_HAS_SSE2
struct Sse2Policy {
    static constexpr int kLanes = 4;
    using Reg = __m128;
    using MaskReg = __m128;

    static Reg signBit() { return _mm_set1_ps(-0.0f); }
    static Reg splat(float s) { return _mm_set1_ps(s); }
    static Reg load(const float* p) { return _mm_loadu_ps(p); }
    static void store(float* p, Reg a) { _mm_storeu_ps(p, a); }
    static Reg add(Reg a, Reg b) { return _mm_add_ps(a, b); }
    static Reg sub(Reg a, Reg b) { return _mm_sub_ps(a, b); }
    static Reg mul(Reg a, Reg b) { return _mm_mul_ps(a, b); }
    static Reg div(Reg a, Reg b) { return _mm_div_ps(a, b); }
    static Reg fma(Reg a, Reg b, Reg c) {
#if defined(__FMA__)
        return _mm_fmadd_ps(a, b, c);
#else  // exact but slow: compile with -mfma where fusedMulAdd is hot
        alignas(16) float x[4], y[4], z[4];
        _mm_store_ps(x, a), _mm_store_ps(y, b), _mm_store_ps(z, c);
        for (int i = 0; i < 4; ++i) x[i] = std::fma(x[i], y[i], z[i]);
        return _mm_load_ps(x);
#endif
    }
    static Reg min(Reg a, Reg b) { return _mm_min_ps(a, b); }  // a < b ? a : b
    static Reg max(Reg a, Reg b) { return _mm_max_ps(a, b); }  // a > b ? a : b
    static Reg abs(Reg a) { return _mm_andnot_ps(signBit(), a); }
    static Reg neg(Reg a) { return _mm_xor_ps(signBit(), a); }
    static Reg sqrt(Reg a) { return _mm_sqrt_ps(a); }
    static Reg rcpApprox(Reg a) {
        const Reg r = _mm_rcp_ps(a);  // ~12 bits; one Newton step r(2 - ar) gives ~23
        return _mm_mul_ps(r, _mm_sub_ps(_mm_set1_ps(2.0f), _mm_mul_ps(a, r)));
    }
    static MaskReg lt(Reg a, Reg b) { return _mm_cmplt_ps(a, b); }
    static MaskReg le(Reg a, Reg b) { return _mm_cmple_ps(a, b); }
    static MaskReg eq(Reg a, Reg b) { return _mm_cmpeq_ps(a, b); }
    static MaskReg neq(Reg a, Reg b) { return _mm_cmpneq_ps(a, b); }  // true if unordered, as scalar !=
    static MaskReg maskAnd(MaskReg a, MaskReg b) { return _mm_and_ps(a, b); }
    static MaskReg maskOr(MaskReg a, MaskReg b) { return _mm_or_ps(a, b); }
    static MaskReg maskNot(MaskReg a) { return _mm_xor_ps(a, _mm_castsi128_ps(_mm_set1_epi32(-1))); }
    static Reg select(MaskReg m, Reg a, Reg b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); }
    static std::uint32_t bits(MaskReg m) { return static_cast<std::uint32_t>(_mm_movemask_ps(m)); }
    FULCRUM_SIMD_ALWAYS_INLINE static void loadTransposed4(const float* const* rows, Reg* out) {
        Reg r0 = _mm_loadu_ps(rows[0]), r1 = _mm_loadu_ps(rows[1]), r2 = _mm_loadu_ps(rows[2]), r3 = _mm_loadu_ps(rows[3]);
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        out[0] = r0, out[1] = r1, out[2] = r2, out[3] = r3;
    }
    FULCRUM_SIMD_ALWAYS_INLINE static void storeTransposed4(float* const* rows, const Reg* in) {
        Reg r0 = in[0], r1 = in[1], r2 = in[2], r3 = in[3];
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        _mm_storeu_ps(rows[0], r0), _mm_storeu_ps(rows[1], r1), _mm_storeu_ps(rows[2], r2), _mm_storeu_ps(rows[3], r3);
    }
};
#endif

#if FULCRUM_SIMD_HAS_AVX2
struct Avx2Policy {
    static constexpr int kLanes = 8;
    using Reg = __m256;
    using MaskReg = __m256;

    static Reg signBit() { return _mm256_set1_ps(-0.0f); }
    static Reg splat(float s) { return _mm256_set1_ps(s); }
    static Reg load(const float* p) { return _mm256_loadu_ps(p); }
    static void store(float* p, Reg a) { _mm256_storeu_ps(p, a); }
    static Reg add(Reg a, Reg b) { return _mm256_add_ps(a, b); }
    static Reg sub(Reg a, Reg b) { return _mm256_sub_ps(a, b); }
    static Reg mul(Reg a, Reg b) { return _mm256_mul_ps(a, b); }
    static Reg div(Reg a, Reg b) { return _mm256_div_ps(a, b); }
    static Reg fma(Reg a, Reg b, Reg c) {
#if defined(__FMA__)
        return _mm256_fmadd_ps(a, b, c);
#else
        alignas(32) float x[8], y[8], z[8];
        _mm256_store_ps(x, a), _mm256_store_ps(y, b), _mm256_store_ps(z, c);
        for (int i = 0; i < 8; ++i) x[i] = std::fma(x[i], y[i], z[i]);
        return _mm256_load_ps(x);
#endif
    }
    static Reg min(Reg a, Reg b) { return _mm256_min_ps(a, b); }
    static Reg max(Reg a, Reg b) { return _mm256_max_ps(a, b); }
    static Reg abs(Reg a) { return _mm256_andnot_ps(signBit(), a); }
    static Reg neg(Reg a) { return _mm256_xor_ps(signBit(), a); }
    static Reg sqrt(Reg a) { return _mm256_sqrt_ps(a); }
    static Reg rcpApprox(Reg a) {
        const Reg r = _mm256_rcp_ps(a);
        return _mm256_mul_ps(r, _mm256_sub_ps(_mm256_set1_ps(2.0f), _mm256_mul_ps(a, r)));
    }
    static MaskReg lt(Reg a, Reg b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
    static MaskReg le(Reg a, Reg b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
    static MaskReg eq(Reg a, Reg b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
    static MaskReg neq(Reg a, Reg b) { return _mm256_cmp_ps(a, b, _CMP_NEQ_UQ); }
    static MaskReg maskAnd(MaskReg a, MaskReg b) { return _mm256_and_ps(a, b); }
    static MaskReg maskOr(MaskReg a, MaskReg b) { return _mm256_or_ps(a, b); }
    static MaskReg maskNot(MaskReg a) { return _mm256_xor_ps(a, _mm256_castsi256_ps(_mm256_set1_epi32(-1))); }
    static Reg select(MaskReg m, Reg a, Reg b) { return _mm256_blendv_ps(b, a, m); }
    static std::uint32_t bits(MaskReg m) { return static_cast<std::uint32_t>(_mm256_movemask_ps(m)); }
    // A 4 x 4 transpose inside each 128-bit half (rows 0-3 low, rows 4-7 high);
    // it is its own inverse, so loads and stores share it.
    FULCRUM_SIMD_ALWAYS_INLINE static void transposeHalves(Reg& r0, Reg& r1, Reg& r2, Reg& r3) {
        const Reg t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpacklo_ps(r2, r3);
        const Reg t2 = _mm256_unpackhi_ps(r0, r1), t3 = _mm256_unpackhi_ps(r2, r3);
        r0 = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(1, 0, 1, 0));
        r1 = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 2, 3, 2));
        r2 = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(1, 0, 1, 0));
        r3 = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(3, 2, 3, 2));
    }
    FULCRUM_SIMD_ALWAYS_INLINE static void loadTransposed4(const float* const* rows, Reg* out) {
        Reg r[4];
        for (int i = 0; i < 4; ++i) r[i] = _mm256_set_m128(_mm_loadu_ps(rows[i + 4]), _mm_loadu_ps(rows[i]));
        transposeHalves(r[0], r[1], r[2], r[3]);
        for (int j = 0; j < 4; ++j) out[j] = r[j];
    }
    FULCRUM_SIMD_ALWAYS_INLINE static void storeTransposed4(float* const* rows, const Reg* in) {
        Reg r[4] = {in[0], in[1], in[2], in[3]};
        transposeHalves(r[0], r[1], r[2], r[3]);
        for (int i = 0; i < 4; ++i) {
            _mm_storeu_ps(rows[i], _mm256_castps256_ps128(r[i]));
            _mm_storeu_ps(rows[i + 4], _mm256_extractf128_ps(r[i], 1));
        }
    }
};
#endif

// ---- MaskWide: one boolean per lane -----------------------------------------------

template <class P>
class MaskWide {
public:
    using Reg = typename P::MaskReg;
    static constexpr int kLanes = P::kLanes;

    MaskWide() = default;
    explicit MaskWide(Reg r) : r_(r) {}
    Reg reg() const { return r_; }

    std::uint32_t bits() const { return P::bits(r_); }  // bit i = lane i
    bool lane(int i) const { return (bits() >> i) & 1u; }
    bool any() const { return bits() != 0; }
    bool all() const { return bits() == (1u << kLanes) - 1u; }
    bool none() const { return bits() == 0; }

    friend MaskWide operator&(MaskWide a, MaskWide b) { return MaskWide(P::maskAnd(a.r_, b.r_)); }
    friend MaskWide operator|(MaskWide a, MaskWide b) { return MaskWide(P::maskOr(a.r_, b.r_)); }
    friend MaskWide operator!(MaskWide a) { return MaskWide(P::maskNot(a.r_)); }

private:
    Reg r_{};
};

// ---- FloatWide: kLanes floats ------------------------------------------------------

inline constexpr std::uint32_t kEmptyLane = 0xffffffffu;

template <class P>
class FloatWide {
public:
    using Policy = P;
    using Reg = typename P::Reg;
    using Mask = MaskWide<P>;
    static constexpr int kLanes = P::kLanes;

    FloatWide() = default;  // zero
    FloatWide(Real s) : r_(P::splat(s)) {}  // NOLINT(google-explicit-constructor): `2 * x` reads best
    explicit FloatWide(Reg r) : r_(r) {}
    Reg reg() const { return r_; }

    static FloatWide load(const Real* p) { return FloatWide(P::load(p)); }  // unaligned
    void store(Real* p) const { P::store(p, r_); }
    Real lane(int i) const {
        Real out[kLanes];
        P::store(out, r_);
        return out[i];
    }
    // Lane i = f(i), for gathers from anything that is not a struct field.
    template <class F>
    static FloatWide fromLanes(F&& f) {
        Real in[kLanes];
        for (int i = 0; i < kLanes; ++i) in[i] = f(i);
        return load(in);
    }

    // Lane i = items[indices[i]].*field (0 for kEmptyLane).
    template <class S>
    static FloatWide gather(const S* items, const std::uint32_t* indices, Real S::*field) {
        return fromLanes([&](int i) { return indices[i] == kEmptyLane ? Real(0) : items[indices[i]].*field; });
    }
    // items[indices[i]].*field = lane i, except for kEmptyLane.
    template <class S>
    void scatter(S* items, const std::uint32_t* indices, Real S::*field) const {
        Real out[kLanes];
        store(out);
        for (int i = 0; i < kLanes; ++i)
            if (indices[i] != kEmptyLane) items[indices[i]].*field = out[i];
    }

    // Whole structs at once: column j of the result holds float j of every
    // lane's struct (items[indices[i]], read as K floats; kEmptyLane reads
    // zeros). K/4 loads per lane and a transpose instead of one load per lane
    // and float: measured 1.9-2.1x (SSE2) and 2.1-2.7x (AVX2) faster than
    // field-by-field gathers in bench/simd.cpp's contact kernel. S must be trivially
    // copyable, at least K floats long, and its first K * 4 bytes hold
    // floats (or bit patterns copied through unchanged, like flags).
    template <int K, class S>
    static std::array<FloatWide, K> gatherTransposed(const S* items, const std::uint32_t* indices) {
        static_assert(K % 4 == 0 && sizeof(S) >= K * sizeof(Real) && std::is_trivially_copyable_v<S>);
        alignas(64) static constexpr Real kZeros[K] = {};
        const Real* rows[kLanes];
        for (int i = 0; i < kLanes; ++i)
            rows[i] = indices[i] == kEmptyLane ? kZeros : reinterpret_cast<const Real*>(items + indices[i]);
        std::array<FloatWide, K> columns;
        for (int j = 0; j < K; j += 4) {
            Reg regs[4];
            const Real* shifted[kLanes];
            for (int i = 0; i < kLanes; ++i) shifted[i] = rows[i] + j;
            P::loadTransposed4(shifted, regs);
            for (int c = 0; c < 4; ++c) columns[j + c] = FloatWide(regs[c]);
        }
        return columns;
    }
    // The inverse: writes all K floats of every lane's struct (skipping kEmptyLane).
    template <int K, class S>
    static void scatterTransposed(S* items, const std::uint32_t* indices, const std::array<FloatWide, K>& columns) {
        static_assert(K % 4 == 0 && sizeof(S) >= K * sizeof(Real) && std::is_trivially_copyable_v<S>);
        Real sink[K];  // empty lanes write here
        Real* rows[kLanes];
        for (int i = 0; i < kLanes; ++i)
            rows[i] = indices[i] == kEmptyLane ? sink : reinterpret_cast<Real*>(items + indices[i]);
        for (int j = 0; j < K; j += 4) {
            const Reg regs[4] = {columns[j].r_, columns[j + 1].r_, columns[j + 2].r_, columns[j + 3].r_};
            Real* shifted[kLanes];
            for (int i = 0; i < kLanes; ++i) shifted[i] = rows[i] + j;
            P::storeTransposed4(shifted, regs);
        }
    }

    friend FloatWide operator+(FloatWide a, FloatWide b) { return FloatWide(P::add(a.r_, b.r_)); }
    friend FloatWide operator-(FloatWide a, FloatWide b) { return FloatWide(P::sub(a.r_, b.r_)); }
    friend FloatWide operator*(FloatWide a, FloatWide b) { return FloatWide(P::mul(a.r_, b.r_)); }
    friend FloatWide operator/(FloatWide a, FloatWide b) { return FloatWide(P::div(a.r_, b.r_)); }
    friend FloatWide operator-(FloatWide a) { return FloatWide(P::neg(a.r_)); }
    FloatWide& operator+=(FloatWide b) { return *this = *this + b; }
    FloatWide& operator-=(FloatWide b) { return *this = *this - b; }
    FloatWide& operator*=(FloatWide b) { return *this = *this * b; }

    friend Mask operator<(FloatWide a, FloatWide b) { return Mask(P::lt(a.r_, b.r_)); }
    friend Mask operator<=(FloatWide a, FloatWide b) { return Mask(P::le(a.r_, b.r_)); }
    friend Mask operator>(FloatWide a, FloatWide b) { return Mask(P::lt(b.r_, a.r_)); }
    friend Mask operator>=(FloatWide a, FloatWide b) { return Mask(P::le(b.r_, a.r_)); }
    friend Mask operator==(FloatWide a, FloatWide b) { return Mask(P::eq(a.r_, b.r_)); }
    friend Mask operator!=(FloatWide a, FloatWide b) { return Mask(P::neq(a.r_, b.r_)); }

    // Lane-wise a < b ? a : b and a > b ? a : b (NaN and ±0 as in those expressions).
    friend FloatWide min(FloatWide a, FloatWide b) { return FloatWide(P::min(a.r_, b.r_)); }
    friend FloatWide max(FloatWide a, FloatWide b) { return FloatWide(P::max(a.r_, b.r_)); }
    friend FloatWide clamp(FloatWide x, FloatWide lo, FloatWide hi) { return min(max(x, lo), hi); }
    friend FloatWide abs(FloatWide a) { return FloatWide(P::abs(a.r_)); }
    friend FloatWide sqrt(FloatWide a) { return FloatWide(P::sqrt(a.r_)); }
    // a * b + c with two roundings: bit-identical to the scalar expression.
    friend FloatWide mulAdd(FloatWide a, FloatWide b, FloatWide c) { return a * b + c; }
    // a * b + c with one rounding: bit-identical to std::fma (hardware FMA with -mfma).
    friend FloatWide fusedMulAdd(FloatWide a, FloatWide b, FloatWide c) { return FloatWide(P::fma(a.r_, b.r_, c.r_)); }
    friend FloatWide reciprocal(FloatWide a) { return FloatWide(Real(1)) / a; }
    // Relative error < 2^-21; differs between CPU vendors (see the header comment).
    friend FloatWide reciprocalApprox(FloatWide a) { return FloatWide(P::rcpApprox(a.r_)); }
    // Lane-wise mask ? a : b.
    friend FloatWide select(Mask m, FloatWide a, FloatWide b) { return FloatWide(P::select(m.reg(), a.r_, b.r_)); }

    // Sum of the lanes, in lane order (deterministic for a given width).
    Real sumLanes() const {
        Real out[kLanes];
        store(out);
        Real s = out[0];
        for (int i = 1; i < kLanes; ++i) s += out[i];
        return s;
    }

private:
    Reg r_{};
};

// ---- Vec3Wide: kLanes vectors in SoA form --------------------------------------------

template <class P>
struct Vec3Wide {
    using W = FloatWide<P>;
    using Mask = MaskWide<P>;
    static constexpr int kLanes = P::kLanes;

    W x, y, z;

    Vec3Wide() = default;
    Vec3Wide(W x_, W y_, W z_) : x(x_), y(y_), z(z_) {}
    explicit Vec3Wide(const Vec3& v) : x(v.x), y(v.y), z(v.z) {}  // the same vector in every lane

    Vec3 lane(int i) const { return {x.lane(i), y.lane(i), z.lane(i)}; }
    template <class F>
    static Vec3Wide fromLanes(F&& f) {  // lane i = f(i), a Vec3
        Vec3 in[kLanes];
        for (int i = 0; i < kLanes; ++i) in[i] = f(i);
        return {W::fromLanes([&](int i) { return in[i].x; }), W::fromLanes([&](int i) { return in[i].y; }),
                W::fromLanes([&](int i) { return in[i].z; })};
    }
    // Lane i = items[indices[i]].*field (zero for kEmptyLane).
    template <class S>
    static Vec3Wide gather(const S* items, const std::uint32_t* indices, Vec3 S::*field) {
        return fromLanes([&](int i) { return indices[i] == kEmptyLane ? Vec3{} : items[indices[i]].*field; });
    }
    // items[indices[i]].*field = lane i, except for kEmptyLane.
    template <class S>
    void scatter(S* items, const std::uint32_t* indices, Vec3 S::*field) const {
        Real xs[kLanes], ys[kLanes], zs[kLanes];
        x.store(xs), y.store(ys), z.store(zs);
        for (int i = 0; i < kLanes; ++i)
            if (indices[i] != kEmptyLane) items[indices[i]].*field = Vec3{xs[i], ys[i], zs[i]};
    }

    friend Vec3Wide operator+(const Vec3Wide& a, const Vec3Wide& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend Vec3Wide operator-(const Vec3Wide& a, const Vec3Wide& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend Vec3Wide operator-(const Vec3Wide& a) { return {-a.x, -a.y, -a.z}; }
    friend Vec3Wide operator*(const Vec3Wide& a, W s) { return {a.x * s, a.y * s, a.z * s}; }
    friend Vec3Wide operator*(W s, const Vec3Wide& a) { return {s * a.x, s * a.y, s * a.z}; }
    Vec3Wide& operator+=(const Vec3Wide& b) { return *this = *this + b; }
    Vec3Wide& operator-=(const Vec3Wide& b) { return *this = *this - b; }

    // Same operation order as fulcrum::dot and fulcrum::cross, so lanes match them bit for bit.
    friend W dot(const Vec3Wide& a, const Vec3Wide& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
    friend Vec3Wide cross(const Vec3Wide& a, const Vec3Wide& b) {
        return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    }
    friend W lengthSquared(const Vec3Wide& a) { return dot(a, a); }
    friend W length(const Vec3Wide& a) { return sqrt(dot(a, a)); }
    // a * s + b per component, two roundings (as the scalar expression).
    friend Vec3Wide mulAdd(const Vec3Wide& a, W s, const Vec3Wide& b) {
        return {mulAdd(a.x, s, b.x), mulAdd(a.y, s, b.y), mulAdd(a.z, s, b.z)};
    }
    friend Vec3Wide min(const Vec3Wide& a, const Vec3Wide& b) { return {min(a.x, b.x), min(a.y, b.y), min(a.z, b.z)}; }
    friend Vec3Wide max(const Vec3Wide& a, const Vec3Wide& b) { return {max(a.x, b.x), max(a.y, b.y), max(a.z, b.z)}; }
    friend Vec3Wide select(Mask m, const Vec3Wide& a, const Vec3Wide& b) {
        return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
    }
};

// ---- One lane in place ---------------------------------------------------------------
// A FloatWide is its kLanes floats in lane order, so a kernel building a block
// lane by lane writes (or reads) the float itself: a store/modify/load round
// trip per lane cost 8 % of pyramid20's instructions in packing alone.

template <class P>
void setLane(FloatWide<P>& w, int lane, Real value) {
    static_assert(sizeof(FloatWide<P>) == P::kLanes * sizeof(Real) && std::is_trivially_copyable_v<FloatWide<P>>);
    std::memcpy(reinterpret_cast<unsigned char*>(&w) + static_cast<std::size_t>(lane) * sizeof(Real), &value,
                sizeof(Real));
}
template <class P>
void setLane(Vec3Wide<P>& w, int lane, const Vec3& value) {
    setLane(w.x, lane, value.x);
    setLane(w.y, lane, value.y);
    setLane(w.z, lane, value.z);
}
template <class P>
Real getLane(const FloatWide<P>& w, int lane) {
    static_assert(sizeof(FloatWide<P>) == P::kLanes * sizeof(Real) && std::is_trivially_copyable_v<FloatWide<P>>);
    Real value;
    std::memcpy(&value, reinterpret_cast<const unsigned char*>(&w) + static_cast<std::size_t>(lane) * sizeof(Real),
                sizeof(Real));
    return value;
}

// ---- The build's default width ------------------------------------------------------

#if defined(FULCRUM_SIMD_PORTABLE) || !FULCRUM_SIMD_HAS_SSE2
using DefaultPolicy = PortablePolicy<4>;
#elif FULCRUM_SIMD_HAS_AVX2
using DefaultPolicy = Avx2Policy;
#else
using DefaultPolicy = Sse2Policy;
#endif

using FloatW = FloatWide<DefaultPolicy>;
using MaskW = MaskWide<DefaultPolicy>;
using Vec3W = Vec3Wide<DefaultPolicy>;
constexpr int kSimdLanes = DefaultPolicy::kLanes;  // not inline: it differs between -mavx2 files and others

}  // namespace fulcrum::simd
