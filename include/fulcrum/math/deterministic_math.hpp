#pragma once
// Fulcrum's own sine, cosine and arc functions, built only from + - * / and
// sqrt (which IEEE 754 requires to be correctly rounded, so every compiler,
// standard library and CPU -- x86-64 with or without AVX2, WebAssembly --
// gives the same bits) plus exact operations (floor, fabs, copysign,
// comparisons). The C library's sin, cos, atan2, acos... are not required to
// be correctly rounded and differ between glibc, musl, MSVC and Emscripten's
// libc, and between versions of one of them; anything that changes the
// simulated state calls these instead (docs/determinism.md).
//
// Every function is evaluated in double and the float overloads round the
// double result once. Measured against glibc's functions
// (tests/math/deterministic_math_test.cpp samples each domain and keeps to
// these bounds):
//   sin, cos     |x| <= 8: within 1 ulp; |x| <= 1e6: absolute error <= 2.3e-16;
//                beyond, still deterministic, the error grows as |x| 2^-100
//                (the reduction by pi/2)
//   atan, atan2, asin: within 4 ulp of double; acos: within 5 ulp
//   float overloads: within 1 ulp of glibc's sinf, cosf, atan2f, acosf...
// NaN gives NaN; an infinite sin/cos argument gives NaN.
//
// The guarantee needs the arithmetic here to be done as written: Fulcrum
// compiles with -ffp-contract=off (no fused multiply-add) and never with
// -ffast-math; code of users that includes this header keeps the same
// results when compiled the same way.
#include <cmath>
#include <limits>

