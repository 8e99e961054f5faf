// Lane values cross only this file's internal functions and the inline
// kernels of deterministic_math.hpp (the AVX calling-convention note
// concerns no interface; GCC and Clang both give it).
#pragma GCC diagnostic ignored "-Wpsabi"
#include "dynamics/pose_lanes.hpp"

#include <atomic>
#include <bit>
#include <type_traits>

#include "dynamics/body_store.hpp"
#include "math/real_bits.hpp"

namespace fulcrum::detail {

namespace {
// On by default. They were off for a while: two copies of one world at
// three threads (ManifoldBits) were seen to part about once in thirty runs
// with them on, which was taken for a lane whose result depends on its
// group. It is not theirs: the same parting happens with them off, a
// lane's bits do not depend on its group, and on or off the same memory is
// read and written in the same ranges (docs/benchmarks.md, branch lanes12;
// tests/dynamics/pose_lanes_test.cpp).
std::atomic<bool> gPoseLanes{true};
}  // namespace

bool poseLanesEnabled() { return gPoseLanes.load(std::memory_order_relaxed); }
void setPoseLanesEnabled(bool enabled) { gPoseLanes.store(enabled, std::memory_order_relaxed); }

#if defined(__GNUC__) && defined(__SSE2__)
}  // namespace fulcrum::detail

#include <xmmintrin.h>  // _MM_TRANSPOSE4_PS
#include <emmintrin.h>  // sqrtps / sqrtpd (correctly rounded, as std::sqrt); f32x4/f64x2.sqrt under Emscripten's SSE2

namespace fulcrum::detail {

namespace {

using Float4 = float __attribute__((vector_size(16)));
using Double2 = double __attribute__((vector_size(16)));
using Double4 = double __attribute__((vector_size(32)));
using RealLanes = Real __attribute__((vector_size(4 * sizeof(Real))));
using BitLanes = RealBits __attribute__((vector_size(4 * sizeof(Real))));

// The float build uses the Float4 overloads, the double build the Double4 ones.
[[maybe_unused]] Float4 sqrtLanes(Float4 x) { return _mm_sqrt_ps(x); }
[[maybe_unused]] Double4 sqrtLanes(const Double4& x) {
    const Double2 lo = _mm_sqrt_pd(Double2{x[0], x[1]}), hi = _mm_sqrt_pd(Double2{x[2], x[3]});
    return Double4{lo[0], lo[1], hi[0], hi[1]};
}
// Real lanes as doubles (exact) and back (rounded to nearest, as static_cast).
[[maybe_unused]] Double4 widened(Float4 x) { return __builtin_convertvector(x, Double4); }
[[maybe_unused]] Double4 widened(const Double4& x) { return x; }
[[maybe_unused]] Float4 toReal(const Double4& x, Float4) { return __builtin_convertvector(x, Float4); }
[[maybe_unused]] Double4 toReal(const Double4& x, const Double4&) { return x; }

// Four quaternions (lanes past n repeat lane 0) as lanes of w, x, y, z; in
// the float build one 4 x 4 transpose (Quat is four floats, w first).
template <class L>
void loadQuats(const Quat* const* q, int n, L& w, L& x, L& y, L& z) {
    if constexpr (std::is_same_v<L, Float4>) {
        static_assert(sizeof(Quat) == sizeof(L));
        const auto row = [&](int k) { return _mm_loadu_ps(reinterpret_cast<const float*>(q[k < n ? k : 0])); };
        __m128 r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        w = r0, x = r1, y = r2, z = r3;
    } else {
        for (int k = 0; k < 4; ++k) {
            const Quat& from = *q[k < n ? k : 0];
            w[k] = from.w, x[k] = from.x, y[k] = from.y, z[k] = from.z;
        }
    }
}
// Three-vectors likewise (x and y as one 8-byte load, z alone: nothing past the Vec3 is read).
template <class L>
void loadVecs(const Vec3* const* v, int n, L& x, L& y, L& z) {
    if constexpr (std::is_same_v<L, Float4>) {
        static_assert(sizeof(Vec3) * 4 == sizeof(L) * 3);
        __m128 r[4];
        for (int k = 0; k < 4; ++k) {
            const float* from = reinterpret_cast<const float*>(v[k < n ? k : 0]);
            r[k] = _mm_movelh_ps(_mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(from))), _mm_load_ss(from + 2));
        }
        _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
        x = r[0], y = r[1], z = r[2];
    } else {
        for (int k = 0; k < 4; ++k) {
            const Vec3& from = *v[k < n ? k : 0];
            x[k] = from.x, y[k] = from.y, z[k] = from.z;
        }
    }
}
// Lane k of (w, x, y, z) into a Quat each, for the lanes `write` keeps.
template <class L, class Write>
void storeQuats(Quat* const* q, int n, const L& w, const L& x, const L& y, const L& z, Write&& write) {
    if constexpr (std::is_same_v<L, Float4>) {
        __m128 r0 = w, r1 = x, r2 = y, r3 = z;
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        const __m128 r[4] = {r0, r1, r2, r3};
        for (int k = 0; k < n; ++k) {
            if (write(k)) _mm_storeu_ps(reinterpret_cast<float*>(q[k]), r[k]);
        }
    } else {
        for (int k = 0; k < n; ++k) {
            if (write(k)) *q[k] = Quat(w[k], x[k], y[k], z[k]);
        }
    }
}
template <class L, class Write>
void storeVecs(Vec3* const* v, int n, const L& x, const L& y, const L& z, Write&& write) {
    if constexpr (std::is_same_v<L, Float4>) {
        __m128 r0 = x, r1 = y, r2 = z, r3 = _mm_setzero_ps();
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        const __m128 r[4] = {r0, r1, r2, r3};
        for (int k = 0; k < n; ++k) {
            if (!write(k)) continue;
            float* to = reinterpret_cast<float*>(v[k]);
            _mm_storel_pi(reinterpret_cast<__m64*>(to), r[k]);
            _mm_store_ss(to + 2, _mm_movehl_ps(r[k], r[k]));
        }
    } else {
        for (int k = 0; k < n; ++k) {
            if (write(k)) *v[k] = Vec3(x[k], y[k], z[k]);
        }
    }
}

}  // namespace

