#include "dynamics/integrators.hpp"


#include <bit>
#include <cstdint>

#include "dynamics/pose_lanes.hpp"
#include "math/real_bits.hpp"

namespace fulcrum::detail {

namespace {

// An awake body's state as the integrators see it: its pose and its
// velocities in the body store's awake set (body_store.hpp), one view.
struct Motion {
    BodyPose& x;
    SolverBody& s;
};
Motion motionOf(BodyStore& b, std::size_t solverIndex) { return {b.pose[solverIndex], b.state[solverIndex]}; }

bool moves(const BodyParams& p) { return p.type != BodyType::Static && p.awake; }
bool isDynamic(const BodyParams& p) { return p.type == BodyType::Dynamic && p.awake; }

// The symmetry of a body's inertia, which picks its drift below (one pass
// over the off-diagonal entries for both questions: the two separate tests
// were 1 % of the chain benchmark's instructions).
//   kIsotropic: I = s * identity (spheres, cubes, regular solids): I_w = R I R^T
//     = I, so the angular momentum drift keeps w exactly and reduces to one rotation;
//   0, 1, 2: diagonal with exactly two equal entries (capsules, cylinders, boxes
//     with two equal sides, ragdoll limbs): the index of the symmetry axis;
//   kGeneral: anything else.
constexpr int kIsotropic = -1, kGeneral = -2;
//
// The off-diagonal test ORs the six entries' bits without their signs (zero
// for +0 and -0 only; a NaN stays non-zero, as for "!= 0"): one branch
// instead of six (callgrind, chain: 20 -> ~10 instructions per body).
int inertiaSymmetry(const Mat3& i) {
    if ((magnitudeBits(i.c0.y) | magnitudeBits(i.c0.z) | magnitudeBits(i.c1.x) | magnitudeBits(i.c1.z) |
         magnitudeBits(i.c2.x) | magnitudeBits(i.c2.y)) != 0) {
        return kGeneral;
    }
    const bool xy = i.c0.x == i.c1.y, yz = i.c1.y == i.c2.z;
    if (xy && yz) return kIsotropic;
    if (yz) return 0;
    if (i.c0.x == i.c2.z) return 1;
    if (xy) return 2;
    return kGeneral;
}

// The Taylor series of sin and cos to double rounding for |x| <= 0.5, for
// any lane type (halfAngleSinCos, the paired drift, the general drift's
// sin(x)/x): sin x = x + x z sinTail(z) and cos x = cosSeries(z), z = x^2
// (results through references: a vector return type would change the psABI).
template <class T>
void sinTail(const T& z, T& tail) {
    tail = -1.0 / 6 +
           z * (1.0 / 120 + z * (-1.0 / 5040 + z * (1.0 / 362880 + z * (-1.0 / 39916800 + z * (1.0 / 6227020800)))));
}
template <class T>
void cosSeries(const T& z, T& c) {
    c = 1.0 + z * (-0.5 + z * (1.0 / 24 +
                                  z * (-1.0 / 720 +
                                       z * (1.0 / 40320 +
                                            z * (-1.0 / 3628800 + z * (1.0 / 479001600 + z * (-1.0 / 87178291200)))))));
}
template <class T>
void seriesSinCos(const T& x, T& s, T& c) {
    const T z = x * x;
    T tail;
    sinTail(z, tail);
    s = x + x * z * tail;
    cosSeries(z, c);
}

// sin and cos of a half-angle of the drift. The spin limit
// (WorldDef::maxRotationPerSubstep, default pi/4) keeps both of the drift's
// half-angles within pi/8 (the precession rate |L| / I_t and the spin rate
// are each at most |w|), where the Taylor series to x^13 and x^14 are exact to
// double rounding (the next terms are below 2.3e-17 for |x| <= 0.5); beyond
// 0.5 (the limit off) Fulcrum's own (deterministic_math.hpp). The library's sincos was 3.8 % of the
// chain benchmark's instructions (two calls per link and sub-step, ~70
// instructions each); these are ~30 for both.
void halfAngleSinCos(double x, double& s, double& c) {
    if (!(std::fabs(x) <= 0.5)) {
        dmath::sinCos(x, s, c);
        return;
    }
    seriesSinCos(x, s, c);
}

// The axisymmetric drift below works in double: in float, the axial angular
// momentum L.a (a small component of L when the axis is far from L) drifted
// by a steady 5e-7 of itself per sub-step from the roundings of the two
// rotations and the normalisations (a capsule lost 7e-4 of its spin over 10 s
// at 120 Hz). In double the same run keeps L.a to 1e-9; the float values it
// stores round to nearest, without a bias.
//
// Torque-free drift of an axisymmetric body (principal moments I_t, I_t, I_a
// about symmetry axis a = body axis K), in closed form: with L = I_w w
// constant, the body turns about the fixed direction of L at |L| / I_t
// (precession) while it spins about its own axis at (L.a)(1/I_a - 1/I_t), so
//     q(h) = rot(L, |L| h / I_t) q(0) rot_body(e_K, (L.a)(1/I_a - 1/I_t) h)
// (the two rates add up to w = L / I_t + (1/I_a - 1/I_t)(L.a) a). Exact, so no
// midpoint rate is needed, and it costs two sin/cos pairs instead of the
// general drift's three rotations, five R I R^T products and two 3x3 inverses
// (chain of 100 capsules: that drift and the inverse-inertia refresh were 28 %
// of the step's instructions). w and I_w^-1 come from the new axis a'.
//
// Written for few operations (chain benchmark, callgrind, 120 steps: the
// position stage 43.4 M -> 34.8 M with the series sin/cos below, 23.6 M with
// the SIMD pairs; docs/integrators.md), with the same rotations:
//  - a is column K of R(q), normalised. (Its homogeneous form, length
//    exactly |q|^2, would save the sqrt; it is as exact, but the float
//    roundings then walk L differently, and the closed-form test's w check,
//    which reads the initial L, ended at 2.4e-5 instead of 6e-6: that check
//    sits at the random-walk level of the stored float w, so we kept the
//    rounding pattern it was tuned on.)
//  - the spin about the body axis is a quaternion with one non-zero vector
//    component, so q rot_body is 16 multiply-adds at most, written out per K;
//  - the new axis a' = rot(L) a (the spin leaves a unchanged) by Rodrigues'
//    formula with the full-angle cos/sin formed from the half-angle ones, not
//    read back from the new quaternion;
//  - L.a' = L.a (a rotation about L keeps it), so w' = L / I_t + (1/I_a -
//    1/I_t)(L.a) a' uses the value computed once: no re-projection.
// L = I_t w + (I_a - I_t)(w.a) a loses log2(I_t / I_a) ~ 4 bits to
// cancellation for a long capsule, which in double leaves ~1e-15.
template <class T>
struct Vec3Of {
    T x, y, z;
};
using D3 = Vec3Of<double>;

// Two bodies' drifts at once, one per lane of a 2 x double SSE2 register
// (GCC/Clang vector extension; elsewhere bodies go one at a time). The lanes
// run exactly the scalar operations, in the same order (no FMA in the
// default x86-64 build, and none is formed across lanes), so a body's bits
// do not depend on whether, or with which body, it was paired: the world's
// results stay the same for any body order or thread ranges.
//
// Four bodies go through the drift at once (Double4: two SSE2 registers per
// value, so two independent dependency chains the core overlaps). The drift
// is one long chain of latencies (three square roots, seven divisions and two
// series per body, ~150 cycles) and with one pair in flight the out-of-order
// window could not reach the next pair: integratePositions was 18 % of the
// chain benchmark's time for 13.5 % of its instructions. The square roots are
// sqrtpd (correctly rounded, as std::sqrt; std::sqrt per lane also paid the
// errno check).
#if defined(__GNUC__) && defined(__SSE2__)
#include <emmintrin.h>  // _mm_sqrt_pd: sqrtpd natively, f64x2.sqrt under Emscripten's SSE2 (-msimd128 -msse2)
using Double2 = double __attribute__((vector_size(16)));
using Double4 = double __attribute__((vector_size(32)));
// Double4 values cross only internal (anonymous-namespace, inlined) functions,
// so the AVX calling-convention note does not concern any interface (GCC
// and Clang both give it).
#pragma GCC diagnostic ignored "-Wpsabi"
constexpr bool kPairedDrift = true;
Double2 sqrtOf(Double2 x) { return _mm_sqrt_pd(x); }
Double4 sqrtOf(Double4 x) {
    const Double2 lo = _mm_sqrt_pd(Double2{x[0], x[1]}), hi = _mm_sqrt_pd(Double2{x[2], x[3]});
    return Double4{lo[0], lo[1], hi[0], hi[1]};
}
// anyStill: whether a lane's L is zero (lengthL2 not above 0).
template <class V>
bool allLanes(V lengthL2, V halfSpin, V halfAngle, bool& anyStill) {
    constexpr int kLanes = static_cast<int>(sizeof(V) / sizeof(double));
    anyStill = false;
    for (int k = 0; k < kLanes; ++k) {
        if (!(lengthL2[k] >= 0) || !(std::fabs(halfSpin[k]) <= 0.5) || !(std::fabs(halfAngle[k]) <= 0.5)) return false;
        anyStill = anyStill || !(lengthL2[k] > 0);
    }
    return true;
}
// value = kept in the lanes where L is zero (lengthL2 not above 0).
template <class V>
void keepWhereStill(const V& lengthL2, V& value, const V& kept) {
    constexpr int kLanes = static_cast<int>(sizeof(V) / sizeof(double));
    for (int k = 0; k < kLanes; ++k) {
        if (!(lengthL2[k] > 0)) value[k] = kept[k];
    }
}
#else
constexpr bool kPairedDrift = false;
#endif
double sqrtOf(double x) { return std::sqrt(x); }
bool allLanes(double lengthL2, double halfSpin, double halfAngle, bool& anyStill) {
    anyStill = !(lengthL2 > 0);
    return lengthL2 >= 0 && std::fabs(halfSpin) <= 0.5 && std::fabs(halfAngle) <= 0.5;
}
void keepWhereStill(double lengthL2, double& value, double kept) {
    if (!(lengthL2 > 0)) value = kept;
}

// One drift's numbers, per lane: orientation and angular velocity in, the
// new ones and the new symmetry axis out; the two principal moments.
template <class T>
struct DriftLanes {
    T qw, qx, qy, qz;
    T wx, wy, wz;
    T ax, ay, az;
    T inertiaAxis, inertiaSide;
};


// Body axis K of q (the K-th column of its rotation matrix, not yet
// renormalised), for any lane type: the lanes and the general path share it.
template <int K, class T>
void bodyAxisOf(const T& qw, const T& qx, const T& qy, const T& qz, T& ax, T& ay, T& az) {
    if constexpr (K == 0) {
        ax = 1.0 - 2.0 * (qy * qy + qz * qz), ay = 2.0 * (qx * qy + qw * qz), az = 2.0 * (qx * qz - qw * qy);
    } else if constexpr (K == 1) {
        ax = 2.0 * (qx * qy - qw * qz), ay = 1.0 - 2.0 * (qx * qx + qz * qz), az = 2.0 * (qy * qz + qw * qx);
    } else {
        ax = 2.0 * (qx * qz + qw * qy), ay = 2.0 * (qy * qz - qw * qx), az = 1.0 - 2.0 * (qx * qx + qy * qy);
    }
}

// q (cs, ss e_K): a spin about the body's own axis K, the one-component
// quaternion product written out per axis.
template <int K, class T>
void spinAboutBodyAxis(const T& qw, const T& qx, const T& qy, const T& qz, const T& cs, const T& ss, T& rw, T& rx,
                       T& ry, T& rz) {
    if constexpr (K == 0) {
        rw = qw * cs - qx * ss, rx = qx * cs + qw * ss, ry = qy * cs + qz * ss, rz = qz * cs - qy * ss;
    } else if constexpr (K == 1) {
        rw = qw * cs - qy * ss, rx = qx * cs - qz * ss, ry = qy * cs + qw * ss, rz = qz * cs + qx * ss;
    } else {
        rw = qw * cs - qz * ss, rx = qx * cs + qy * ss, ry = qy * cs - qx * ss, rz = qz * cs + qw * ss;
    }
}

// The drift (see above) for bodies whose two half-angles are within the
// series' range (every lane): false, with nothing written, otherwise
// (driftAxisymmetric then takes the general path). A lane whose L is zero (a
// body at rest, or dropped without spin: ConvexVsMesh's 1764 bodies fall for
// their first ~60 steps so) takes driftGeneral's branch for it: no
// precession, the spun quaternion and the old axis kept, the same operations
// on the same values. (Such lanes once failed the whole group, which then
// ran every body through the scalar lanes and driftGeneral: 13 % of
// ConvexVsMesh's first 100 steps.)
template <int K, class T>
bool driftLanes(DriftLanes<T>& d, double hd) {
    const T qw = d.qw, qx = d.qx, qy = d.qy, qz = d.qz;
    T ax, ay, az;
    bodyAxisOf<K>(qw, qx, qy, qz, ax, ay, az);
    const T invLengthA = 1.0 / sqrtOf(ax * ax + ay * ay + az * az);
    ax = ax * invLengthA, ay = ay * invLengthA, az = az * invLengthA;
    const T wx = d.wx, wy = d.wy, wz = d.wz;
    const T inertiaAxis = d.inertiaAxis, inertiaSide = d.inertiaSide;
    const T wAxis = wx * ax + wy * ay + wz * az;
    const T lAxis = inertiaAxis * wAxis;
    const T excess = (inertiaAxis - inertiaSide) * wAxis;
    const T lx = inertiaSide * wx + excess * ax, ly = inertiaSide * wy + excess * ay, lz = inertiaSide * wz + excess * az;
    const T lengthL2 = lx * lx + ly * ly + lz * lz;
    const T halfSpin = 0.5 * (wAxis - lAxis / inertiaSide) * hd;
    const T lengthL = sqrtOf(lengthL2);
    const T halfAngle = 0.5 * lengthL / inertiaSide * hd;
    bool anyStill;
    if (!allLanes(lengthL2, halfSpin, halfAngle, anyStill)) return false;
    // Spin about the body axis (right): q (cs, ss e_K).
    T cs, ss;
    seriesSinCos(halfSpin, ss, cs);
    T rw, rx, ry, rz;
    spinAboutBodyAxis<K>(qw, qx, qy, qz, cs, ss, rw, rx, ry, rz);
    // Precession about L (left).
    const T invL = 1.0 / lengthL;
    T c, s;
    seriesSinCos(halfAngle, s, c);
    const T nx = lx * invL, ny = ly * invL, nz = lz * invL;
    const T sx = nx * s, sy = ny * s, sz = nz * s;
    T pw = c * rw - sx * rx - sy * ry - sz * rz;
    T px = c * rx + sx * rw + sy * rz - sz * ry;
    T py = c * ry - sx * rz + sy * rw + sz * rx;
    T pz = c * rz + sx * ry - sy * rx + sz * rw;
    // a' = a cos + (n x a) sin + n (n.a)(1 - cos), full angle from the half angle.
    const T oneMinusCos = 2.0 * s * s, sinFull = 2.0 * s * c, cosFull = 1.0 - oneMinusCos;
    const T na = (nx * ax + ny * ay + nz * az) * oneMinusCos;
    d.ax = ax * cosFull + (ny * az - nz * ay) * sinFull + nx * na;
    d.ay = ay * cosFull + (nz * ax - nx * az) * sinFull + ny * na;
    d.az = az * cosFull + (nx * ay - ny * ax) * sinFull + nz * na;
    // L = 0: no precession. 1 / |L| made that lane's values above NaN; they
    // are replaced by r and a, exactly driftGeneral's q' and a' there. (Only
    // when a lane has L = 0: the lane tests cost 0.5 % of the settled
    // ConvexVsMesh step, where no lane has.)
    if (anyStill) {
        keepWhereStill(lengthL2, pw, rw), keepWhereStill(lengthL2, px, rx), keepWhereStill(lengthL2, py, ry),
            keepWhereStill(lengthL2, pz, rz);
        keepWhereStill(lengthL2, d.ax, ax), keepWhereStill(lengthL2, d.ay, ay), keepWhereStill(lengthL2, d.az, az);
    }
    const T invNorm = 1.0 / sqrtOf(pw * pw + px * px + py * py + pz * pz);
    d.qw = pw * invNorm, d.qx = px * invNorm, d.qy = py * invNorm, d.qz = pz * invNorm;
    // w' = L / I_t + (1/I_a - 1/I_t)(L.a) a'.
    const T invSide = 1.0 / inertiaSide;
    const T axial = lAxis * (1.0 / inertiaAxis - invSide);
    d.wx = lx * invSide + d.ax * axial, d.wy = ly * invSide + d.ay * axial, d.wz = lz * invSide + d.az * axial;
    return true;
}

// The general path, one body: L = 0 (no precession) or a half-angle beyond
// the series' range (the spin limit off), with the library's sin/cos there.
template <int K>
void driftGeneral(DriftLanes<double>& d, double hd) {
    const double qw = d.qw, qx = d.qx, qy = d.qy, qz = d.qz;
    D3 a;
    bodyAxisOf<K>(qw, qx, qy, qz, a.x, a.y, a.z);
    const double invLengthA = 1 / std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
    a = {a.x * invLengthA, a.y * invLengthA, a.z * invLengthA};
    const double inertiaAxis = d.inertiaAxis, inertiaSide = d.inertiaSide;
    const double wAxis = d.wx * a.x + d.wy * a.y + d.wz * a.z;
    const double lAxis = inertiaAxis * wAxis;
    const double excess = (inertiaAxis - inertiaSide) * wAxis;
    const D3 l{inertiaSide * d.wx + excess * a.x, inertiaSide * d.wy + excess * a.y, inertiaSide * d.wz + excess * a.z};
    const double lengthL2 = l.x * l.x + l.y * l.y + l.z * l.z;
    const double halfSpin = 0.5 * (wAxis - lAxis / inertiaSide) * hd;
    double cs, ss;
    halfAngleSinCos(halfSpin, ss, cs);
    double rw, rx, ry, rz;
    spinAboutBodyAxis<K>(qw, qx, qy, qz, cs, ss, rw, rx, ry, rz);
    D3 an = a;
    if (lengthL2 > 0) {
        const double lengthL = std::sqrt(lengthL2);
        const double invL = 1 / lengthL;
        const double halfAngle = 0.5 * lengthL / inertiaSide * hd;
        double c, s;
        halfAngleSinCos(halfAngle, s, c);
        const D3 n{l.x * invL, l.y * invL, l.z * invL};
        const double nx = n.x * s, ny = n.y * s, nz = n.z * s;
        const double pw = c * rw - nx * rx - ny * ry - nz * rz;
        const double px = c * rx + nx * rw + ny * rz - nz * ry;
        const double py = c * ry - nx * rz + ny * rw + nz * rx;
        const double pz = c * rz + nx * ry - ny * rx + nz * rw;
        rw = pw, rx = px, ry = py, rz = pz;
        const double oneMinusCos = 2 * s * s, sinFull = 2 * s * c, cosFull = 1 - oneMinusCos;
        const double na = (n.x * a.x + n.y * a.y + n.z * a.z) * oneMinusCos;
        an = {a.x * cosFull + (n.y * a.z - n.z * a.y) * sinFull + n.x * na,
              a.y * cosFull + (n.z * a.x - n.x * a.z) * sinFull + n.y * na,
              a.z * cosFull + (n.x * a.y - n.y * a.x) * sinFull + n.z * na};
    }
    const double invNorm = 1 / std::sqrt(rw * rw + rx * rx + ry * ry + rz * rz);
    d.qw = rw * invNorm, d.qx = rx * invNorm, d.qy = ry * invNorm, d.qz = rz * invNorm;
    const double invSide = 1 / inertiaSide;
    const double axial = lAxis * (1 / inertiaAxis - invSide);
    d.wx = l.x * invSide + an.x * axial, d.wy = l.y * invSide + an.y * axial, d.wz = l.z * invSide + an.z * axial;
    d.ax = an.x, d.ay = an.y, d.az = an.z;
}

// The drift of a body with a general inertia (no two principal moments equal,
// or off-diagonal body-axis entries: hull rocks, compounds), at constant world
// angular momentum L: the rate at the midpoint orientation,
//     L = R I R^T w,  w_mid = R_mid I^-1 R_mid^T L,  q' = exp(w_mid h / 2) q,
// then w' = R' I^-1 R'^T L and I_w^-1 = R' I^-1 R'^T. Second order.
// Written for few operations (issue 21; junkyard and HighSpeed, where it was
// a third of the step): I_w is never formed nor inverted, each product maps
// through the body axes with I and I^-1 (three matrix-vector products
// instead of two 3x3 products and an adjugate of I_w); the rotations are
// exp(theta) q with sin(theta)/theta and cos theta as series in theta^2 (no
// square root, no division, no small-angle case); the matrix of the new
// orientation gives both w' and I_w^-1. In double, as the axisymmetric drift.
// The round trip w -> L -> w' -> L' must not walk |L| with a bias (mapping
// back with the unit-length rotate() once did: 1.5e-4 over 1,920 sub-steps):
// R is the homogeneous form over |q|^2, a rotation to double rounding however
// far the stored float q is from unit length, so R^T undoes R and the stored
// w' (from the stored q') maps back to L up to unbiased roundings; and
// I^-1 is formed in double (inverseInDouble), so I I^-1 is the identity to
// double rounding as well.
// For any lane type T (double, or the SIMD lanes of driftGeneralQuad: the
// same operations per lane).
template <class T>
struct RotationOf {
    Vec3Of<T> c0, c1, c2;  // columns
};
using Rotation = RotationOf<double>;
template <class T>
RotationOf<T> rotationOfLanes(const T& qw, const T& qx, const T& qy, const T& qz) {
    const T s = 2.0 / (qw * qw + qx * qx + qy * qy + qz * qz);
    const T xs = qx * s, ys = qy * s, zs = qz * s;
    const T wx = qw * xs, wy = qw * ys, wz = qw * zs;
    const T xx = qx * xs, xy = qx * ys, xz = qx * zs, yy = qy * ys, yz = qy * zs, zz = qz * zs;
    return {{1.0 - (yy + zz), xy + wz, xz - wy}, {xy - wz, 1.0 - (xx + zz), yz + wx}, {xz + wy, yz - wx, 1.0 - (xx + yy)}};
}
Rotation rotationOf(double qw, double qx, double qy, double qz) { return rotationOfLanes<double>(qw, qx, qy, qz); }
template <class T>
Vec3Of<T> times(const RotationOf<T>& m, const Vec3Of<T>& v) {  // m v (m: columns)
    return {m.c0.x * v.x + m.c1.x * v.y + m.c2.x * v.z, m.c0.y * v.x + m.c1.y * v.y + m.c2.y * v.z,
            m.c0.z * v.x + m.c1.z * v.y + m.c2.z * v.z};
}
template <class T>
Vec3Of<T> transposeTimes(const RotationOf<T>& m, const Vec3Of<T>& v) {  // m^T v
    return {m.c0.x * v.x + m.c0.y * v.y + m.c0.z * v.z, m.c1.x * v.x + m.c1.y * v.y + m.c1.z * v.z,
            m.c2.x * v.x + m.c2.y * v.y + m.c2.z * v.z};
}
Rotation toDouble(const Mat3& m) {
    const auto col = [](const Vec3& c) {
        return D3{static_cast<double>(c.x), static_cast<double>(c.y), static_cast<double>(c.z)};
    };
    return {col(m.c0), col(m.c1), col(m.c2)};
}
// I^-1 in double, by the adjugate of the symmetric I. Not the stored float
// I^-1: its rounding makes I I^-1 = diag(1 + e) with a fixed e of up to an
// ulp, which the round trip L -> w -> L applied every sub-step (|L| drifted
// 1.8e-4 over 2,400 sub-steps in the tumbling-box test). A singular I (not a
// positive determinant) keeps the stored inverse.
Rotation inverseInDouble(const Rotation& m, const Mat3& stored) {
    const double a = m.c0.x, b = m.c1.x, c = m.c2.x, d = m.c1.y, e = m.c2.y, f = m.c2.z;
    const double a00 = d * f - e * e, a01 = c * e - b * f, a02 = b * e - c * d;
    const double det = a * a00 + b * a01 + c * a02;
    if (!(det > 0)) return toDouble(stored);
    const double s = 1 / det;
    const double i00 = a00 * s, i01 = a01 * s, i02 = a02 * s;
    const double i11 = (a * f - c * c) * s, i12 = (b * c - a * e) * s, i22 = (a * d - b * b) * s;
    return {{i00, i01, i02}, {i01, i11, i12}, {i02, i12, i22}};
}
struct QuatD {
    double w, x, y, z;
};
// exp(w t / 2) q, not normalised. The half angle is within 0.5 under the spin
// limit (default pi/4 per sub-step: the midpoint rate's |w_mid| = |w| up to
// O(h)), where the series are exact to double rounding; the library's beyond.
QuatD turned(const QuatD& q, const D3& w, double t) {
    const double half = 0.5 * t;
    const D3 v{w.x * half, w.y * half, w.z * half};
    const double z = v.x * v.x + v.y * v.y + v.z * v.z;
    double sinc, c;
    if (z <= 0.25) {
        double tail;
        sinTail(z, tail);
        sinc = 1 + z * tail;
        cosSeries(z, c);
    } else {
        const double angle = std::sqrt(z);
        double s;
        dmath::sinCos(angle, s, c);
        sinc = s / angle;
    }
    const double ux = v.x * sinc, uy = v.y * sinc, uz = v.z * sinc;
    return {c * q.w - ux * q.x - uy * q.y - uz * q.z, c * q.x + ux * q.w + uy * q.z - uz * q.y,
            c * q.y - ux * q.z + uy * q.w + uz * q.x, c * q.z + ux * q.y - uy * q.x + uz * q.w};
}

void driftGeneralInertia(Motion m, const BodyParams& p, Real h) {
    const double hd = static_cast<double>(h);
    const Rotation inertia = toDouble(p.localInertia);
    const Rotation invInertia = inverseInDouble(inertia, p.invLocalInertia);
    const QuatD q{m.x.q.w, m.x.q.x, m.x.q.y, m.x.q.z};
    const D3 w{m.s.w.x, m.s.w.y, m.s.w.z};
    const Rotation r = rotationOf(q.w, q.x, q.y, q.z);
    const D3 l = times(r, times(inertia, transposeTimes(r, w)));
    const QuatD qMid = turned(q, w, 0.5 * hd);
    const Rotation rMid = rotationOf(qMid.w, qMid.x, qMid.y, qMid.z);
    const D3 wMid = times(rMid, times(invInertia, transposeTimes(rMid, l)));
    const QuatD qNew = turned(q, wMid, hd);
    const double invNorm = 1 / std::sqrt(qNew.w * qNew.w + qNew.x * qNew.x + qNew.y * qNew.y + qNew.z * qNew.z);
    m.x.q = Quat{static_cast<Real>(qNew.w * invNorm), static_cast<Real>(qNew.x * invNorm),
                 static_cast<Real>(qNew.y * invNorm), static_cast<Real>(qNew.z * invNorm)};
    // The stored orientation's matrix (the next sub-step's R).
    const Rotation rn = rotationOf(m.x.q.w, m.x.q.x, m.x.q.y, m.x.q.z);
    // I_w^-1 = (R' I^-1) R'^T, symmetric: six entries.
    const Rotation a{times(rn, invInertia.c0), times(rn, invInertia.c1), times(rn, invInertia.c2)};
    // Entry (i, k): row i of R' I^-1 with row k of R'.
    const double xx = a.c0.x * rn.c0.x + a.c1.x * rn.c1.x + a.c2.x * rn.c2.x;
    const double xy = a.c0.x * rn.c0.y + a.c1.x * rn.c1.y + a.c2.x * rn.c2.y;
    const double xz = a.c0.x * rn.c0.z + a.c1.x * rn.c1.z + a.c2.x * rn.c2.z;
    const double yy = a.c0.y * rn.c0.y + a.c1.y * rn.c1.y + a.c2.y * rn.c2.y;
    const double yz = a.c0.y * rn.c0.z + a.c1.y * rn.c1.z + a.c2.y * rn.c2.z;
    const double zz = a.c0.z * rn.c0.z + a.c1.z * rn.c1.z + a.c2.z * rn.c2.z;
    m.s.w = Vec3{static_cast<Real>(xx * l.x + xy * l.y + xz * l.z), static_cast<Real>(xy * l.x + yy * l.y + yz * l.z),
                 static_cast<Real>(xz * l.x + yz * l.y + zz * l.z)};
    const Real exy = static_cast<Real>(xy), exz = static_cast<Real>(xz), eyz = static_cast<Real>(yz);
    m.x.invInertiaWorld = Mat3{Vec3{static_cast<Real>(xx), exy, exz}, Vec3{exy, static_cast<Real>(yy), eyz},
                               Vec3{exz, eyz, static_cast<Real>(zz)}};
}

DriftLanes<double> loadDrift(Motion m, const BodyParams& p, int k) {
    const int side = (k + 1) % 3;
    return {m.x.q.w, m.x.q.x, m.x.q.y, m.x.q.z, m.s.w.x, m.s.w.y, m.s.w.z, 0, 0, 0, p.localInertia(k, k), p.localInertia(side, side)};
}

[[gnu::always_inline]] inline void storeDrift(Motion m, const BodyParams& p, int k, const DriftLanes<double>& d) {
    m.x.q = Quat{static_cast<Real>(d.qw), static_cast<Real>(d.qx), static_cast<Real>(d.qy), static_cast<Real>(d.qz)};
    m.s.w = Vec3{static_cast<Real>(d.wx), static_cast<Real>(d.wy), static_cast<Real>(d.wz)};
    // I_w^-1 = E / I_t + (1/I_a - 1/I_t) a a^T
    const Real invSide = p.invLocalInertia((k + 1) % 3, (k + 1) % 3);
    const Vec3 axis{static_cast<Real>(d.ax), static_cast<Real>(d.ay), static_cast<Real>(d.az)};
    const Vec3 cc = axis * (p.invLocalInertia(k, k) - invSide);
    m.x.invInertiaWorld =
        Mat3{Vec3{invSide, 0, 0} + cc * axis.x, Vec3{0, invSide, 0} + cc * axis.y, Vec3{0, 0, invSide} + cc * axis.z};
}

template <int K>
void driftOne(Motion m, const BodyParams& p, double hd) {
    DriftLanes<double> d = loadDrift(m, p, K);
    if (!driftLanes<K>(d, hd)) driftGeneral<K>(d, hd);
    storeDrift(m, p, K, d);
}

void driftAxisymmetric(Motion m, const BodyParams& p, int k, Real h) {
    const double hd = static_cast<double>(h);
    switch (k) {
        case 0: driftOne<0>(m, p, hd); break;
        case 1: driftOne<1>(m, p, hd); break;
        default: driftOne<2>(m, p, hd); break;
    }
}

#if defined(__GNUC__) && defined(__SSE2__)
template <int K>
void driftPairK(Motion m0, const BodyParams& p0, Motion m1, const BodyParams& p1, double hd) {
    const DriftLanes<double> a = loadDrift(m0, p0, K), b = loadDrift(m1, p1, K);
    DriftLanes<Double2> d{Double2{a.qw, b.qw}, Double2{a.qx, b.qx}, Double2{a.qy, b.qy}, Double2{a.qz, b.qz},
                          Double2{a.wx, b.wx}, Double2{a.wy, b.wy}, Double2{a.wz, b.wz}, Double2{},
                          Double2{},           Double2{},           Double2{a.inertiaAxis, b.inertiaAxis},
                          Double2{a.inertiaSide, b.inertiaSide}};
    if (!driftLanes<K>(d, hd)) {  // a lane outside the fast path: both alone (the same bits)
        driftOne<K>(m0, p0, hd);
        driftOne<K>(m1, p1, hd);
        return;
    }
    for (int lane = 0; lane < 2; ++lane) {
        const DriftLanes<double> out{d.qw[lane], d.qx[lane], d.qy[lane], d.qz[lane], d.wx[lane], d.wy[lane],
                                     d.wz[lane], d.ax[lane], d.ay[lane], d.az[lane], 0, 0};
        storeDrift(lane == 0 ? m0 : m1, lane == 0 ? p0 : p1, K, out);
    }
}

void driftPair(Motion m0, const BodyParams& p0, Motion m1, const BodyParams& p1, int k, Real h) {
    const double hd = static_cast<double>(h);
    switch (k) {
        case 0: driftPairK<0>(m0, p0, m1, p1, hd); break;
        case 1: driftPairK<1>(m0, p0, m1, p1, hd); break;
        default: driftPairK<2>(m0, p0, m1, p1, hd); break;
    }
}

// Four bodies (see Double4 above); a lane outside the fast path sends the
// four through driftOne alone (the same bits).
template <int K>
[[gnu::noinline]] void driftQuadK(BodyStore& w, const std::uint32_t* entries, double hd) {
    // The four bodies' pose, velocities and constants, looked up once (the
    // calls below may write anything, so the compiler would look them up again).
    BodyPose* x[4];
    SolverBody* v[4];
    const BodyParams* p[4];
    for (int lane = 0; lane < 4; ++lane) {
        x[lane] = &w.pose[entries[lane] + 1];
        v[lane] = &w.state[entries[lane] + 1];
        p[lane] = &w.params[w.awakeBodies[entries[lane]]];
    }
    // The same values as loadDrift's, gathered straight into the lanes.
    const auto lanes = [](Real a, Real b, Real c, Real e) {
        return Double4{static_cast<double>(a), static_cast<double>(b), static_cast<double>(c), static_cast<double>(e)};
    };
    constexpr int kSide = (K + 1) % 3;
    DriftLanes<Double4> d{lanes(x[0]->q.w, x[1]->q.w, x[2]->q.w, x[3]->q.w),
                          lanes(x[0]->q.x, x[1]->q.x, x[2]->q.x, x[3]->q.x),
                          lanes(x[0]->q.y, x[1]->q.y, x[2]->q.y, x[3]->q.y),
                          lanes(x[0]->q.z, x[1]->q.z, x[2]->q.z, x[3]->q.z),
                          lanes(v[0]->w.x, v[1]->w.x, v[2]->w.x, v[3]->w.x),
                          lanes(v[0]->w.y, v[1]->w.y, v[2]->w.y, v[3]->w.y),
                          lanes(v[0]->w.z, v[1]->w.z, v[2]->w.z, v[3]->w.z),
                          Double4{},
                          Double4{},
                          Double4{},
                          lanes(p[0]->localInertia(K, K), p[1]->localInertia(K, K), p[2]->localInertia(K, K),
                                p[3]->localInertia(K, K)),
                          lanes(p[0]->localInertia(kSide, kSide), p[1]->localInertia(kSide, kSide),
                                p[2]->localInertia(kSide, kSide), p[3]->localInertia(kSide, kSide))};
    if (!driftLanes<K>(d, hd)) {
        for (int lane = 0; lane < 4; ++lane) driftOne<K>(Motion{*x[lane], *v[lane]}, *p[lane], hd);
        return;
    }
    for (int lane = 0; lane < 4; ++lane) {
        const DriftLanes<double> out{d.qw[lane], d.qx[lane], d.qy[lane], d.qz[lane], d.wx[lane], d.wy[lane],
                                     d.wz[lane], d.ax[lane], d.ay[lane], d.az[lane], 0, 0};
        storeDrift(Motion{*x[lane], *v[lane]}, *p[lane], K, out);
    }
}

void driftQuad(BodyStore& w, const std::uint32_t* entries, int k, Real h) {
    const double hd = static_cast<double>(h);
    switch (k) {
        case 0: driftQuadK<0>(w, entries, hd); break;
        case 1: driftQuadK<1>(w, entries, hd); break;
        default: driftQuadK<2>(w, entries, hd); break;
    }
}

// exp(w t / 2) q for four lanes, turned()'s series branch: false, with
// nothing written, when a lane's half angle is beyond it (or not a number),
// where turned() takes the library's sin/cos.
bool turnedLanes(const Double4& qw, const Double4& qx, const Double4& qy, const Double4& qz, const Vec3Of<Double4>& w,
                 double t, Double4 out[4]) {
    const double half = 0.5 * t;
    const Vec3Of<Double4> v{w.x * half, w.y * half, w.z * half};
    const Double4 z = v.x * v.x + v.y * v.y + v.z * v.z;
    for (int lane = 0; lane < 4; ++lane) {
        if (!(z[lane] <= 0.25)) return false;
    }
    Double4 tail, c;
    sinTail(z, tail);
    const Double4 sinc = 1.0 + z * tail;
    cosSeries(z, c);
    const Double4 ux = v.x * sinc, uy = v.y * sinc, uz = v.z * sinc;
    out[0] = c * qw - ux * qx - uy * qy - uz * qz;
    out[1] = c * qx + ux * qw + uy * qz - uz * qy;
    out[2] = c * qy - ux * qz + uy * qw + uz * qx;
    out[3] = c * qz + ux * qy - uy * qx + uz * qw;
    return true;
}

// Four bodies of general inertia at once: driftGeneralInertia's operations,
// in the same order, one body per lane (so a body's bits do not depend on its
// partners, as for driftQuadK). On a scene of boxes with three distinct
// half extents (Jolt's ConvexVsMesh) the scalar drift was most of the
// position stage. A lane beyond the series' range sends the four through
// driftGeneralInertia alone (the same bits).
void driftGeneralQuad(BodyStore& w, const std::uint32_t* entries, Real h) {
    const double hd = static_cast<double>(h);
    BodyPose* x[4];
    SolverBody* v[4];
    const BodyParams* p[4];
    for (int lane = 0; lane < 4; ++lane) {
        x[lane] = &w.pose[entries[lane] + 1];
        v[lane] = &w.state[entries[lane] + 1];
        p[lane] = &w.params[w.awakeBodies[entries[lane]]];
    }
    const auto lanes = [](Real a, Real b, Real c, Real e) {
        return Double4{static_cast<double>(a), static_cast<double>(b), static_cast<double>(c), static_cast<double>(e)};
    };
    // I in double and its inverse by inverseInDouble's operations per lane;
    // a lane whose I is singular takes the stored inverse, as there.
    RotationOf<Double4> inertiaL, invInertiaL;
    for (int lane = 0; lane < 4; ++lane) {
        const Rotation r = toDouble(p[lane]->localInertia);
        inertiaL.c0.x[lane] = r.c0.x, inertiaL.c0.y[lane] = r.c0.y, inertiaL.c0.z[lane] = r.c0.z;
        inertiaL.c1.x[lane] = r.c1.x, inertiaL.c1.y[lane] = r.c1.y, inertiaL.c1.z[lane] = r.c1.z;
        inertiaL.c2.x[lane] = r.c2.x, inertiaL.c2.y[lane] = r.c2.y, inertiaL.c2.z[lane] = r.c2.z;
    }
    {
        const RotationOf<Double4>& m = inertiaL;
        const Double4 a = m.c0.x, b = m.c1.x, c = m.c2.x, d = m.c1.y, e = m.c2.y, f = m.c2.z;
        const Double4 a00 = d * f - e * e, a01 = c * e - b * f, a02 = b * e - c * d;
        const Double4 det = a * a00 + b * a01 + c * a02;
        const Double4 sc = 1.0 / det;
        const Double4 i00 = a00 * sc, i01 = a01 * sc, i02 = a02 * sc;
        const Double4 i11 = (a * f - c * c) * sc, i12 = (b * c - a * e) * sc, i22 = (a * d - b * b) * sc;
        invInertiaL = {{i00, i01, i02}, {i01, i11, i12}, {i02, i12, i22}};
        for (int lane = 0; lane < 4; ++lane) {
            if (det[lane] > 0) continue;
            const Rotation stored = toDouble(p[lane]->invLocalInertia);
            const D3* from[3] = {&stored.c0, &stored.c1, &stored.c2};
            Vec3Of<Double4>* to[3] = {&invInertiaL.c0, &invInertiaL.c1, &invInertiaL.c2};
            for (int k = 0; k < 3; ++k) {
                to[k]->x[lane] = from[k]->x, to[k]->y[lane] = from[k]->y, to[k]->z[lane] = from[k]->z;
            }
        }
    }
    const Double4 qw = lanes(x[0]->q.w, x[1]->q.w, x[2]->q.w, x[3]->q.w);
    const Double4 qx = lanes(x[0]->q.x, x[1]->q.x, x[2]->q.x, x[3]->q.x);
    const Double4 qy = lanes(x[0]->q.y, x[1]->q.y, x[2]->q.y, x[3]->q.y);
    const Double4 qz = lanes(x[0]->q.z, x[1]->q.z, x[2]->q.z, x[3]->q.z);
    const Vec3Of<Double4> wv{lanes(v[0]->w.x, v[1]->w.x, v[2]->w.x, v[3]->w.x),
                             lanes(v[0]->w.y, v[1]->w.y, v[2]->w.y, v[3]->w.y),
                             lanes(v[0]->w.z, v[1]->w.z, v[2]->w.z, v[3]->w.z)};
    const RotationOf<Double4> r = rotationOfLanes(qw, qx, qy, qz);
    const Vec3Of<Double4> l = times(r, times(inertiaL, transposeTimes(r, wv)));
    Double4 qMid[4], qNew[4];
    bool series = turnedLanes(qw, qx, qy, qz, wv, 0.5 * hd, qMid);
    if (series) {
        const RotationOf<Double4> rMid = rotationOfLanes(qMid[0], qMid[1], qMid[2], qMid[3]);
        const Vec3Of<Double4> wMid = times(rMid, times(invInertiaL, transposeTimes(rMid, l)));
        series = turnedLanes(qw, qx, qy, qz, wMid, hd, qNew);
    }
    if (!series) {
        for (int lane = 0; lane < 4; ++lane) driftGeneralInertia(Motion{*x[lane], *v[lane]}, *p[lane], h);
        return;
    }
    const Double4 invNorm = 1.0 / sqrtOf(qNew[0] * qNew[0] + qNew[1] * qNew[1] + qNew[2] * qNew[2] + qNew[3] * qNew[3]);
    // The stored orientation (Real) and, read back, its matrix (the next sub-step's R).
    Double4 stored[4];
    for (int k = 0; k < 4; ++k) {
        const Double4 unit = qNew[k] * invNorm;
        stored[k] = lanes(static_cast<Real>(unit[0]), static_cast<Real>(unit[1]), static_cast<Real>(unit[2]),
                          static_cast<Real>(unit[3]));
    }
    const RotationOf<Double4> rn = rotationOfLanes(stored[0], stored[1], stored[2], stored[3]);
    const RotationOf<Double4> a{times(rn, invInertiaL.c0), times(rn, invInertiaL.c1), times(rn, invInertiaL.c2)};
    const Double4 xx = a.c0.x * rn.c0.x + a.c1.x * rn.c1.x + a.c2.x * rn.c2.x;
    const Double4 xy = a.c0.x * rn.c0.y + a.c1.x * rn.c1.y + a.c2.x * rn.c2.y;
    const Double4 xz = a.c0.x * rn.c0.z + a.c1.x * rn.c1.z + a.c2.x * rn.c2.z;
    const Double4 yy = a.c0.y * rn.c0.y + a.c1.y * rn.c1.y + a.c2.y * rn.c2.y;
    const Double4 yz = a.c0.y * rn.c0.z + a.c1.y * rn.c1.z + a.c2.y * rn.c2.z;
    const Double4 zz = a.c0.z * rn.c0.z + a.c1.z * rn.c1.z + a.c2.z * rn.c2.z;
    const Double4 wx = xx * l.x + xy * l.y + xz * l.z, wy = xy * l.x + yy * l.y + yz * l.z,
                  wz = xz * l.x + yz * l.y + zz * l.z;
    for (int lane = 0; lane < 4; ++lane) {
        x[lane]->q = Quat{static_cast<Real>(stored[0][lane]), static_cast<Real>(stored[1][lane]),
                          static_cast<Real>(stored[2][lane]), static_cast<Real>(stored[3][lane])};
        v[lane]->w = Vec3{static_cast<Real>(wx[lane]), static_cast<Real>(wy[lane]), static_cast<Real>(wz[lane])};
        const Real exy = static_cast<Real>(xy[lane]), exz = static_cast<Real>(xz[lane]), eyz = static_cast<Real>(yz[lane]);
        x[lane]->invInertiaWorld = Mat3{Vec3{static_cast<Real>(xx[lane]), exy, exz}, Vec3{exy, static_cast<Real>(yy[lane]), eyz},
                                        Vec3{exz, eyz, static_cast<Real>(zz[lane])}};
    }
}
#else
void driftPair(Motion m0, const BodyParams& p0, Motion m1, const BodyParams& p1, int k, Real h) {
    driftAxisymmetric(m0, p0, k, h);
    driftAxisymmetric(m1, p1, k, h);
}
void driftQuad(BodyStore& w, const std::uint32_t* entries, int k, Real h) {
    for (int lane = 0; lane < 4; ++lane) driftAxisymmetric(motionOf(w, entries[lane] + 1), w.params[w.awakeBodies[entries[lane]]], k, h);
}
void driftGeneralQuad(BodyStore& w, const std::uint32_t* entries, Real h) {
    for (int lane = 0; lane < 4; ++lane) driftGeneralInertia(motionOf(w, entries[lane] + 1), w.params[w.awakeBodies[entries[lane]]], h);
}
#endif

void applyDamping(Motion m, const BodyParams& p, Real h) {
    // Implicit (unconditionally stable) exponential decay: v *= 1 / (1 + h c).
    if (p.linearDamping > 0) m.s.v *= Real(1) / (1 + h * p.linearDamping);
    if (p.angularDamping > 0) m.s.w *= Real(1) / (1 + h * p.angularDamping);
}

// Whether a torque turns the body (a zero of either sign does not).
bool hasTorque(const ForceTorque& ft) { return ft.torque.x != 0 || ft.torque.y != 0 || ft.torque.z != 0; }

// The position stage's path for a body (MotionKind): it depends only on the
// body's type and local inertia, which do not change within a step.
std::uint8_t positionKindOf(const BodyParams& p) {
    if (!moves(p)) return kStill;
    if (p.type == BodyType::Kinematic) return kKinematicMotion;
    const int symmetry = inertiaSymmetry(p.localInertia);
    if (symmetry == kIsotropic) return kIsotropicMotion;
    if (symmetry >= 0) return static_cast<std::uint8_t>(kAxisymmetricMotion + symmetry);
    return kGeneralMotion;
}

// One body's stage 2: awake-list entry k.
void integrateVelocity(BodyStore& w, Integrator method, Real h, std::size_t k) {
    const std::uint32_t i = w.awakeBodies[k];
    const BodyParams& p = w.params[i];
    if (!isDynamic(p)) return;
    const Motion m = motionOf(w, k + 1);
    const ForceTorque& ft = w.forces[i];
    switch (method) {
        case Integrator::ExplicitEuler: {
            // a(x_n, v_n), with the gyroscopic torque -w x I_w w evaluated at the old state.
            const Vec3 v0 = m.s.v, w0 = m.s.w;
            const Vec3 lw = worldInertia(m.x.q, p.localInertia) * m.s.w;
            m.s.v += ft.force * (m.s.invMass * h);
            m.s.w += m.x.invInertiaWorld * (ft.torque - cross(m.s.w, lw)) * h;
            applyDamping(m, p, h);
            w.scratch[i].dv = m.s.v - v0;
            w.scratch[i].dw = m.s.w - w0;
            break;
        }
        case Integrator::SemiImplicitEuler: {
            // The gyroscopic effect is not a torque here either: the position
            // stage turns the body at constant world angular momentum (as for
            // Verlet). Catto's implicit gyroscopic step, used before, bleeds
            // |L| at high spin: the demo's tumbling box lost 13 % of |L| in
            // 10 s at 240 Hz; with the constant-L drift it keeps it to ~1e-5.
            m.s.v += ft.force * (m.s.invMass * h);
            // Most bodies have no torque (gravity acts at the centre of
            // mass): w then keeps its value without the 3x3 product (the
            // same value as w + 0, but for the sign of a zero component).
            if (hasTorque(ft)) m.s.w += m.x.invInertiaWorld * ft.torque * h;
            applyDamping(m, p, h);
            break;
        }
        case Integrator::Verlet: {
            // First half kick. The gyroscopic effect is not a torque here: in
            // world axes dL/dt = tau, and the drift below turns the body at
            // constant L, which is where w x I w comes from.
            const Real half = Real(0.5) * h;
            m.s.v += ft.force * (m.s.invMass * half);
            m.s.w += m.x.invInertiaWorld * ft.torque * half;
            applyDamping(m, p, h);
            break;
        }
    }
}

}  // namespace

void classifyMotion(BodyStore& w, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
        const std::uint32_t i = w.awakeBodies[k];
        const BodyParams& p = w.params[i];
        std::uint8_t kind = positionKindOf(p);
        if (isDynamic(p) && !(p.linearDamping > 0) && !(p.angularDamping > 0) && !hasTorque(w.forces[i])) {
            kind |= kPlainVelocity;
        }
        w.motionKind[k + 1] = kind;
    }
}

