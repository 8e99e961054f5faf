#pragma once
// Vec3: the 3-component vector every other type is built on, over Real: float, or double in the FULCRUM_DOUBLE=1 build.
#define FULCRUM_REAL_FOR_FULCRUM_DOUBLE float  // FULCRUM_DOUBLE undefined: the float build
#define FULCRUM_REAL_FOR_1 double  // docs/double-precision.md
#include <cmath>
#include <cstddef>
#define FULCRUM_REAL_PASTE(flag) FULCRUM_REAL_FOR_##flag  // the choice is one line, so the float build's
namespace fulcrum {
#define FULCRUM_REAL_OF(flag) FULCRUM_REAL_PASTE(flag)  // preprocessed text is unchanged (compiler caches)
using Real = FULCRUM_REAL_OF(FULCRUM_DOUBLE);

struct Vec3 {
    Real x = 0, y = 0, z = 0;

    constexpr Vec3() = default;
    constexpr Vec3(Real x_, Real y_, Real z_) : x(x_), y(y_), z(z_) {}
    static constexpr Vec3 zero() { return {0, 0, 0}; }
    static constexpr Vec3 splat(Real v) { return {v, v, v}; }
    static constexpr Vec3 unitX() { return {1, 0, 0}; }
    static constexpr Vec3 unitY() { return {0, 1, 0}; }
    static constexpr Vec3 unitZ() { return {0, 0, 1}; }

    constexpr Real operator[](std::size_t i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Real& operator[](std::size_t i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    constexpr Vec3& operator*=(Real s) { x *= s; y *= s; z *= s; return *this; }
    constexpr Vec3& operator/=(Real s) { x /= s; y /= s; z /= s; return *this; }
    constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
constexpr Vec3 operator*(Vec3 a, Real s) { return a *= s; }
constexpr Vec3 operator*(Real s, Vec3 a) { return a *= s; }
constexpr Vec3 operator/(Vec3 a, Real s) { return a /= s; }

constexpr Real dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// Component-wise product and quotient.
constexpr Vec3 mul(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
constexpr Vec3 div(const Vec3& a, const Vec3& b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
constexpr Vec3 min(const Vec3& a, const Vec3& b) {
    return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
constexpr Vec3 max(const Vec3& a, const Vec3& b) {
    return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}
inline Vec3 abs(const Vec3& a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
constexpr Real lengthSquared(const Vec3& a) { return dot(a, a); }
inline Real length(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Real distance(const Vec3& a, const Vec3& b) { return length(b - a); }
constexpr Vec3 lerp(const Vec3& a, const Vec3& b, Real t) { return a + (b - a) * t; }
constexpr Real minComponent(const Vec3& a) { return a.x < a.y ? (a.x < a.z ? a.x : a.z) : (a.y < a.z ? a.y : a.z); }
constexpr Real maxComponent(const Vec3& a) { return a.x > a.y ? (a.x > a.z ? a.x : a.z) : (a.y > a.z ? a.y : a.z); }
// Index (0, 1, 2) of the largest component.
constexpr int maxAxis(const Vec3& a) { return a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2); }

// Unit vector along `a`; the zero vector stays zero instead of turning into NaN.
inline Vec3 normalize(const Vec3& a) {
    const Real len = length(a);
    return len > Real(0) ? a / len : Vec3::zero();
}

inline bool isFinite(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

// Two unit vectors completing `n` (unit) to a right-handed orthonormal basis
// (Duff et al. 2017, "Building an Orthonormal Basis, Revisited"): branch-free
// apart from the sign, and continuous except across n.z = 0.
inline void orthonormalBasis(const Vec3& n, Vec3& t1, Vec3& t2) {
    const Real sign = std::copysign(Real(1), n.z);
    const Real a = Real(-1) / (sign + n.z);
    const Real b = n.x * n.y * a;
    t1 = {Real(1) + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t2 = {b, sign + n.y * n.y * a, -n.y};
}

}  // namespace fulcrum