void integrateRotations(Quat* const* q, const Vec3* const* w, int n, Real h) {
    if (!poseLanesEnabled()) {
        for (int k = 0; k < n; ++k) *q[k] = integrateRotation(*q[k], *w[k], h);
        return;
    }
    // Lanes past n repeat lane 0 (computed, never written).
    RealLanes qw, qx, qy, qz, wx, wy, wz;
    loadQuats(q, n, qw, qx, qy, qz);
    loadVecs(w, n, wx, wy, wz);
    // integrateRotation's first-order path (angle = |w| h < 1e-9):
    // normalize(q + Quat(0, w) q (h / 2)), operator* written out (its 0 * q
    // terms kept: they give the sign of a zero).
    const RealLanes len = sqrtLanes(wx * wx + wy * wy + wz * wz);
    const RealLanes angle = len * h;
    const Real halfStep = Real(0.5) * h;
    const RealLanes zero{};
    const RealLanes tw = (zero * qw - wx * qx - wy * qy - wz * qz) * halfStep;
    const RealLanes tx = (zero * qx + wx * qw + wy * qz - wz * qy) * halfStep;
    const RealLanes ty = (zero * qy - wx * qz + wy * qw + wz * qx) * halfStep;
    const RealLanes tz = (zero * qz + wx * qy - wy * qx + wz * qw) * halfStep;
    const RealLanes fw = qw + tw, fx = qx + tx, fy = qy + ty, fz = qz + tz;
    const RealLanes flen = sqrtLanes(fw * fw + fx * fx + fy * fy + fz * fz);
    const RealLanes finv = Real(1) / flen;
    // NaN fails every comparison: such a lane goes to the scalar function,
    // as does a zero length (normalize's identity).
    const auto firstOrder = (angle < Real(1e-9)) & (flen > Real(0));
    bool allFirstOrder = true;
    for (int k = 0; k < n; ++k) allFirstOrder = allFirstOrder && firstOrder[k] != 0;
    if (allFirstOrder) {
        storeQuats(q, n, fw * finv, fx * finv, fy * finv, fz * finv, [](int) { return true; });
        return;
    }
    // And its exact-map path: the rotation by `angle` about w / |w|
    // (Quat::fromAxisAngle, its sinCos at a half angle in [0, 0.75], where
    // the reduction by pi/2 is the identity: quadrant 0, r = x), times q,
    // renormalised.
    const RealLanes nx = wx / len, ny = wy / len, nz = wz / len;
    const RealLanes half = Real(0.5) * angle;
    const Double4 x = widened(half);
    const RealLanes s = toReal(dmath::detail::sinKernelOf(x), RealLanes{});
    const RealLanes c = toReal(dmath::detail::cosKernelOf(x), RealLanes{});
    const RealLanes ax = nx * s, ay = ny * s, az = nz * s;
    const RealLanes pw = c * qw - ax * qx - ay * qy - az * qz;
    const RealLanes px = c * qx + ax * qw + ay * qz - az * qy;
    const RealLanes py = c * qy - ax * qz + ay * qw + az * qx;
    const RealLanes pz = c * qz + ax * qy - ay * qx + az * qw;
    const RealLanes plen = sqrtLanes(pw * pw + px * px + py * py + pz * pz);
    const RealLanes pinv = Real(1) / plen;
    const auto exactMap = (angle >= Real(1e-9)) & (half <= Real(0.75)) & (plen > Real(0));
    // The scalar function first (it reads q), then the lanes' results.
    for (int k = 0; k < n; ++k) {
        if (firstOrder[k] == 0 && exactMap[k] == 0) *q[k] = integrateRotation(*q[k], *w[k], h);
    }
    storeQuats(q, n, fw * finv, fx * finv, fy * finv, fz * finv, [&](int k) { return firstOrder[k] != 0; });
    storeQuats(q, n, pw * pinv, px * pinv, py * pinv, pz * pinv,
               [&](int k) { return firstOrder[k] == 0 && exactMap[k] != 0; });
}