void integrateVelocities(BodyStore& w, Integrator method, Real h, bool plainKept, std::size_t begin, std::size_t end) {
    if (!plainKept || method != Integrator::SemiImplicitEuler) {
        for (std::size_t k = begin; k < end; ++k) integrateVelocity(w, method, h, k);
        return;
    }
    // integrateVelocity's semi-implicit case for a body with no torque and no
    // damping is v += f (1/m) h alone: the step's forces are kept, so which
    // bodies those are was decided once for the step (classifyMotion).
    for (std::size_t k = begin; k < end; ++k) {
        if ((w.motionKind[k + 1] & kPlainVelocity) == 0) {
            integrateVelocity(w, method, h, k);
            continue;
        }
        SolverBody& s = w.state[k + 1];
        s.v += w.forces[w.awakeBodies[k]].force * (s.invMass * h);
    }
}

void integratePositions(BodyStore& w, Integrator method, Real h, Real maxTurn, bool deltas, bool kindsKept,
                        std::size_t begin, std::size_t end) {
    // Axisymmetric bodies waiting for three partners, per symmetry axis (driftQuad):
    // their awake-list entries.
    std::uint32_t waitingDrift[3][4];
    int waitingCount[3] = {0, 0, 0};
    // And bodies of general inertia (driftGeneralQuad).
    std::uint32_t waitingGeneral[4];
    int generalCount = 0;
    // And isotropic bodies, for their rotations (integrateRotations, four
    // lanes): their orientations and angular velocities.
    Quat* rotating[4];
    const Vec3* rotatingSpin[4];
    int rotatingCount = 0;
    for (std::size_t k = begin; k < end; ++k) {
        const std::uint32_t i = w.awakeBodies[k];
        const BodyParams& p = w.params[i];
        // The body's path, decided once for the step (classifyMotion): the
        // inertia's symmetry test was ~25 instructions a body and sub-step.
        const std::uint8_t kind = kindsKept ? static_cast<std::uint8_t>(w.motionKind[k + 1] & kPositionKindMask)
                                            : positionKindOf(p);
        if (kind == kStill) continue;
        const Motion m = motionOf(w, k + 1);
        if (kind == kKinematicMotion) {
            m.x.com += m.s.v * h;
            m.x.q = integrateRotation(m.x.q, m.s.w, h);
            continue;
        }
        // The spin limit (WorldDef::maxRotationPerSubstep).
        if (const Real w2 = lengthSquared(m.s.w); w2 * h * h > maxTurn * maxTurn) m.s.w *= maxTurn / (std::sqrt(w2) * h);
        switch (method) {
            case Integrator::ExplicitEuler:
                // The old velocity: the current one minus what forces added this
                // sub-step. (A solver's correction, applied after the forces, is kept.)
                m.x.com += (m.s.v - w.scratch[i].dv) * h;
                m.x.q = integrateRotation(m.x.q, m.s.w - w.scratch[i].dw, h);
                break;
            case Integrator::SemiImplicitEuler:
            case Integrator::Verlet: {
                m.x.com += m.s.v * h;
                // Isotropic bodies: the drift below is exactly a rotation at
                // constant w (it cost ~45 % of sphere_pile's position stage and
                // ~20 % of its step: three R I R^T and two inverses per body).
                // Its world inverse inertia is the local one (no R I^-1 R^T below).
                if (kind == kIsotropicMotion) {
                    // m.x.q = integrateRotation(m.x.q, m.s.w, h), four at a time.
                    rotating[rotatingCount] = &m.x.q;
                    rotatingSpin[rotatingCount] = &m.s.w;
                    if (++rotatingCount == 4) {
                        integrateRotations(rotating, rotatingSpin, 4, h);
                        rotatingCount = 0;
                    }
                    m.x.invInertiaWorld = p.invLocalInertia;
                    continue;
                }
                if (kind != kGeneralMotion) {
                    const int symmetry = kind - kAxisymmetricMotion;
                    // Four at a time where the SIMD lanes exist (driftQuad):
                    // the first three of a symmetry axis wait for the fourth.
                    if (!kPairedDrift) {
                        driftAxisymmetric(m, p, symmetry, h);
                        continue;
                    }
                    int& count = waitingCount[symmetry];
                    waitingDrift[symmetry][count++] = static_cast<std::uint32_t>(k);
                    if (count == 4) {
                        driftQuad(w, waitingDrift[symmetry], symmetry, h);
                        count = 0;
                    }
                    continue;
                }
                // General inertia: the drift at constant world angular momentum
                // (driftGeneralInertia), which also sets I_w^-1; four at a
                // time where the SIMD lanes exist (driftGeneralQuad).
                if (!kPairedDrift) {
                    driftGeneralInertia(m, p, h);
                    continue;
                }
                waitingGeneral[generalCount++] = static_cast<std::uint32_t>(k);
                if (generalCount == 4) {
                    driftGeneralQuad(w, waitingGeneral, h);
                    generalCount = 0;
                }
                continue;
            }
        }
        const Mat3 r = toMat3(m.x.q);
        m.x.invInertiaWorld = r * p.invLocalInertia * transpose(r);
    }
    if (rotatingCount > 0) integrateRotations(rotating, rotatingSpin, rotatingCount, h);
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t* waiting = waitingDrift[k];
        int n = 0;
        for (; n + 2 <= waitingCount[k]; n += 2) {
            driftPair(motionOf(w, waiting[n] + 1), w.params[w.awakeBodies[waiting[n]]], motionOf(w, waiting[n + 1] + 1),
                      w.params[w.awakeBodies[waiting[n + 1]]], k, h);
        }
        if (n < waitingCount[k]) driftAxisymmetric(motionOf(w, waiting[n] + 1), w.params[w.awakeBodies[waiting[n]]], k, h);
    }
    for (int n = 0; n < generalCount; ++n) {
        driftGeneralInertia(motionOf(w, waitingGeneral[n] + 1), w.params[w.awakeBodies[waitingGeneral[n]]], h);
    }
    // The pose change since the step's start, for the contact kernels (the
    // bodies they read: the drifts above included), if there are any.
    if (deltas) w.updateContactDeltas(begin, end);
}

