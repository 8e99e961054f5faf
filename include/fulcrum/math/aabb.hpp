#pragma once
// AABB: axis-aligned bounding box, the currency of the broad phase.
#include <limits>

#include "fulcrum/math/transform.hpp"

namespace fulcrum {

struct AABB {
    Vec3 min{std::numeric_limits<Real>::max(), std::numeric_limits<Real>::max(), std::numeric_limits<Real>::max()};
    Vec3 max{-std::numeric_limits<Real>::max(), -std::numeric_limits<Real>::max(), -std::numeric_limits<Real>::max()};

    constexpr AABB() = default;  // empty: min > max, so any point grows it
    constexpr AABB(const Vec3& lo, const Vec3& hi) : min(lo), max(hi) {}
    static constexpr AABB fromCenterHalf(const Vec3& c, const Vec3& h) { return {c - h, c + h}; }

    constexpr bool isEmpty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    constexpr Vec3 center() const { return (min + max) * Real(0.5); }
    constexpr Vec3 halfExtents() const { return (max - min) * Real(0.5); }
    constexpr Real surfaceArea() const {
        const Vec3 d = max - min;
        return 2 * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
    constexpr void grow(const Vec3& p) { min = fulcrum::min(min, p); max = fulcrum::max(max, p); }
    constexpr void grow(const AABB& b) { min = fulcrum::min(min, b.min); max = fulcrum::max(max, b.max); }
    constexpr AABB fattened(Real margin) const { return {min - Vec3::splat(margin), max + Vec3::splat(margin)}; }
    constexpr bool contains(const Vec3& p) const {
        return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z && p.z <= max.z;
    }
    constexpr bool contains(const AABB& b) const {
        return b.min.x >= min.x && b.min.y >= min.y && b.min.z >= min.z && b.max.x <= max.x && b.max.y <= max.y &&
               b.max.z <= max.z;
    }
    constexpr bool operator==(const AABB&) const = default;
};

constexpr AABB merge(const AABB& a, const AABB& b) { return {min(a.min, b.min), max(a.max, b.max)}; }
constexpr bool overlaps(const AABB& a, const AABB& b) {
    return a.min.x <= b.max.x && a.max.x >= b.min.x && a.min.y <= b.max.y && a.max.y >= b.min.y &&
           a.min.z <= b.max.z && a.max.z >= b.min.z;
}

// Bounds of a local box after a rigid transform (Arvo's method: |R| times the half extents).
inline AABB transformBounds(const Transform& t, const AABB& local) {
    const Mat3 r = toMat3(t.q);
    const Vec3 c = transformPoint(t, local.center());
    const Vec3 h = local.halfExtents();
    const Vec3 e = abs(r.c0) * h.x + abs(r.c1) * h.y + abs(r.c2) * h.z;
    return {c - e, c + e};
}

// Slab test: entry fraction in [0, maxFraction] of the ray p + t d, or a negative value for a miss.
inline Real rayCastAABB(const AABB& b, const Vec3& p, const Vec3& d, Real maxFraction) {
    Real tmin = 0, tmax = maxFraction;
    for (std::size_t i = 0; i < 3; ++i) {
        if (std::fabs(d[i]) < Real(1e-12)) {
            if (p[i] < b.min[i] || p[i] > b.max[i]) return -1;
        } else {
            const Real inv = 1 / d[i];
            Real t1 = (b.min[i] - p[i]) * inv, t2 = (b.max[i] - p[i]) * inv;
            if (t1 > t2) { const Real tmp = t1; t1 = t2; t2 = tmp; }
            tmin = t1 > tmin ? t1 : tmin;
            tmax = t2 < tmax ? t2 : tmax;
            if (tmin > tmax) return -1;
        }
    }
    return tmin;
}

}  // namespace fulcrum
