#pragma once
// Mat3: 3x3 matrix stored as three columns, used for rotations and inertia
// tensors. Columns because `R * v = c0*v.x + c1*v.y + c2*v.z` is the form the
// inertia and rotation code reads most naturally.
#include "fulcrum/math/vec3.hpp"

namespace fulcrum {

struct Mat3 {
    Vec3 c0{1, 0, 0}, c1{0, 1, 0}, c2{0, 0, 1};  // identity by default

    constexpr Mat3() = default;
    constexpr Mat3(const Vec3& col0, const Vec3& col1, const Vec3& col2) : c0(col0), c1(col1), c2(col2) {}
    static constexpr Mat3 identity() { return {}; }
    static constexpr Mat3 zero() { return {Vec3::zero(), Vec3::zero(), Vec3::zero()}; }
    static constexpr Mat3 diagonal(const Vec3& d) { return {{d.x, 0, 0}, {0, d.y, 0}, {0, 0, d.z}}; }
    static constexpr Mat3 diagonal(Real d) { return diagonal(Vec3::splat(d)); }
    static constexpr Mat3 fromRows(const Vec3& r0, const Vec3& r1, const Vec3& r2) {
        return {{r0.x, r1.x, r2.x}, {r0.y, r1.y, r2.y}, {r0.z, r1.z, r2.z}};
    }
    // The matrix of `v -> a x v`.
    static constexpr Mat3 skew(const Vec3& a) { return {{0, a.z, -a.y}, {-a.z, 0, a.x}, {a.y, -a.x, 0}}; }
    // The outer product a b^T.
    static constexpr Mat3 outer(const Vec3& a, const Vec3& b) { return {a * b.x, a * b.y, a * b.z}; }

    constexpr Vec3 col(int i) const { return i == 0 ? c0 : (i == 1 ? c1 : c2); }
    constexpr Vec3 row(int i) const { return {c0[static_cast<std::size_t>(i)], c1[static_cast<std::size_t>(i)], c2[static_cast<std::size_t>(i)]}; }
    // Element at row r, column c.
    constexpr Real operator()(int r, int c) const { return col(c)[static_cast<std::size_t>(r)]; }

    constexpr Mat3& operator+=(const Mat3& o) { c0 += o.c0; c1 += o.c1; c2 += o.c2; return *this; }
    constexpr Mat3& operator-=(const Mat3& o) { c0 -= o.c0; c1 -= o.c1; c2 -= o.c2; return *this; }
    constexpr Mat3& operator*=(Real s) { c0 *= s; c1 *= s; c2 *= s; return *this; }
    constexpr bool operator==(const Mat3&) const = default;
};

constexpr Mat3 operator+(Mat3 a, const Mat3& b) { return a += b; }
constexpr Mat3 operator-(Mat3 a, const Mat3& b) { return a -= b; }
constexpr Mat3 operator*(Mat3 a, Real s) { return a *= s; }
constexpr Mat3 operator*(Real s, Mat3 a) { return a *= s; }
constexpr Vec3 operator*(const Mat3& m, const Vec3& v) { return m.c0 * v.x + m.c1 * v.y + m.c2 * v.z; }
constexpr Mat3 operator*(const Mat3& a, const Mat3& b) { return {a * b.c0, a * b.c1, a * b.c2}; }

constexpr Mat3 transpose(const Mat3& m) { return Mat3::fromRows(m.c0, m.c1, m.c2); }
// m^T v without forming the transpose.
constexpr Vec3 transposeMul(const Mat3& m, const Vec3& v) { return {dot(m.c0, v), dot(m.c1, v), dot(m.c2, v)}; }
constexpr Real determinant(const Mat3& m) { return dot(m.c0, cross(m.c1, m.c2)); }
constexpr Real trace(const Mat3& m) { return m.c0.x + m.c1.y + m.c2.z; }

// Inverse by the adjugate; a singular matrix gives the zero matrix, which is
// what an infinite mass / inertia needs (static bodies, locked axes).
constexpr Mat3 inverse(const Mat3& m) {
    const Vec3 r0 = cross(m.c1, m.c2), r1 = cross(m.c2, m.c0), r2 = cross(m.c0, m.c1);
    const Real det = dot(m.c0, r0);
    if (det == Real(0)) return Mat3::zero();
    return Mat3::fromRows(r0, r1, r2) * (Real(1) / det);
}

// Inverse of a symmetric matrix (inertia tensors); same rule for singular ones.
constexpr Mat3 inverseSymmetric(const Mat3& m) { return inverse(m); }

inline bool isFinite(const Mat3& m) { return isFinite(m.c0) && isFinite(m.c1) && isFinite(m.c2); }

}  // namespace fulcrum