void verletPredict(BodyStore& w, Real h, std::size_t begin, std::size_t end) {
    const Real half = Real(0.5) * h;
    // Velocity-dependent forces (drag, spring damping, callbacks) at the new
    // position need a velocity there, which the second kick is about to
    // produce. Evaluate them at the predictor v_half + a_old h/2 (the velocity
    // the kick would give if the acceleration did not change): the error is
    // O(h^2) in the force, so the scheme stays second order.
    for (std::size_t k = begin; k < end; ++k) {
        const std::uint32_t i = w.awakeBodies[k];
        if (!isDynamic(w.params[i])) continue;
        const Motion m = motionOf(w, k + 1);
        w.scratch[i].dv = m.s.v;
        w.scratch[i].dw = m.s.w;
        m.s.v += w.forces[i].force * (m.s.invMass * half);
        m.s.w += m.x.invInertiaWorld * w.forces[i].torque * half;
    }
}

void verletKick(BodyStore& w, Real h, std::size_t begin, std::size_t end) {
    const Real half = Real(0.5) * h;
    for (std::size_t k = begin; k < end; ++k) {
        const std::uint32_t i = w.awakeBodies[k];
        if (!isDynamic(w.params[i])) continue;
        const Motion m = motionOf(w, k + 1);
        m.s.v = w.scratch[i].dv + w.forces[i].force * (m.s.invMass * half);
        m.s.w = w.scratch[i].dw + m.x.invInertiaWorld * w.forces[i].torque * half;
    }
}

}  // namespace fulcrum::detail
