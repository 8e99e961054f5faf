#pragma once
// Quat: unit quaternion for orientation, stored and read as [w, x, y, z]
// (the scene-file order). Rotations compose as q = q2 * q1 (q1 first).
#include "fulcrum/math/deterministic_math.hpp"
#include "fulcrum/math/mat3.hpp"

namespace fulcrum {

struct Quat {
    Real w = 1, x = 0, y = 0, z = 0;

    constexpr Quat() = default;
    constexpr Quat(Real w_, Real x_, Real y_, Real z_) : w(w_), x(x_), y(y_), z(z_) {}
    static constexpr Quat identity() { return {}; }
    constexpr Vec3 vec() const { return {x, y, z}; }
    constexpr bool operator==(const Quat&) const = default;

    // Rotation by `angle` radians about `axis` (normalised here; a zero axis gives identity).
    static Quat fromAxisAngle(const Vec3& axis, Real angle) {
        const Vec3 n = normalize(axis);
        Real s = 0, c = 1;
        dmath::sinCos(Real(0.5) * angle, s, c);  // not the C library's: the same bits everywhere
        return {c, n.x * s, n.y * s, n.z * s};
    }
    // The shortest rotation taking unit vector `from` to unit vector `to`.
    static Quat fromTo(const Vec3& from, const Vec3& to);
    // Rotation from a proper rotation matrix (Shepperd's method, stable for all angles).
    static Quat fromMatrix(const Mat3& m);
};

constexpr Quat operator*(const Quat& a, const Quat& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
constexpr Quat operator+(const Quat& a, const Quat& b) { return {a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Quat operator*(const Quat& a, Real s) { return {a.w * s, a.x * s, a.y * s, a.z * s}; }
constexpr Quat operator-(const Quat& a) { return {-a.w, -a.x, -a.y, -a.z}; }

constexpr Quat conjugate(const Quat& q) { return {q.w, -q.x, -q.y, -q.z}; }
constexpr Real dot(const Quat& a, const Quat& b) { return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z; }
inline Real length(const Quat& q) { return std::sqrt(dot(q, q)); }
inline bool isFinite(const Quat& q) {
    return std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}
// Unit quaternion along q; a zero quaternion gives identity rather than NaN.
inline Quat normalize(const Quat& q) {
    const Real len = length(q);
    return len > Real(0) ? q * (Real(1) / len) : Quat::identity();
}

// v rotated by q (unit): v + 2w(u x v) + 2u x (u x v), cheaper than forming the matrix.
constexpr Vec3 rotate(const Quat& q, const Vec3& v) {
    const Vec3 u = q.vec();
    const Vec3 t = cross(u, v) * Real(2);
    return v + t * q.w + cross(u, t);
}
constexpr Vec3 inverseRotate(const Quat& q, const Vec3& v) { return rotate(conjugate(q), v); }

constexpr Mat3 toMat3(const Quat& q) {
    const Real xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    const Real xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    const Real wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    return {{1 - 2 * (yy + zz), 2 * (xy + wz), 2 * (xz - wy)},
            {2 * (xy - wz), 1 - 2 * (xx + zz), 2 * (yz + wx)},
            {2 * (xz + wy), 2 * (yz - wx), 1 - 2 * (xx + yy)}};
}

// Orientation after rotating at world angular velocity `omega` for `h` seconds,
// using the exact exponential map (a first-order `q + h/2 w q` drifts off the
// unit sphere and under-rotates at high spin rates). Renormalised.
inline Quat integrateRotation(const Quat& q, const Vec3& omega, Real h) {
    const Real angle = length(omega) * h;
    if (angle < Real(1e-9)) return normalize(q + Quat(0, omega.x, omega.y, omega.z) * q * (Real(0.5) * h));
    return normalize(Quat::fromAxisAngle(omega, angle) * q);
}

// Rotation vector (axis * angle, angle in [0, pi]) of unit quaternion q.
inline Vec3 toRotationVector(const Quat& q) {
    const Quat p = q.w < 0 ? -q : q;  // shortest arc
    const Real s = length(p.vec());
    if (s < Real(1e-7)) return p.vec() * Real(2);
    return p.vec() * (Real(2) * dmath::atan2(s, p.w) / s);
}

inline Quat slerp(const Quat& a, Quat b, Real t) {
    Real c = dot(a, b);
    if (c < 0) { b = -b; c = -c; }
    if (c > Real(0.9995)) return normalize(a * (1 - t) + b * t);
    const Real theta = dmath::acos(c);
    const Real s = dmath::sin(theta);
    return a * (dmath::sin((1 - t) * theta) / s) + b * (dmath::sin(t * theta) / s);
}

inline Quat Quat::fromTo(const Vec3& from, const Vec3& to) {
    const Real c = dot(from, to);
    if (c < Real(-0.999999)) {
        Vec3 t1, t2;
        orthonormalBasis(from, t1, t2);
        return {0, t1.x, t1.y, t1.z};
    }
    const Vec3 a = cross(from, to);
    return normalize(Quat(1 + c, a.x, a.y, a.z));
}

inline Quat Quat::fromMatrix(const Mat3& m) {
    const Real tr = trace(m);
    Quat q;
    if (tr > 0) {
        const Real s = std::sqrt(tr + 1) * 2;
        q = {Real(0.25) * s, (m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s};
    } else if (m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2)) {
        const Real s = std::sqrt(1 + m(0, 0) - m(1, 1) - m(2, 2)) * 2;
        q = {(m(2, 1) - m(1, 2)) / s, Real(0.25) * s, (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s};
    } else if (m(1, 1) > m(2, 2)) {
        const Real s = std::sqrt(1 + m(1, 1) - m(0, 0) - m(2, 2)) * 2;
        q = {(m(0, 2) - m(2, 0)) / s, (m(0, 1) + m(1, 0)) / s, Real(0.25) * s, (m(1, 2) + m(2, 1)) / s};
    } else {
        const Real s = std::sqrt(1 + m(2, 2) - m(0, 0) - m(1, 1)) * 2;
        q = {(m(1, 0) - m(0, 1)) / s, (m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, Real(0.25) * s};
    }
    return normalize(q);
}

}  // namespace fulcrum