void stepRotationVectors(const Quat* const* q, const Quat* const* start, Vec3* const* out, int n) {
    if (!poseLanesEnabled()) {
        for (int k = 0; k < n; ++k) *out[k] = stepRotationVector(*q[k] * conjugate(*start[k]));
        return;
    }
    RealLanes aw, ax, ay, az, bw, bx, by, bz;
    loadQuats(q, n, aw, ax, ay, az);
    loadQuats(start, n, bw, bx, by, bz);
    // conjugate(start): the vector part negated (exact).
    bx = -bx, by = -by, bz = -bz;
    // q * conjugate(start), operator* written out.
    const RealLanes rw = aw * bw - ax * bx - ay * by - az * bz;
    const RealLanes rx = aw * bx + ax * bw + ay * bz - az * by;
    const RealLanes ry = aw * by - ax * bz + ay * bw + az * bx;
    const RealLanes rz = aw * bz + ax * by - ay * bx + az * bw;
    // The shortest arc: -r where r.w < 0, as a sign flip (the scalar negation).
    const BitLanes flip = std::bit_cast<BitLanes>(rw < Real(0)) & (~RealBits(0) ^ (~RealBits(0) >> 1));
    const auto negated = [&](const RealLanes& v) { return std::bit_cast<RealLanes>(std::bit_cast<BitLanes>(v) ^ flip); };
    const RealLanes pw = negated(rw), px = negated(rx), py = negated(ry), pz = negated(rz);
    // stepRotationVector's series path (x^2 = s^2 / w^2 < 0.01).
    const RealLanes s2 = px * px + py * py + pz * pz;
    const RealLanes w2 = pw * pw;
    const auto inRange = s2 < Real(0.01) * w2;
    const RealLanes x2 = s2 / w2;
    const RealLanes series = Real(1) - x2 * (Real(1) / 3 - x2 * (Real(1) / 5 - x2 * (Real(1) / 7)));
    const RealLanes f = Real(2) / pw * series;
    const RealLanes dx = px * f, dy = py * f, dz = pz * f;
    storeVecs(out, n, dx, dy, dz, [&](int k) { return inRange[k] != 0; });
    for (int k = 0; k < n; ++k) {
        if (inRange[k] == 0) *out[k] = stepRotationVector(*q[k] * conjugate(*start[k]));
    }
}

#else

void integrateRotations(Quat* const* q, const Vec3* const* w, int n, Real h) {
    for (int k = 0; k < n; ++k) *q[k] = integrateRotation(*q[k], *w[k], h);
}

void stepRotationVectors(const Quat* const* q, const Quat* const* start, Vec3* const* out, int n) {
    for (int k = 0; k < n; ++k) *out[k] = stepRotationVector(*q[k] * conjugate(*start[k]));
}

#endif

}  // namespace fulcrum::detail