namespace fulcrum::dmath {

namespace detail {

// pi / 2 as three parts: the first two have 33 significant bits, so k * part
// is exact for |k| < 2^20 and x - k pi/2 loses nothing for |x| < ~1.6e6.
inline constexpr double kHalfPi1 = 1.5707963267341256;
inline constexpr double kHalfPi2 = 6.077100506303966e-11;
inline constexpr double kHalfPi3 = 2.0222662487959506e-21;
inline constexpr double kTwoOverPi = 0.6366197723675814;
// pi, pi/2, pi/4 each as a double and the remainder, to add small results
// to them with one rounding.
inline constexpr double kPiHi = 3.141592653589793, kPiLo = 1.2246467991473532e-16;
inline constexpr double kHalfPiHi = 1.5707963267948966, kHalfPiLo = 6.123233995736766e-17;
inline constexpr double kQuarterPiHi = 0.7853981633974483, kQuarterPiLo = 3.061616997868383e-17;

// sin and cos on |r| <= pi/4 (a little more after the reduction's
// rounding): Taylor series (coefficients 1/n!) to r^17 and r^18; the first
// terms left out are below 1e-19. Templates so that lanes of doubles (GCC
// and Clang vector types: src/dynamics/pose_lanes.hpp) run exactly these
// operations; the double functions below are the same expressions.
template <class T>
inline T sinKernelOf(const T& r) {
    const T z = r * r;
    const T p =
        -0.16666666666666666 +
        z * (0.008333333333333333 +
             z * (-0.0001984126984126984 +
                  z * (2.7557319223985893e-06 +
                       z * (-2.505210838544172e-08 +
                            z * (1.6059043836821613e-10 + z * (-7.647163731819816e-13 + z * 2.8114572543455206e-15))))));
    return r + r * (z * p);
}
template <class T>
inline T cosKernelOf(const T& r) {
    const T z = r * r;
    const T p =
        0.041666666666666664 +
        z * (-0.001388888888888889 +
             z * (2.48015873015873e-05 +
                  z * (-2.755731922398589e-07 +
                       z * (2.08767569878681e-09 +
                            z * (-1.1470745597729725e-11 + z * (4.779477332387385e-14 + z * -1.5619206968586225e-16))))));
    // 1 - z/2 + z^2 p: the two small terms summed first, then added to 1.
    return 1.0 + (z * (-0.5) + (z * z) * p);
}
inline double sinKernel(double r) { return sinKernelOf(r); }
inline double cosKernel(double r) { return cosKernelOf(r); }

// r = x - k pi/2 with k the nearest integer to x 2/pi; quadrant = k mod 4.
// An infinite or NaN x gives r = NaN (and no conversion of NaN to int).
inline double reduceHalfPi(double x, int& quadrant) {
    if (!std::isfinite(x)) {
        quadrant = 0;
        return x - x;
    }
    const double k = std::floor(x * kTwoOverPi + 0.5);
    const double k4 = k - 4.0 * std::floor(k * 0.25);  // exact: integers, k mod 4 in [0, 4)
    quadrant = static_cast<int>(k4);
    return ((x - k * kHalfPi1) - k * kHalfPi2) - k * kHalfPi3;
}

// atan on [0, 1] (NaN passes through): above tan(pi/8), atan(t) =
// pi/4 + atan((t - 1) / (t + 1)); then one halving, atan(u) = 2 atan(u / (1 +
// sqrt(1 + u^2))), brings |u| under tan(pi/16) ~ 0.199, where the series
// u - u^3/3 + u^5/5 ... to u^25 leaves out less than 6e-19 of u.
inline double atanUnit(double t) {
    double base = 0.0, baseLo = 0.0;
    if (t > 0.41421356237309503) {
        t = (t - 1.0) / (t + 1.0);
        base = kQuarterPiHi;
        baseLo = kQuarterPiLo;
    }
    const double u = t / (1.0 + std::sqrt(1.0 + t * t));
    const double z = u * u;
    const double p =
        -1.0 / 3 +
        z * (1.0 / 5 +
             z * (-1.0 / 7 +
                  z * (1.0 / 9 +
                       z * (-1.0 / 11 +
                            z * (1.0 / 13 +
                                 z * (-1.0 / 15 +
                                      z * (1.0 / 17 +
                                           z * (-1.0 / 19 + z * (1.0 / 21 + z * (-1.0 / 23 + z * (1.0 / 25)))))))))));
    const double atanU = u + u * (z * p);
    return base + (2.0 * atanU + baseLo);
}

}  // namespace detail

inline double sin(double x) {
    int quadrant = 0;
    const double r = detail::reduceHalfPi(x, quadrant);
    switch (quadrant) {
        case 0: return detail::sinKernel(r);
        case 1: return detail::cosKernel(r);
        case 2: return -detail::sinKernel(r);
        default: return -detail::cosKernel(r);
    }
}
inline double cos(double x) {
    int quadrant = 0;
    const double r = detail::reduceHalfPi(x, quadrant);
    switch (quadrant) {
        case 0: return detail::cosKernel(r);
        case 1: return -detail::sinKernel(r);
        case 2: return -detail::cosKernel(r);
        default: return detail::sinKernel(r);
    }
}
// Both at once, one reduction: the same bits as sin(x) and cos(x).
inline void sinCos(double x, double& s, double& c) {
    int quadrant = 0;
    const double r = detail::reduceHalfPi(x, quadrant);
    const double sr = detail::sinKernel(r), cr = detail::cosKernel(r);
    switch (quadrant) {
        case 0: s = sr, c = cr; break;
        case 1: s = cr, c = -sr; break;
        case 2: s = -sr, c = -cr; break;
        default: s = -cr, c = sr; break;
    }
}

inline double atan(double x) {
    const double t = std::fabs(x);
    // Above 1: pi/2 - atan(1/t) (an infinite t gives pi/2).
    const double a = t <= 1.0 ? detail::atanUnit(t)
                              : (t > 1.0 ? detail::kHalfPiHi + (detail::kHalfPiLo - detail::atanUnit(1.0 / t)) : t);
    return std::copysign(a, x);
}

// The angle of (x, y) in [-pi, pi], with the C library's signs and
// special cases: atan2(+-0, +0) = +-0, atan2(+-0, -0) = +-pi, both infinite:
// odd multiples of pi/4.
inline double atan2(double y, double x) {
    if (std::isnan(x) || std::isnan(y)) return x + y;
    const double ax = std::fabs(x), ay = std::fabs(y);
    double a;  // the angle of (|x|, |y|), in [0, pi/2]
    if (std::isinf(ax) && std::isinf(ay)) {
        a = detail::kQuarterPiHi;
    } else if (ay <= ax) {
        a = ax == 0.0 ? 0.0 : detail::atanUnit(ay / ax);
    } else {
        a = detail::kHalfPiHi + (detail::kHalfPiLo - detail::atanUnit(ax / ay));
    }
    if (std::signbit(x)) a = detail::kPiHi + (detail::kPiLo - a);
    return std::copysign(a, y);
}

// acos(x) = 2 atan(sqrt((1 - x) / (1 + x))), as an atan2 so that x = -1
// gives pi; 1 - x and 1 + x lose nothing near the end where each matters.
// Outside [-1, 1]: NaN.
inline double acos(double x) {
    if (!(std::fabs(x) <= 1.0)) return std::numeric_limits<double>::quiet_NaN();
    return 2.0 * atan2(std::sqrt(1.0 - x), std::sqrt(1.0 + x));
}
inline double asin(double x) {
    if (!(std::fabs(x) <= 1.0)) return std::numeric_limits<double>::quiet_NaN();
    return atan2(x, std::sqrt((1.0 - x) * (1.0 + x)));
}

inline float sin(float x) { return static_cast<float>(sin(static_cast<double>(x))); }
inline float cos(float x) { return static_cast<float>(cos(static_cast<double>(x))); }
inline void sinCos(float x, float& s, float& c) {
    double sd = 0, cd = 0;
    sinCos(static_cast<double>(x), sd, cd);
    s = static_cast<float>(sd);
    c = static_cast<float>(cd);
}
inline float atan(float x) { return static_cast<float>(atan(static_cast<double>(x))); }
inline float atan2(float y, float x) { return static_cast<float>(atan2(static_cast<double>(y), static_cast<double>(x))); }
inline float acos(float x) { return static_cast<float>(acos(static_cast<double>(x))); }
inline float asin(float x) { return static_cast<float>(asin(static_cast<double>(x))); }

}  // namespace fulcrum::dmath
